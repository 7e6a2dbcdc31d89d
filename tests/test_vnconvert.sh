#!/usr/bin/env bash
# End-to-end checks of vnconvert and vnbench, run as a user would run them.
#   test_vnconvert.sh PATH/TO/vnconvert PATH/TO/vnbench
set -u
VNC=$1
VNB=$2
SAMPLES=$(cd "$(dirname "$0")/../samples" && pwd)
. "$(dirname "$0")/lib.sh"

# run CMD...: sets $rc, $out (stdout), $err (stderr)

# ---- information
run "$VNC" --help;          check "--help exits 0 with usage" [ $rc -eq 0 ] && check "--help text" grep -q "usage: vnconvert IN OUT" "$T/stdout"
run "$VNC" --version;       check "--version" grep -qE "^vnconvert [0-9]+\.[0-9]+\.[0-9]+" "$T/stdout"
run "$VNC" --list-methods;  check "--list-methods lists 7" [ "$(wc -l <"$T/stdout")" -eq 7 ]
check "--list-methods names mewcsa with reference" grep -q "^mewcsa .*Desbrun" "$T/stdout"

# ---- a normal conversion: NOFF with unit normals, same positions and faces
run "$VNC" "$SAMPLES/torus.off" "$T/torus.off" --method MWSELR -q
check "conversion exits 0" [ $rc -eq 0 ]
check "quiet conversion prints nothing" [ -z "$out$err" ]
check "output is NOFF" [ "$(head -1 "$T/torus.off")" = "NOFF" ]
check "every normal has unit length" awk 'NR>2 && NF==6 { l=sqrt($4*$4+$5*$5+$6*$6); if (l<0.9999999 || l>1.0000001) bad=1; n++ }
  END { exit (bad || n != 960) }' "$T/torus.off"
# Outward torus: normal . (p - ring centre) > 0 at every vertex.
check "torus normals point outward" awk 'NR>2 && NF==6 { r=sqrt($1*$1+$2*$2); cx=$1/r; cy=$2/r;
  d=($1-cx)*$4+($2-cy)*$5+$3*$6; if (d<=0) bad=1 } END { exit bad }' "$T/torus.off"

# Thread count does not change a single bit.
run "$VNC" "$SAMPLES/torus.off" "$T/j1.off" -j 1 -q
run "$VNC" "$SAMPLES/torus.off" "$T/j2.off" -j 2 -q
check "-j 1 and -j 2 give identical files" cmp -s "$T/j1.off" "$T/j2.off"
# Methods differ from each other (the option is honoured).
run "$VNC" "$SAMPLES/torus.off" "$T/mwe.off" -m mwe -q
check "--method changes the output" not cmp -s "$T/j1.off" "$T/mwe.off"

# Polygons: the quad sphere's normals are within 1 degree of the position direction.
run "$VNC" "$SAMPLES/sphere-quads.off" "$T/sq.off" --stats
check "polygon conversion exits 0" [ $rc -eq 0 ]
check "--stats reports counts" grep -q "^vertices: *266$" "$T/stdout"
check "--stats reports polygons" grep -q "^faces: *288 (polygons)$" "$T/stdout"
check "--stats reports timing" grep -q "^time normals: .* ms$" "$T/stdout"
check "sphere normals radial" awk 'NR>2 && NF==6 { d=$1*$4+$2*$5+$3*$6; if (d < 0.99985) bad=1; n++ } END { exit (bad || n != 266) }' "$T/sq.off"

# ---- errors: one line on stderr, non-zero exit, no output file
run "$VNC" "$SAMPLES/torus.off" "$T/x.off" --method nope
check "unknown method exits 2" [ $rc -eq 2 ]; check "unknown method: one line" one_line_err
check "unknown method: no output" [ ! -e "$T/x.off" ]
run "$VNC" "$SAMPLES/torus.off"
check "missing OUT exits 2" [ $rc -eq 2 ]; check "missing OUT: one line" one_line_err
run "$VNC" "$T/does-not-exist.off" "$T/x.off"
check "missing input exits 1" [ $rc -eq 1 ]; check "missing input: one line" one_line_err
check "missing input names the file" grep -q "does-not-exist.off" "$T/stderr"
run "$VNC" "$SAMPLES/torus.off" "$T/x.xyz"
check "unknown extension exits 2" [ $rc -eq 2 ]; check "unknown extension: one line" one_line_err
run "$VNC" "$SAMPLES/torus.off" "$T/x.off" --threads 0
check "bad --threads exits 2" [ $rc -eq 2 ]
run "$VNC" "$SAMPLES/torus.off" "$T/no/such/dir/x.off"
check "unwritable output exits 1" [ $rc -eq 1 ]; check "unwritable output: one line" one_line_err

# A malformed input leaves an existing output byte for byte as it was, and no temporary file.
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n' >"$T/bad.off"
echo "precious" >"$T/keep.off"
run "$VNC" "$T/bad.off" "$T/keep.off"
check "malformed input exits 1" [ $rc -eq 1 ]; check "malformed input: one line" one_line_err
check "malformed input error names file and line" grep -q "bad.off:6:" "$T/stderr"
check "existing output untouched" [ "$(cat "$T/keep.off")" = "precious" ]
check "no temporary files left" [ "$(ls -A "$T" | grep -vc -e '^stdout$' -e '^stderr$' -e '\.off$')" -eq 0 ]

# OUT == IN is refused (also through another path to the same file) unless --in-place.
cp "$SAMPLES/torus.off" "$T/self.off"
before=$(md5sum <"$T/self.off")
run "$VNC" "$T/self.off" "$T/self.off"
check "OUT == IN refused with 2" [ $rc -eq 2 ]; check "OUT == IN: one line" one_line_err
run "$VNC" "$T/self.off" "$T/../$(basename "$T")/self.off"
check "OUT == IN through another path refused" [ $rc -eq 2 ]
ln -s "$T/self.off" "$T/link.off"
run "$VNC" "$T/self.off" "$T/link.off"
check "OUT == IN through a symlink refused" [ $rc -eq 2 ]
check "input unchanged after refusals" [ "$(md5sum <"$T/self.off")" = "$before" ]
run "$VNC" "$T/self.off" "$T/self.off" --in-place -q
check "--in-place works" [ $rc -eq 0 ] && check "--in-place rewrote the file as NOFF" [ "$(head -1 "$T/self.off")" = "NOFF" ]

# ---- vnbench
run "$VNB" "$SAMPLES/torus.off" --csv --repeat 3
check "vnbench exits 0" [ $rc -eq 0 ]
check "vnbench CSV header" [ "$(head -1 "$T/stdout")" = "method,threads,triangles,median_ns_per_tri,mtri_per_s" ]
check "vnbench CSV has 7 rows of numbers" [ "$(grep -cE '^[a-z]+,1,1920,[0-9.]+,[0-9.]+$' "$T/stdout")" -eq 7 ]
run "$VNB" "$SAMPLES/torus.off" --csv --repeat 3 --method mwa --threads 2
check "vnbench one method" [ "$(grep -cE '^mwa,2,1920,' "$T/stdout")" -eq 1 ] && check "vnbench one row only" [ "$(wc -l <"$T/stdout")" -eq 2 ]
run "$VNB" "$SAMPLES/torus.off" --repeat 0
check "vnbench bad --repeat exits 2" [ $rc -eq 2 ]
run "$VNB" "$SAMPLES/sphere-quads.off" --repeat 1
check "vnbench polygons" grep -q "polygons" "$T/stdout"

finish
