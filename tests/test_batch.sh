#!/usr/bin/env bash
# vnconvert's batch mode (--out-dir), '-' for standard input and output, and
# --apply-transforms.
#   test_batch.sh PATH/TO/vnconvert
set -u
VNC=$1
HERE=$(cd "$(dirname "$0")" && pwd)
SAMPLES=$HERE/../samples
MODELS=$HERE/data/models/gltf
. "$HERE/lib.sh"
cd "$T"

# sorted_status FILE: the ok/FAIL lines of FILE without their timings, sorted
# (files finish in any order when several run at once).
sorted_status() { grep -E '^(ok  |FAIL)' "$1" | sed 's/, [0-9.]* ms)$/)/' | sort; }
# summary FILE: the summary line without its time.
summary() { grep '^vnconvert: [0-9]* files\? converted' "$1" | sed 's/ in [0-9.]* s$//'; }

# ---- a folder of mixed inputs: OFF (ASCII, binary, polygons), GLB, a .gltf with a
# texture, Draco; a subfolder, and files vn does not read.
mkdir -p in/sub/deeper in/Duck
cp "$SAMPLES/torus.off" "$SAMPLES/sphere-quads.off" "$HERE/data/off/tetra_binary.off" in/
cp "$HERE/data/gltf/shapes.glb" in/
cp "$MODELS/Duck/"* in/Duck/
cp "$HERE/data/draco/cube.drc" in/sub/
cp "$HERE/data/gltf/quantized.glb" in/sub/deeper/
echo notes >in/readme.txt
cp "$MODELS/Box.glb" in/.hidden.glb

# Without --recursive: the folder's own files; subfolders are counted, not entered.
run "$VNC" --out-dir flat in
check "flat batch exits 0" [ $rc -eq 0 ]
cat >expected <<'EOF'
ok   in/shapes.glb -> flat/shapes.glb  (408 triangles)
ok   in/sphere-quads.off -> flat/sphere-quads.off  (528 triangles)
ok   in/tetra_binary.off -> flat/tetra_binary.off  (4 triangles)
ok   in/torus.off -> flat/torus.off  (1,920 triangles)
EOF
check "flat batch: a status line per file" diff expected <(sorted_status "$T/stderr")
check "flat batch: summary" [ "$(summary "$T/stderr")" = "vnconvert: 4 files converted, 1 skipped (not a format vn reads), 2 folders not entered (--recursive); 2,860 triangles" ]
check "flat batch: only the folder's own files, each format kept" [ "$(cd flat && find . -type f | sort | tr '\n' ' ')" = "./shapes.glb ./sphere-quads.off ./tetra_binary.off ./torus.off " ]
# Each output is what converting its file alone gives.
"$VNC" in/torus.off single.off -q
check "batch output equals a single conversion" cmp -s single.off flat/torus.off

