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
run "$VNC" --list-methods;  check "--list-methods lists 11" [ "$(wc -l <"$T/stdout")" -eq 11 ]
check "--list-methods names mewcsa with reference" grep -q "^mewcsa .*Desbrun" "$T/stdout"
check "--list-methods: descriptions in one column (names padded to the longest, adaptive)" [ "$(cut -c1-9 "$T/stdout" | sed -n "1p;11p")" = "$(printf "mwe      \nadaptive ")" ]

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

# ---- messages: each one line that names what is wrong and what to do.
GLTF=$(cd "$(dirname "$0")/data/models/gltf" && pwd)
# Formats vn does not read or write: --input-format/--format cannot help.
for ext in fbx dae; do
  touch "$T/mesh.$ext"
  run "$VNC" "$T/mesh.$ext" "$T/x.off"
  check ".$ext input exits 2" [ $rc -eq 2 ]; check ".$ext input: one line" one_line_err
  check ".$ext input: what vn reads, and to convert" grep -q "mesh.$ext' is an\? [A-Z]* file, and vn reads only OFF, OBJ, PLY, STL, glTF, GLB and Draco files: convert it to one of these first (e.g. with meshlabserver or Blender)" "$T/stderr"
  check ".$ext input: no --input-format advice" not grep -q -- "--input-format" "$T/stderr"
  run "$VNC" "$SAMPLES/torus.off" "$T/out.$ext"
  check ".$ext output exits 2" [ $rc -eq 2 ]
  check ".$ext output: what vn writes" grep -q "vn writes only OFF, OBJ, PLY, STL, glTF, GLB and Draco files: write one of these and convert that" "$T/stderr"
done
run "$VNC" "$T/mesh.xyz" "$T/x.off"
check "unknown extension: names --input-format" grep -q "cannot tell the format of '$T/mesh.xyz' from its extension: vn reads OFF (.off), OBJ (.obj), PLY (.ply), STL (.stl), glTF (.gltf, .glb) and Draco (.drc); name the format with --input-format" "$T/stderr"
# Option errors name the option and what it accepts.
expect_usage() {  # expect_usage MESSAGE ARGS...: exit 2, one line, MESSAGE in it
  local message=$1; shift
  run "$VNC" "$@"
  check "$* exits 2" [ $rc -eq 2 ]; check "$*: one line" one_line_err
  check "$*: says '$message'" grep -qF -- "$message" "$T/stderr"
}
expect_usage "--draco-qp needs a whole number of bits from 1 to 30, not '31'" "$SAMPLES/torus.off" "$T/u.drc" --draco-qp 31
expect_usage "--draco-qt needs a whole number of bits from 1 to 30, not '0'" "$SAMPLES/torus.off" "$T/u.drc" --draco-qt 0
expect_usage "--draco-qc needs a whole number of bits from 1 to 30, not 'x'" "$SAMPLES/torus.off" "$T/u.drc" --draco-qc x
expect_usage "--draco-qn needs a whole number of bits from 2 to 30, not '1'" "$SAMPLES/torus.off" "$T/u.drc" --draco-qn 1
expect_usage "--draco-cl needs a whole number from 0 to 10, not '11'" "$SAMPLES/torus.off" "$T/u.drc" --draco-cl 11
expect_usage "--threads needs a whole number from 1 to 256, not '0'" "$SAMPLES/torus.off" "$T/u.off" --threads 0
expect_usage "--method is one of mwe, mwa, mwselr, mwaat, mwelr, mwrelr, mewcsa, smewcsa, quadric, jet, adaptive, not 'nope'" "$SAMPLES/torus.off" "$T/u.off" --method nope
expect_usage "--format is one of off, obj, ply, stl, gltf, glb, drc, not 'fbx'" "$SAMPLES/torus.off" "$T/u.off" --format fbx
expect_usage "--input-format is one of off, obj, ply, stl, gltf, glb, drc, not 'dae'" "$SAMPLES/torus.off" "$T/u.off" --input-format dae
expect_usage "--draco-qp applies to Draco (.drc) output, to glTF to glTF conversions and to glTF output with --draco on, and this one is off to off: leave it out" "$SAMPLES/torus.off" "$T/u.off" --draco-qp 12
expect_usage "--draco-qp applies to Draco (.drc) output, to glTF to glTF conversions and to glTF output with --draco on, and this one is off to glb: leave it out" "$SAMPLES/torus.off" "$T/u.glb" --draco-qp 12
expect_usage "--draco applies to glTF output (.gltf or .glb), and this one is glb to off: leave it out" "$GLTF/Duck.glb" "$T/u.off" --draco on
# glTF-only options are refused for other conversions rather than ignored.
for option in "--weld-scope mesh" "--tangents drop"; do
  expect_usage "${option%% *} applies only to glTF to glTF conversions (.gltf or .glb in and out), and this one is off to glb: leave it out" "$SAMPLES/torus.off" "$T/u.glb" $option
  expect_usage "${option%% *} applies only to glTF to glTF conversions (.gltf or .glb in and out), and this one is glb to off: leave it out" "$GLTF/Duck.glb" "$T/u.off" $option
