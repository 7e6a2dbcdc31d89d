#!/usr/bin/env bash
# vnconvert's outputs, for every format: what OUT may be (a link is written
# through, a device, FIFO or folder is refused), the mode it keeps, a missing
# folder named before any work, and non-finite positions refused.
#   test_output_safety.sh PATH/TO/vnconvert GLTF_SAMPLES
set -u
VNC=$1
GLTF=$2
SAMPLES=$(cd "$(dirname "$0")/../samples" && pwd)
. "$(dirname "$0")/lib.sh"
TORUS=$SAMPLES/torus.off
DUCK=$GLTF/Duck.glb

# no_temporaries FOLDER: nothing hidden (".NAME.XXXXXX") left in FOLDER.
no_temporaries() { [ -z "$(find "$1" -name '.*.??????' -print -quit)" ]; }

# ---- OUT a symbolic link: its target is replaced, the links stay.
mkdir -p "$T/links/a" "$T/links/b"
for ext in off glb gltf drc; do
  ln -s "target.$ext" "$T/links/b/second.$ext"
  ln -s "../b/second.$ext" "$T/links/a/first.$ext"
  echo old >"$T/links/b/target.$ext"
  in=$TORUS; [ $ext = glb ] || [ $ext = gltf ] && in=$DUCK
  run "$VNC" "$in" "$T/links/a/first.$ext" -q
  check "link chain .$ext: exits 0" [ $rc -eq 0 ]
  check "link chain .$ext: the first link stays" [ -L "$T/links/a/first.$ext" ]
  check "link chain .$ext: the second link stays" [ -L "$T/links/b/second.$ext" ]
  check "link chain .$ext: the target replaced" not grep -qx old "$T/links/b/target.$ext"
done
check "link chain .off: NOFF" [ "$(head -1 "$T/links/b/target.off")" = NOFF ]
check "link chain: no temporaries" no_temporaries "$T/links"
# A dangling link: its target is created.
ln -s new.off "$T/links/dangling.off"
run "$VNC" "$TORUS" "$T/links/dangling.off" -q
check "dangling link: the link stays" [ -L "$T/links/dangling.off" ]
check "dangling link: target created" [ "$(head -1 "$T/links/new.off")" = NOFF ]

# ---- OUT not a regular file: refused, one line, left as it was.
mkdir -p "$T/special/dir.off"
mkfifo "$T/special/pipe.off" "$T/special/pipe.glb"
ln -s pipe.off "$T/special/to-pipe.off"
for o in dir.off pipe.off pipe.glb to-pipe.off; do
  run timeout 60 "$VNC" "$TORUS" "$T/special/$o"
  [ $o = pipe.glb ] && run timeout 60 "$VNC" "$DUCK" "$T/special/$o"
  check "$o refused with 1" [ $rc -eq 1 ]; check "$o: one line" one_line_err
  check "$o: says why" grep -q "special/$o is a \(folder\|FIFO (pipe)\), not a regular file" "$T/stderr"
done
check "the folder stays" [ -d "$T/special/dir.off" ]
check "the FIFOs stay" test -p "$T/special/pipe.off" -a -p "$T/special/pipe.glb"
check "the link to a FIFO stays" [ -L "$T/special/to-pipe.off" ]
# /dev/stdout when standard output is a pipe (through a link of our own,
# so that a failure could only replace the link in $T).
ln -s /proc/self/fd/1 "$T/special/stdout.glb"
"$VNC" "$DUCK" "$T/special/stdout.glb" 2>"$T/stderr" | cat >"$T/piped"; rc=${PIPESTATUS[0]}
check "/dev/stdout as a pipe refused with 1" [ $rc -eq 1 ]; check "/dev/stdout: one line" one_line_err
check "/dev/stdout: says why" grep -q "stdout.glb is a FIFO (pipe)" "$T/stderr"
check "/dev/stdout: nothing written" [ ! -s "$T/piped" ]
check "/dev/stdout: the link stays" [ -L "$T/special/stdout.glb" ]
if [ "$(id -u)" = 0 ]; then  # a device node of our own, as root may make one
  mknod "$T/special/null.off" c 1 3
  run "$VNC" "$TORUS" "$T/special/null.off"
  check "device refused with 1" [ $rc -eq 1 ]; check "device: says why" grep -q "is a character device" "$T/stderr"
  check "device stays" [ -c "$T/special/null.off" ]
fi
check "special: no temporaries" no_temporaries "$T/special"

# ---- modes: a replaced file keeps its own, a new file gets 0666 & ~umask.
mkdir -p "$T/mode"
for mode in 640 444 755; do
  for ext in off glb drc; do
    in=$TORUS; [ $ext = glb ] && in=$DUCK
    echo old >"$T/mode/m$mode.$ext"; chmod $mode "$T/mode/m$mode.$ext"
    run "$VNC" "$in" "$T/mode/m$mode.$ext" -q
    check "mode $mode .$ext: replaced" not grep -qx old "$T/mode/m$mode.$ext"
    check "mode $mode .$ext: kept" [ "$(stat -c %a "$T/mode/m$mode.$ext")" = $mode ]
  done
  cp "$TORUS" "$T/mode/self$mode.off"; chmod $mode "$T/mode/self$mode.off"
  run "$VNC" "$T/mode/self$mode.off" "$T/mode/self$mode.off" --in-place -q
  check "--in-place with mode $mode: NOFF" [ "$(head -1 "$T/mode/self$mode.off")" = NOFF ]
  check "--in-place keeps mode $mode" [ "$(stat -c %a "$T/mode/self$mode.off")" = $mode ]
done
(umask 027 && "$VNC" "$TORUS" "$T/mode/new.off" -q && "$VNC" "$DUCK" "$T/mode/new.gltf" -q)
check "new files: 0666 & ~umask" [ "$(stat -c %a "$T/mode/new.off" "$T/mode/new.gltf" "$T/mode/new.bin" | sort -u)" = 640 ]

# ---- a missing output folder is named before anything is read or written.
for ext in off glb gltf drc; do
  in=$TORUS; [ $ext = gltf ] && in=$DUCK
  run "$VNC" "$in" "$T/no/such/x.$ext"
  check "missing folder .$ext: exits 1" [ $rc -eq 1 ]; check "missing folder .$ext: one line" one_line_err
  check "missing folder .$ext: names the folder" grep -q "the folder '$T/no/such' does not exist" "$T/stderr"
done

# ---- non-finite positions: refused for every output format, naming the vertex.
mkdir -p "$T/nan"
printf 'OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n' >"$T/nan/nan.off"
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 -inf\n3 0 1 2\n' >"$T/nan/inf.off"
for ext in off glb gltf drc; do
  check_rejected "$VNC" "$T/nan/nan.off" "$T/nan/none.$ext" "$T/nan/keep.$ext"
  check "NaN -> .$ext: names the vertex" grep -q "nan.off: vertex 1 is at (1, nan, 0)" "$T/stderr"
  check_rejected "$VNC" "$T/nan/inf.off" "$T/nan/none.$ext" "$T/nan/keep.$ext"
  check "inf -> .$ext: names the vertex" grep -q "inf.off: vertex 2 is at (0, 1, -inf)" "$T/stderr"
done
check "NaN: no temporaries" no_temporaries "$T/nan"

finish