# The triangle counts of the status lines, counted independently.
# offtri FILE: the triangles of an OFF file's faces once fanned (comments left out).
offtri() { grep -v '^#' "$1" | awk 'NR==2 {v=$1; f=$2} NR>2+v && NR<=2+v+f {n+=$1-2} END {print n}'; }
check "torus: 1,920 triangles in the file" [ "$(offtri "$SAMPLES/torus.off")" = 1920 ]
check "sphere-quads: 528 triangles once fanned" [ "$(offtri "$SAMPLES/sphere-quads.off")" = 528 ]
check "tetra_binary: 4 triangles" [ "$("$VNC" "$HERE/data/off/tetra_binary.off" t.off --stats | grep '^faces:')" = "faces:              4 (triangles)" ]
check "shapes.glb: 408 triangles (lists, a strip, points)" [ "$(q in/shapes.glb "sum({4: c // 3, 5: c - 2, 6: c - 2}.get(p.get('mode', 4), 0) for m in d['meshes'] for p in m['primitives'] if 'indices' in p for c in [d['accessors'][p['indices']]['count']])")" = 408 ]

# --recursive: the folders' layout under DIR; --format for every output.
run "$VNC" --out-dir deep --recursive --format glb in -j 2
check "recursive batch exits 0" [ $rc -eq 0 ]
check "recursive batch: layout kept" [ "$(cd deep && find . -type f | sort | tr '\n' ' ')" = "./Duck/Duck.glb ./shapes.glb ./sphere-quads.glb ./sub/cube.glb ./sub/deeper/quantized.glb ./tetra_binary.glb ./torus.glb " ]
check "recursive batch: summary" [ "$(summary "$T/stderr")" = "vnconvert: 7 files converted, 3 skipped (not a format vn reads); 7,276 triangles" ]
check "recursive batch: cube.drc line" grep -q "^ok   in/sub/cube.drc -> deep/sub/cube.glb  (12 triangles, " "$T/stderr"
check "recursive batch: no hidden file converted" not grep -q hidden "$T/stderr"

# One file at a time or two at once: the same bytes.
run "$VNC" --out-dir j1 -r in -j 1 -q
run "$VNC" --out-dir j2 -r in -j 2 -q
check "-j 1 and -j 2: identical outputs" diff -r j1 j2
check "-q: nothing printed" [ -z "$err" ]
check "the .gltf keeps its texture, named after the output" cmp -s "$MODELS/Duck/DuckCM.png" j1/Duck/Duck_DuckCM.png
check "the .gltf's buffer named after the output" [ "$(q j1/Duck/Duck.gltf "[b['uri'] for b in d['buffers']] + [i['uri'] for i in d['images']]")" = "['Duck.bin', 'Duck_DuckCM.png']" ]

# ---- a bad file: that file fails, the others complete, exit status 1.
mkdir bad
cp "$SAMPLES/torus.off" "$HERE/data/gltf/shapes.glb" bad/
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n' >bad/broken.off
run "$VNC" --out-dir badout bad -j 2
check "a failed file: exit 1" [ $rc -eq 1 ]
check "a failed file: its one line" [ "$(grep -c '^FAIL' "$T/stderr")" = 1 ]
check "a failed file: the reader's error in it" grep -q "^FAIL bad/broken.off: bad/broken.off:[0-9]*: " "$T/stderr"
check "a failed file: no output for it" [ ! -e badout/broken.off ]
check "a failed file: the others written" cmp -s single.off badout/torus.off
check "a failed file: the other glb written" [ -s badout/shapes.glb ]
check "a failed file: summary" [ "$(summary "$T/stderr")" = "vnconvert: 2 files converted, 1 failed; 2,328 triangles" ]
run "$VNC" --out-dir badout2 bad -q
check "-q: the failure still printed, alone" [ "$(grep -c . "$T/stderr")" = 1 ] && check "-q: FAIL line" grep -q "^FAIL bad/broken.off: " "$T/stderr"

# ---- OBJ, PLY and STL to GLB (issue 17's "vnconvert --out-dir out/ --format glb
# assets/*.obj assets/*.ply"): every file of tests/data/obj, ply and stl (Draco's
# test files and Blender's exports; PLY and STL prefixed, as cube_att.obj and
# cube_att.ply would both be out/cube_att.glb). The two with infinite
# coordinates fail, the others convert, the point clouds as POINTS (Draco's
# test_lines.obj too: lines alone, which GLB output names as not written);
# the summary's triangles are those the GLB files hold.
mkdir assets
cp "$HERE"/data/obj/*.obj "$HERE"/data/obj/*.mtl assets/
for f in "$HERE"/data/ply/*.ply "$HERE"/data/stl/*.stl; do cp "$f" "assets/${f##*.}_$(basename "$f")"; done
run "$VNC" --out-dir pipeline --format glb assets/*.obj assets/*.ply assets/*.stl
check "OBJ, PLY, STL to GLB: exit 1 (some files are invalid)" [ $rc -eq 1 ]
check "OBJ, PLY, STL to GLB: the two files fail" [ "$(grep '^FAIL' "$T/stderr" | cut -d: -f1 | sort | tr '\n' ' ')" = \
  "FAIL assets/inf_nan.obj FAIL assets/ply_float_inf_point_cloud.ply " ]
check "OBJ, PLY, STL to GLB: summary" [ "$(summary "$T/stderr")" = "vnconvert: 31 files converted, 2 failed; 7,060 triangles" ]
check "OBJ, PLY, STL to GLB: 31 files" [ "$(ls pipeline | grep -c '\.glb$')" = 31 ]
check "OBJ, PLY, STL to GLB: the point clouds as POINTS" [ "$(for g in ply_int_point_cloud ply_point_cloud_test_pos test_lines; do q pipeline/$g.glb "[p['mode'] for m in d['meshes'] for p in m['primitives']]"; done | tr '\n' ' ')" = "[0] [0] [0] " ]
check "OBJ, PLY, STL to GLB: test_lines.obj's lines named as not written" grep -q "test_lines.glb cannot hold lines: not written" "$T/stderr"
glbtri=0
for g in pipeline/*.glb; do
  glbtri=$((glbtri + $(q "$g" "sum(d['accessors'][p['indices']]['count'] // 3 for m in d['meshes'] for p in m['primitives'] if p['mode'] == 4)")))
done
check "OBJ, PLY, STL to GLB: the GLB files hold 7060 triangles" [ $glbtri = 7060 ]

# ---- textures: two .gltf, each with its own Texture0.png, into one folder.
mkdir a b
cp "$MODELS/Duck/Duck.gltf" a/duck.gltf; cp "$MODELS/Duck/Duck0.bin" a/; cp "$MODELS/Duck/DuckCM.png" a/Texture0.png
cp "$MODELS/Duck/Duck.gltf" b/duck2.gltf; cp "$MODELS/Duck/Duck0.bin" b/; cp "$MODELS/TwoSidedPlane/TwoSidedPlane_BaseColor.png" b/Texture0.png
sed -i 's/DuckCM.png/Texture0.png/' a/duck.gltf b/duck2.gltf
run "$VNC" --out-dir tex a/duck.gltf b/duck2.gltf -j 2
check "two Texture0.png: exit 0" [ $rc -eq 0 ]
for m in a/duck b/duck2; do
  name=$(basename $m)
  image=$(q tex/$name.gltf "d['images'][0]['uri']")
  check "$name: its image has a name of its own" [ "$image" = "${name}_Texture0.png" ]
  check "$name: its image is its input's" cmp -s "$(dirname $m)/Texture0.png" "tex/$image"
done
# Again, into the same folder: the same files, no failure.
run "$VNC" --out-dir tex a/duck.gltf b/duck2.gltf -q
check "two Texture0.png again: exit 0" [ $rc -eq 0 ]

# ---- refused before any work (exit 2, nothing written)
mkdir c
cp b/duck2.gltf c/duck.gltf; cp b/Duck0.bin b/Texture0.png c/
run "$VNC" --out-dir same a c
check "two inputs, one output: exit 2" [ $rc -eq 2 ]
check "two inputs, one output: one line naming both" [ "$err" = "vnconvert: error: 'a/duck.gltf' and 'c/duck.gltf' would both be written to 'same/duck.gltf': convert them into different folders" ]
check "two inputs, one output: nothing written" [ ! -e same ]
run "$VNC" --out-dir in in/torus.off
check "an output that is its input: exit 2" [ $rc -eq 2 ]
run "$VNC" --out-dir x in/torus.off --tangents drop
check "an option for no file of the batch: exit 2" [ $rc -eq 2 ]
check "an option for no file of the batch: says so" grep -q "tangents applies only to glTF to glTF.*no file of this batch" "$T/stderr"
run "$VNC" --out-dir x in/torus.off in/shapes.glb --tangents drop -q
check "an option for some files of the batch: applied to those" [ $rc -eq 0 ]
run "$VNC" --out-dir x in/readme.txt
check "an unknown extension given by name: exit 2" [ $rc -eq 2 ]
run "$VNC" --out-dir x --stats in
check "--stats in a batch: exit 2" [ $rc -eq 2 ]
run "$VNC" in/torus.off x.off --recursive
check "--recursive without --out-dir: exit 2" [ $rc -eq 2 ]

# ---- '-': standard input and output
export TMPDIR=$T/tmp
mkdir "$TMPDIR"
run sh -c "cat '$SAMPLES/torus.off' | '$VNC' - - --input-format off --format off"
check "- to -: exit 0" [ $rc -eq 0 ]
check "- to -: what the file conversion writes" cmp -s "$T/stdout" single.off
"$VNC" in/shapes.glb shapes.drc -q
cat in/shapes.glb | "$VNC" - - --input-format glb --format drc -q >piped.drc
check "glb to drc through pipes: exit 0" [ $? -eq 0 ]
check "glb to drc through pipes: the file conversion's bytes" cmp -s piped.drc shapes.drc
"$VNC" in/shapes.glb - --format glb -q >piped.glb
check "file to -: exit 0" [ $? -eq 0 ]
"$VNC" in/shapes.glb shapes2.glb -q
check "file to -: the file conversion's bytes" cmp -s piped.glb shapes2.glb
run sh -c "'$VNC' - piped.off --input-format off <'$SAMPLES/torus.off'"
check "- to file: the same file" cmp -s piped.off single.off
run sh -c "'$VNC' - - --input-format off <in/torus.off"
check "- without --format: exit 2" [ $rc -eq 2 ]; check "- without --format: says so" grep -q "needs --format" "$T/stderr"
run sh -c "'$VNC' - x.off <in/torus.off"
check "- without --input-format: exit 2" [ $rc -eq 2 ]
run sh -c "'$VNC' - - --input-format gltf --format off <a/duck.gltf"
check ".gltf from -: exit 2" [ $rc -eq 2 ]; check ".gltf from -: says why" grep -q "may come with other files (buffers and images)" "$T/stderr"
run sh -c "'$VNC' - - --input-format off --format off <bad/broken.off"
check "bad input from -: exit 1" [ $rc -eq 1 ]
check "bad input from -: one line naming <stdin>" [ "$(grep -c . "$T/stderr")" = 1 ] && check "bad input: <stdin>" grep -q "^vnconvert: error: <stdin>:[0-9]*: " "$T/stderr"
check "bad input from -: nothing on stdout" [ ! -s "$T/stdout" ]
check "'-': no temporary folder left" [ -z "$(ls "$TMPDIR")" ]

# ---- --apply-transforms: the default scene's node transforms
# bounds FILE: the bounding box of an OFF file's vertices, 6 numbers at 4 decimals.
bounds() { awk 'NR==2 {n=$1} NR>2 && NR<=n+2 { for (i=1;i<=3;i++) { if (NR==3||$i<lo[i]) lo[i]=$i; if (NR==3||$i>hi[i]) hi[i]=$i } }
  END { printf "%.4f %.4f %.4f %.4f %.4f %.4f\n", lo[1],lo[2],lo[3],hi[1],hi[2],hi[3] }' "$1"; }
# scene_bounds FILE SCENE: the same, computed here from the glTF (SCENE 1: node transforms applied).
scene_bounds() {
  /usr/bin/python3 - "$1" "$2" <<'EOF'
import json, struct, sys, os
import numpy as np
path, scene = sys.argv[1], sys.argv[2] == "1"
raw = open(path, "rb").read()
if raw[:4] == b"glTF":
    n = struct.unpack("<I", raw[12:16])[0]
    d = json.loads(raw[20:20 + n]); bins = [raw[28 + n:]]
else:
    d = json.loads(raw); bins = [open(os.path.join(os.path.dirname(path), b["uri"]), "rb").read() for b in d["buffers"]]
def positions(a):
    acc = d["accessors"][a]; v = d["bufferViews"][acc["bufferView"]]
    stride = v.get("byteStride", 12); off = v.get("byteOffset", 0) + acc.get("byteOffset", 0)
    buf = bins[v["buffer"]]
    return np.array([struct.unpack_from("<3f", buf, off + i * stride) for i in range(acc["count"])], dtype=float)
def local(node):
    if "matrix" in node: return np.array(node["matrix"], dtype=float).reshape(4, 4).T
    x, y, z, w = node.get("rotation", [0, 0, 0, 1]); t = node.get("translation", [0, 0, 0]); s = node.get("scale", [1, 1, 1])
    r = np.array([[1-2*(y*y+z*z), 2*(x*y-z*w), 2*(x*z+y*w)], [2*(x*y+z*w), 1-2*(x*x+z*z), 2*(y*z-x*w)], [2*(x*z-y*w), 2*(y*z+x*w), 1-2*(x*x+y*y)]])
    m = np.eye(4); m[:3, :3] = r @ np.diag(s); m[:3, 3] = t; return m
points = []
def visit(i, parent):
    node = d["nodes"][i]; world = parent @ local(node)
    if "mesh" in node:
        for p in d["meshes"][node["mesh"]]["primitives"]:
            xyz = positions(p["attributes"]["POSITION"])
            points.append((np.c_[xyz, np.ones(len(xyz))] @ world.T)[:, :3])
    for c in node.get("children", []): visit(c, world)
if scene:
    for r in d["scenes"][d.get("scene", 0)]["nodes"]: visit(r, np.eye(4))
else:
    for m in d["meshes"]:
        for p in m["primitives"]: points.append(positions(p["attributes"]["POSITION"]))
p = np.vstack(points)
print(" ".join("%.4f" % v for v in list(p.min(0)) + list(p.max(0))))
EOF
}
for model in "$MODELS/Duck/Duck.gltf" "$MODELS/CesiumMan.glb" "$MODELS/Box.glb"; do
  name=$(basename "$model")
  "$VNC" "$model" local.off -q
  "$VNC" "$model" world.off --apply-transforms -q
  check "$name: without --apply-transforms, mesh-local bounds" [ "$(bounds local.off)" = "$(scene_bounds "$model" 0)" ]
  check "$name: with --apply-transforms, the scene's bounds" [ "$(bounds world.off)" = "$(scene_bounds "$model" 1)" ]
  [ "$name" = Duck.gltf ] && check "Duck: the transforms change the bounds" not [ "$(bounds local.off)" = "$(bounds world.off)" ]
done
# rescene IN OUT CODE: the GLB IN with its JSON d changed by CODE (Python).
rescene() {
  python3 - "$@" <<'EOF'
import json, struct, sys
raw = open(sys.argv[1], "rb").read()
n = struct.unpack("<I", raw[12:16])[0]
d = json.loads(raw[20:20 + n]); rest = raw[20 + n:]
exec(sys.argv[3])
j = json.dumps(d).encode(); j += b" " * (-len(j) % 4)
body = struct.pack("<II", len(j), 0x4E4F534A) + j + rest
open(sys.argv[2], "wb").write(b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body)
EOF
}
# One mesh instanced twice, once mirrored (scale -1): two copies, both with outward normals.
rescene "$MODELS/Box.glb" twice.glb 'd["nodes"] = [{"mesh": 0}, {"mesh": 0, "translation": [3, 0, 0], "scale": [-1, 1, 1]}]
d["scenes"] = [{"nodes": [0, 1]}]; d["scene"] = 0'
run "$VNC" twice.glb twice.off --apply-transforms -q
check "instanced twice: exit 0" [ $rc -eq 0 ]
check "instanced twice: 48 vertices, 24 triangles" [ "$(sed -n 2p twice.off)" = "48 24 0" ]
check "instanced twice: bounds" [ "$(bounds twice.off)" = "-0.5000 -0.5000 -0.5000 3.5000 0.5000 0.5000" ]
check "instanced twice: every normal points out of its cube" awk 'NR>2 && NR<=50 { c = (NR > 26) ? 3 : 0; if (($1-c)*$4 + $2*$5 + $3*$6 <= 0) bad=1; n++ } END { exit (bad || n != 48) }' twice.off
# Without the option, a scene drawn otherwise than its meshes' own
# coordinates is named; a mesh at its node without transform is not.
W="node transforms not applied: each mesh is written once, in its own coordinates, where the scene draws"
A="(--apply-transforms writes the scene as drawn)"
run "$VNC" "$MODELS/Box.glb" box.off
check "Box: its root node's rotation named" [ "$err" = "vnconvert: warning: $MODELS/Box.glb: $W 1 of 1 mesh instances with a node transform $A" ]
run "$VNC" twice.glb twice-local.off
check "instanced twice: named" [ "$err" = "vnconvert: warning: twice.glb: $W 1 of 2 mesh instances with a node transform, 1 mesh more than once $A" ]
rescene twice.glb undrawn.glb 'd["scenes"] = [{"nodes": []}]'
run "$VNC" undrawn.glb undrawn.off
check "a mesh no node draws: named" [ "$err" = "vnconvert: warning: undrawn.glb: $W 1 mesh by no node $A" ]
run "$VNC" box.off plain.glb -q
run "$VNC" plain.glb plain.off
check "a mesh at its node without transform: no warning" [ "$rc|$err" = "0|" ]
run "$VNC" twice.glb twice-world.off --apply-transforms
check "with --apply-transforms: no warning" [ "$rc|$err" = "0|" ]
# A chain of 100,000 nodes, each moving its child by 0.001 (a valid file:
# walked with a stack of vn's own, not recursion, which overflowed).
rescene "$MODELS/Box.glb" chain.glb 'd["nodes"] = [{"children": [i + 1], "translation": [0.001, 0, 0]} for i in range(100000)] + [{"mesh": 0}]
d["scenes"] = [{"nodes": [0]}]; d["scene"] = 0'
run "$VNC" chain.glb chain.off --apply-transforms
check "100,000 nested nodes: the box moved by 100" [ "$rc|$err|$(bounds chain.off)" = "0||99.5000 -0.5000 -0.5000 100.5000 0.5000 0.5000" ]
run "$VNC" chain.glb chain-local.off
check "100,000 nested nodes, mesh-local: named" [ "$rc|$err" = "0|vnconvert: warning: chain.glb: $W 1 of 1 mesh instances with a node transform $A" ]
run "$VNC" "$MODELS/Box.glb" x.glb --apply-transforms
check "--apply-transforms glTF to glTF: exit 2" [ $rc -eq 2 ]
check "--help states the mesh-local default" quietly grep -q "apply-transforms" <("$VNC" --help)

finish