done
check "usage errors write nothing" [ -z "$(ls "$T" | grep '^u\.')" ]
# Singular and plural.
printf 'OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n5 5 5\n3 0 1 2\n' >"$T/one-isolated.off"
run "$VNC" "$T/one-isolated.off" "$T/one.off"
check "1 of 4 vertices has no normal" grep -q "warning: 1 of 4 vertices has no normal" "$T/stderr"
run "$VNC" "$T/one-isolated.off" "$T/one.drc"
check "Draco: 1 triangle" grep -q "warning: 4 vertices and 1 triangle: only" "$T/stderr"
printf 'OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n' >"$T/no-faces.off"
run "$VNC" "$T/no-faces.off" "$T/no-faces.off.off"
check "a point cloud: no normals computed, none written" grep -q "warning: $T/no-faces.off has no faces (a point cloud): vn computes no normals; it has none, and none are written$" "$T/stderr"
check "a point cloud without normals: written as OFF, not NOFF" [ "$(head -1 "$T/no-faces.off.off")" = OFF ]
run "$VNC" "$GLTF/sphere/sphere.gltf" "$T/sp.glb"
check "1 primitive has TANGENT data" grep -q "warning: 1 primitive has TANGENT data" "$T/stderr"
run "$VNC" "$GLTF/sphere/sphere.gltf" "$T/spd.glb" --tangents drop --stats
check "--stats: 1 accessor, 1 bufferView" grep -q "^removed unused: *1 accessor, 1 bufferView$" "$T/stdout"
check "--stats: 0 points, 0 lines" grep -q "^primitives: *1 processed, 0 skipped (0 points, 0 lines, 0 without POSITION)$" "$T/stdout"
run "$VNC" "$T/one-isolated.off" "$T/one-stats.drc" --stats -q
check "--stats: 3 normals" grep -q "(qn=10, 3 normals)$" "$T/stdout"
# What OUT's format cannot hold is named.
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 255 0 0\n' >"$T/face-colour.off"
for ext in drc glb; do
  run "$VNC" "$T/face-colour.off" "$T/face-colour.$ext"
  check "face colours -> .$ext: exits 0" [ $rc -eq 0 ]
  check "face colours -> .$ext: one warning" [ "$(cat "$T/stderr")" = "vnconvert: warning: $T/face-colour.$ext cannot hold face colours: not written" ]
done
run "$VNC" "$T/face-colour.off" "$T/face-colour-q.drc" -q
check "-q: no loss warning" [ ! -s "$T/stderr" ]
run "$VNC" "$T/face-colour.off" "$T/face-colour.off.off"
check "OFF holds face colours: no warning" [ ! -s "$T/stderr" ]
# A glTF with an extension vn does not know keeps the data vn replaced; the
# warning says which extension, that the data stay unused, why, and that
# the file is otherwise fine.
cp -r "$GLTF/BoxMetaDraco" "$T/meta"
python3 - "$T/meta/BoxMetaDraco.gltf" <<'EOF'
import json, sys
doc = json.load(open(sys.argv[1]))
doc["extensionsUsed"].append("EXT_vn_test_unknown")
json.dump(doc, open(sys.argv[1], "w"))
EOF
run "$VNC" "$T/meta/BoxMetaDraco.gltf" "$T/meta-out.glb"
check "unknown extension: exits 0" [ $rc -eq 0 ]
check "unknown extension: one clear warning" [ "$(cat "$T/stderr")" = "vnconvert: warning: $T/meta-out.glb uses EXT_vn_test_unknown, an extension vn does not know that may refer to accessors or bufferViews by their index, so the data vn replaced stay in the file, unused, rather than being removed and the rest renumbered; the file is otherwise complete and correct" ]
# KHR_interactivity, KHR_node_selectability and KHR_node_hoverability hold
# no accessor or bufferView index (interactivity's pointers reach nodes,
# materials, meshes, cameras, skins, animations and scenes, none of which
# pruning renumbers): what vn replaced is removed, without a warning.
cp -r "$GLTF/BoxMetaDraco" "$T/interactive"
python3 - "$T/interactive/BoxMetaDraco.gltf" <<'EOF'
import json, sys
doc = json.load(open(sys.argv[1]))
doc["extensionsUsed"] += ["KHR_interactivity", "KHR_node_selectability", "KHR_node_hoverability"]
doc["extensions"] = dict(doc.get("extensions", {}), KHR_interactivity={"graphs": [{"nodes": [{"declaration": 0, "configuration": {"pointer": {"value": ["/nodes/{nodeIndex}/translation"]}}}]}]})
doc["nodes"][0].setdefault("extensions", {}).update(KHR_node_selectability={"selectable": True}, KHR_node_hoverability={"hoverable": False})
json.dump(doc, open(sys.argv[1], "w"))
EOF
run "$VNC" "$T/interactive/BoxMetaDraco.gltf" "$T/interactive-out.glb" --stats
check "KHR_interactivity and node selectability, hoverability: no warning" [ "$rc|$(cat "$T/stderr")" = "0|" ]
check "KHR_interactivity and node selectability, hoverability: replaced data removed" grep -q "^removed unused: *0 accessors, 1 bufferView$" "$T/stdout"

# ---- welding, hard edges and creases apply to every conversion
# Two quads meeting at x = 0, the left one flat, the right one rising at 45
# degrees; the file splits the seam's vertices (1 = 4, 2 = 7). Welded, the
# copies get one normal (MWE: the two faces' sum, (-sin 22.5, 0, cos 22.5));
# --no-weld leaves each copy its own face's.
printf 'OFF\n8 2 0\n-1 0 0\n0 0 0\n0 1 0\n-1 1 0\n0 0 0\n1 0 1\n1 1 1\n0 1 0\n4 0 1 2 3\n4 4 5 6 7\n' >"$T/seam.off"
normal() { sed -n "$(($2 + 3))p" "$1" | cut -d' ' -f4-6; }  # normal FILE VERTEX
run "$VNC" "$T/seam.off" "$T/seam-welded.off" -m mwe --stats
check "seam: welded 2" grep -q "^welded vertices: *2$" "$T/stdout"
check "seam: equal normals across the seam" [ "$(normal "$T/seam-welded.off" 1)" = "$(normal "$T/seam-welded.off" 4)" ]
check "seam: the faces' sum" [ "$(normal "$T/seam-welded.off" 2) $(normal "$T/seam-welded.off" 7)" = "-0.382683432 0 0.923879533 -0.382683432 0 0.923879533" ]
run "$VNC" "$T/seam.off" "$T/seam-split.off" -m mwe --no-weld --stats
check "--no-weld: welded 0" grep -q "^welded vertices: *0$" "$T/stdout"
check "--no-weld: each copy its face's normal" [ "$(normal "$T/seam-split.off" 1) $(normal "$T/seam-split.off" 4)" = "0 0 1 -0.707106781 0 0.707106781" ]
# The seam's copies with their faces' normals (as an exporter writes a hard
# edge) keep the edge hard, welded or not.
awk 'NR == 1 { print "NOFF"; next } NR >= 3 && NR <= 6 { print $0, "0 0 1"; next }
  NR >= 7 && NR <= 10 { print $0, "-0.707106781 0 0.707106781"; next } { print }' "$T/seam.off" >"$T/seam-hard.off"
run "$VNC" "$T/seam-hard.off" "$T/seam-hard-out.off" -m mwe --stats
check "hard seam: 1 hard edge" grep -q "^hard edges kept: *1$" "$T/stdout"
check "hard seam: each copy keeps its face's normal" [ "$(normal "$T/seam-hard-out.off" 1) $(normal "$T/seam-hard-out.off" 4)" = "0 0 1 -0.707106781 0 0.707106781" ]
# --crease-angle: the cube's corners split into one vertex per face, each
# with the face's normal (24 vertices); without it, 8 smooth ones.
CUBE=$(cd "$(dirname "$0")/data/off" && pwd)/cube.off
run "$VNC" "$CUBE" "$T/cube-crease.off" --crease-angle 30 --stats
sed -i '/^#/d' "$T/cube-crease.off" # the input's comment, kept: the checks below count lines
check "--crease-angle on OFF: 16 split" grep -q "^split vertices: *16$" "$T/stdout"
check "--crease-angle on OFF: 24 vertices with face normals" [ "$(sed -n 2p "$T/cube-crease.off")" = "24 6 0" ] &&
  check "--crease-angle on OFF: every normal a face's" awk 'NR > 2 && NR <= 26 { if (($4*$4 != 1 && $5*$5 != 1 && $6*$6 != 1) || $4*$5 || $5*$6 || $4*$6) bad = 1; n++ } END { exit bad || n != 24 }' "$T/cube-crease.off"
check "--crease-angle on OFF: still quads" [ "$(awk 'NR > 26 && $1 == 4' "$T/cube-crease.off" | wc -l)" -eq 6 ]
run "$VNC" "$CUBE" "$T/cube-smooth.off"
check "OFF -> OFF: the header's comment kept, after the keyword" \
  [ "$(sed -n 2p "$T/cube-smooth.off")" = "# A unit cube: 8 corners and 6 quads, counter-clockwise seen from outside." ]
sed -i '/^#/d' "$T/cube-smooth.off"
check "no --crease-angle: 8 vertices" [ "$(sed -n 2p "$T/cube-smooth.off")" = "8 6 0" ]
check "no --crease-angle: smooth corners" [ "$(normal "$T/cube-smooth.off" 6)" = "0.577350269 0.577350269 0.577350269" ]
run "$VNC" "$CUBE" "$T/cube-crease.glb" --crease-angle 30
check "--crease-angle to .glb: 24 vertices" [ "$(q "$T/cube-crease.glb" 'd["accessors"][d["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]["count"]')" = 24 ]

# ---- vnbench
run "$VNB" "$SAMPLES/torus.off" --csv --repeat 3
check "vnbench exits 0" [ $rc -eq 0 ]
check "vnbench CSV header" [ "$(head -1 "$T/stdout")" = "method,threads,triangles,median_ns_per_tri,mtri_per_s" ]
check "vnbench CSV has 11 rows of numbers" [ "$(grep -cE '^[a-z]+,1,1920,[0-9.]+,[0-9.]+$' "$T/stdout")" -eq 11 ]
run "$VNB" "$SAMPLES/torus.off" --csv --repeat 3 --method mwa --threads 2
check "vnbench one method" [ "$(grep -cE '^mwa,2,1920,' "$T/stdout")" -eq 1 ] && check "vnbench one row only" [ "$(wc -l <"$T/stdout")" -eq 2 ]
run "$VNB" "$SAMPLES/torus.off" --repeat 0
check "vnbench bad --repeat exits 2" [ $rc -eq 2 ]
run "$VNB" "$SAMPLES/sphere-quads.off" --repeat 1
check "vnbench polygons" grep -q "polygons" "$T/stdout"

# A Git LFS pointer (a repository cloned without its large files, as
# meshio's elephav.obj and tet.ply were here) is named as one in every
# format, and as a glTF's buffer file: it was "malformed", or an OBJ read as
# an empty mesh.
printf 'version https://git-lfs.github.com/spec/v1\noid sha256:863bb0ad077f2af5c05e70338b9a2643c840208d26984141c731e95b7bcc1b6a\nsize 76928\n' >"$T/pointer"
for ext in off obj ply stl gltf glb drc; do
  cp "$T/pointer" "$T/lfs.$ext"
  check_rejected "$VNC" "$T/lfs.$ext" "$T/none.off" "$T/keep.off"
  check "LFS pointer .$ext: says so" [ "$err" = "vnconvert: error: $T/lfs.$ext: a Git LFS pointer, not the file itself (whose 76928 bytes are in LFS storage): fetch it with 'git lfs pull'" ]
done
mkdir -p "$T/lfs-duck" && cp "$SAMPLES/../tests/data/models/gltf/Duck/Duck.gltf" "$T/lfs-duck/" && cp "$T/pointer" "$T/lfs-duck/Duck0.bin"
check_rejected "$VNC" "$T/lfs-duck/Duck.gltf" "$T/none.glb" "$T/keep.glb"
check "LFS pointer as a buffer: says so" grep -qF "Duck.gltf: buffers[0]: $T/lfs-duck/Duck0.bin: a Git LFS pointer, not the file itself" "$T/stderr"
finish
