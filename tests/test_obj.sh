#!/usr/bin/env bash
# OBJ through vnconvert: files from Draco's testdata and Blender 3.4's
# exporter (tests/data/obj), read through Draco's ObjDecoder and written by vn.
#   test_obj.sh PATH/TO/vnconvert NODE_MODULES_DIR
# Checks: the triangle count Draco's own tools see, OBJ -> OBJ keeping every
# face's corners (positions, texture coordinates), polygons, materials,
# object names, groups and smoothing groups exactly (and a second round trip
# changing no byte), mtllib
# names written from the output's folder to the input's .mtl files, unit
# normals, a v line per v line of the input with corners told apart by vn, OBJ -> OFF
# -> OBJ, OBJ -> GLB through the Khronos validator, and one-line errors for
# invalid files. objcheck.py reads OBJ independently of Draco and vn.
set -u
VNC=$(realpath "$1")
MODULES=$2
HERE=$(cd "$(dirname "$0")" && pwd)
DATA=$HERE/data/obj
. "$HERE/lib.sh"
objcheck() { python3 "$HERE/objcheck.py" "$@"; }
# stat NAME: the value of --stats line NAME in $out.
stat() { echo "$out" | sed -n "s/^$1: *\([0-9]*\).*/\1/p"; }

meshes="blender_cube blender_cylinder blender_sphere cube_att cube_att_sub_o cube_quads deg_faces extra_vertex
        mat_test multiple_isolated_triangles octagon point_cloud_test_pos sphere test_nm"
for m in $meshes; do
  in=$DATA/$m.obj
  run "$VNC" "$in" "$T/$m.obj" --stats -q
  check "$m: converts" [ $rc -eq 0 ]
  # Draco's own reader (draco_encoder, then draco_decoder's triangles); it
  # takes at most 8 corners a face, so the cylinder's 12-corner caps are
  # counted from the file; its encoder drops deg_faces' "f 1 1 3", which its
  # reader keeps (as vn does).
  if [ $m = blender_cylinder ]; then
    want=$(objcheck triangles "$in")
  elif [ $m = deg_faces ]; then
    want=4
  else
    draco_encoder -i "$in" -o "$T/$m.drc" >/dev/null && draco_decoder -i "$T/$m.drc" -o "$T/$m-draco.obj" >/dev/null
    want=$(grep -c '^f ' "$T/$m-draco.obj")
  fi
  check "$m: $want triangles as Draco reads it" [ "$(objcheck triangles "$T/$m.obj")" = "$want" ]
  check "$m: --stats counts the file's faces" [ "$(stat faces)" = "$(grep -c '^f' "$in")" ]
  objcheck faces "$in" >"$T/$m.in-faces"
  objcheck faces "$T/$m.obj" >"$T/$m.out-faces"
  check "$m: OBJ -> OBJ keeps every face, its corners, material, object, group and smoothing group" \
    cmp -s "$T/$m.in-faces" "$T/$m.out-faces"
  check "$m: unit normals" objcheck unit "$T/$m.obj"
  check "$m: a v line per v line of the input" [ "$(grep -c '^v ' "$T/$m.obj")" = "$(grep -c '^v ' "$in")" ]
  # Every vertex vn read (a v/vt/vn combination, or a v line no face uses)
  # is one combination written, or one v line no face uses.
  check "$m: a reference or a loose v line per vertex" [ "$(objcheck vertices "$T/$m.obj")" = "$(stat vertices)" ]
  "$VNC" "$T/$m.obj" "$T/$m.2.obj" -q
  check "$m: a second OBJ -> OBJ changes no byte" cmp -s "$T/$m.obj" "$T/$m.2.obj"
  run "$VNC" "$in" "$T/$m.off" -q
  "$VNC" "$T/$m.off" "$T/$m.3.obj" -q
  objcheck faces "$T/$m.3.obj" | cut -d'|' -f5- >"$T/$m.off-faces"
  cut -d'|' -f5- "$T/$m.in-faces" >"$T/$m.in-plain"
  check "$m: OBJ -> OFF -> OBJ keeps every face and its corners" cmp -s "$T/$m.in-plain" "$T/$m.off-faces"
  "$VNC" "$in" "$T/$m.glb" -q
  check "$m: OBJ -> GLB passes the Khronos validator" \
    python3 -c 'import json, sys; r = json.loads(sys.stdin.read()); sys.exit(bool(r["errors"] or r["warnings"]))' \
    < <(node "$HERE/gltf/validate.mjs" "$MODULES" "$T/$m.glb")
done

# What the files hold, as written.
# The output is in another folder: its mtllib names the input's .mtl from there.
mtl=$(sed -n 's/^mtllib //p' "$T/blender_cube.obj")
check "cube: mtllib names the input's .mtl" [ "$T/$mtl" -ef "$DATA/blender_cube.mtl" ]
check "cube: 4 Blue faces, then 2 Red" [ "$(grep -E '^(usemtl|o) ' "$T/blender_cube.obj" | tr '\n' ,)" = "o Cube,usemtl Blue,usemtl Red," ]
check "cube: 4 corners a face" [ "$(grep '^f' "$T/blender_cube.obj" | awk '{print NF - 1}' | sort -u)" = 4 ]
check "cylinder: two 12-corner caps" [ "$(grep '^f' "$T/blender_cylinder.obj" | awk 'NF == 13' | wc -l)" = 2 ]
check "sub_o: three objects" [ "$(grep '^o ' "$T/cube_att_sub_o.obj" | tr '\n' ,)" = "o obj0,o obj1,o obj2," ]
check "mat_test: 7 material changes" [ "$(grep -c '^usemtl' "$T/mat_test.obj")" = 7 ]
# Its GLB draws one vertex array from a primitive per material: converted
# again, the primitives are computed together (no NORMAL accessor split off,
# no vertex without a normal), the normals within 0.01 degrees of the first.
run "$VNC" "$T/mat_test.glb" "$T/mat_test.2.glb" --stats
check "mat_test GLB -> GLB: one vertex array, its NORMAL kept" [ "$rc|$(cat "$T/stderr")|$(echo "$(cat "$T/stdout")" | sed -n 's/^appended accessors: *//p')" = "0||0" ]
check "mat_test GLB -> GLB: the same normals" python3 "$HERE/gltf/gltfcheck.py" samenormals "$T/mat_test.glb" "$T/mat_test.2.glb" 0.01
# cube_att splits each corner of the cube by its face's normal and texture
# coordinate: 8 positions, each vertex a v/vt/vn of its own.
check "cube_att: 8 v lines" [ "$(grep -c '^v ' "$T/cube_att.obj")" = 8 ]
# Faces before the first usemtl stay without a material (Draco gives them the first one).
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nusemtl B\nf 2 4 3\n' >"$T/late.obj"
"$VNC" "$T/late.obj" "$T/late-out.obj" -q
check "faces before usemtl keep none" [ "$(grep -E '^(usemtl|f)' "$T/late-out.obj" | cut -c1-6 | tr '\n' ,)" = "f 1//1,usemtl,f 2//1," ]
# Lines Draco reads otherwise: a comment after a face, a tab after v, CR line ends.
printf 'v\t0 0 0\r\nv 1 0 0\rv 0 1 0\nf 1 2 3 # a comment\n' >"$T/odd.obj"
run "$VNC" "$T/odd.obj" "$T/odd-out.obj" --stats -q
check "comment, tab, CR: 3 vertices, 1 face" [ "$(stat vertices) $(stat faces)" = "3 1" ]
# A 10-corner face with relative indices stays one face.
printf 'v 0 0 0\nv 2 0 0\nv 3 1 0\nv 3 2 0\nv 2 3 0\nv 1 3 0\nv 0 3 0\nv -1 2 0\nv -1 1 0\nv -0.5 0.2 0\nf -10 -9 -8 -7 -6 -5 -4 -3 -2 -1\n' >"$T/ten.obj"
"$VNC" "$T/ten.obj" "$T/ten-out.obj" -q
check "10-corner face kept" [ "$(grep '^f' "$T/ten-out.obj" | sed 's#//1##g')" = "f 1 2 3 4 5 6 7 8 9 10" ]
# What exporters write and Draco refuses or misreads (trimesh's test models
# jacked.obj, polygonfaces.obj, wallhole.obj from Rhino, notenoughindices.obj):
# an empty slot after a slash, a face continued on the next line, an empty
# usemtl (Draco then skips the next line in one pass and writes out of
# bounds), a face of 2 corners (skipped, with a warning).
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1/ 2/2/ 3/3/\nf 2// 4// 3//\n' >"$T/slash.obj"
run "$VNC" "$T/slash.obj" "$T/slash-out.obj" --stats -q
check "v/vt/ and v//: 2 faces" [ "$rc $(stat faces)" = "0 2" ]
check "v/vt/ and v//: texture coordinates kept" [ "$(grep '^f' "$T/slash-out.obj" | head -1)" = "f 1/1/1 2/2/1 3/3/1" ]
# A face without vt beside faces with them stays without (Draco fills its
# corners with the first vt, which was written for them before).
check "v//: no texture coordinate made up" [ "$(grep '^f' "$T/slash-out.obj" | tail -1)" = "f 2//1 4//1 3//1" ]
# A face without vt has vertices of its own: Draco gives its corners the
# first vt, and merged them with a textured face's corners there; written and
# read again, the first vt was another one and they split (fuzz_obj found it).
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 1\nf 3/2 1/1 2/2\nf 1 2 4\n' >"$T/first_vt.obj"
run "$VNC" "$T/first_vt.obj" "$T/first_vt2.obj" --stats
once=$(stat vertices)
run "$VNC" "$T/first_vt2.obj" "$T/first_vt3.obj" --stats
check "f v beside f v/vt: written and read again, the same $once vertices" [ "$once $(stat vertices)" = "6 6" ]
check "f v beside f v/vt: OBJ to OBJ twice, the same file" cmp -s "$T/first_vt2.obj" "$T/first_vt3.obj"
# Draco's parser reads numbers with its own arithmetic, one float away from
# strtod's at times: 44082806 (the float 44082808) was written as 4.408281e+07,
# which Draco reads as 44082812 (fuzz_obj found it). Written as Draco reads.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 44082806\nf 1 2 3\n' >"$T/draco_float.obj"
"$VNC" "$T/draco_float.obj" "$T/draco_float2.obj" -q
"$VNC" "$T/draco_float2.obj" "$T/draco_float3.obj" -q
check "a float Draco reads otherwise than strtod: OBJ to OBJ twice, the same file" cmp -s "$T/draco_float2.obj" "$T/draco_float3.obj"
# An o line whose name is NUL bytes names nothing (it was written as 'o ',
# which reads back as no object).
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\no \0\0\0\nf 1 2 3\n' >"$T/nul_name.obj"
run "$VNC" "$T/nul_name.obj" "$T/nul_name2.obj"
check "o with a NUL name: no o line written" [ "$rc $(grep -c '^o' "$T/nul_name2.obj")" = "0 0" ]
# Names ending in a backslash (a blank or a NUL after it in the input)
# are written with a blank after them: a backslash at the end of a line
# carries it on to the next, which took the first v line into the mtllib
# one (found by fuzz_obj: 3 vertices read back of 4).
printf 'mtllib f\\\0x\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\ng grp\\ \nf 1 2 4 3\n' >"$T/backslash.obj"
run "$VNC" "$T/backslash.obj" "$T/backslash2.obj"
run "$VNC" "$T/backslash2.obj" "$T/backslash3.obj" --stats
check "names ending in a backslash: 4 vertices read back, the names kept" [ "$rc $(stat vertices) $(grep -E '^(mtllib|g) ' "$T/backslash3.obj" | tr '\n' ,)" = '0 4 mtllib f\ ,g grp\ ,' ]
# A NUL ends a name; the blanks before it are not part of it (found by
# fuzz_obj: 's grp ' was written, and read back as 'grp').
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\ns grp \0\0 x\ng a \0b\nf 1 2 3\n' >"$T/nul-name.obj"
run "$VNC" "$T/nul-name.obj" "$T/nul-name2.obj"
"$VNC" "$T/nul-name2.obj" "$T/nul-name3.obj" -q
check "a NUL ends a name, the blanks before it dropped" [ "$rc $(grep -E '^(s|g) ' "$T/nul-name2.obj" | tr '\n' ,)" = '0 g a,s grp,' ]
check "a NUL ends a name: a second OBJ -> OBJ changes no byte" cmp -s "$T/nul-name2.obj" "$T/nul-name3.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0.5 0.25\nvt 0.7 0.7\nf 1 2 3\nf 2/2 4/2 3/2\n' >"$T/mixed.obj"
run "$VNC" "$T/mixed.obj" "$T/mixed-out.obj"
check "f v beside f v/vt: as they were, one vt line" [ "$(grep -E '^(f|vt)' "$T/mixed-out.obj" | tr '\n' ,)" = "vt 0.7 0.7,f 1//1 2//1 3//1,f 2/1/1 4/1/1 3/1/1," ]
printf 'usemtl \nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\no \nv 2 2 0\nf 1 2 \\\r\n 4 3 \\\n\n\nf 1 2 5\nf 3 5\n' >"$T/joined.obj"
run "$VNC" "$T/joined.obj" "$T/joined-out.obj" --stats
check "continued face, empty usemtl and o: 5 vertices, 2 faces" [ "$rc $(stat vertices) $(stat faces)" = "0 5 2" ]
check "continued face: one quad" [ "$(grep '^f' "$T/joined-out.obj" | awk '{ printf "%d,", NF - 1 }')" = "4,3," ]
check "face of 2 corners: skipped, with its line" grep -q "joined.obj: 1 face (f) of fewer than 3 corners skipped (the first on line 13)" "$T/stderr"
# An `o` or `usemtl` after the last face names no face (found by fuzzing: the
# mesh carried names no face has, so GLB output warned of losing them and the
# OBJ read back from the output differed): no names at all.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\no late\nusemtl late\n' >"$T/late-o.obj"
run "$VNC" "$T/late-o.obj" "$T/late-o.glb"
check "o and usemtl after the last face: nothing to lose in GLB" [ "$rc:$err" = "0:" ]
"$VNC" "$T/late-o.obj" "$T/late-o-out.obj" -q
check "o and usemtl after the last face: not written" not grep -qE '^(o|usemtl) ' "$T/late-o-out.obj"
# OFF -> OBJ: loose vertices and vertex colours ("v x y z r g b").
printf 'COFF\n4 1 0\n0 0 0 1 0 0\n1 0 0 0 1 0\n0 1 0 0 0 1\n5 5 5 1 1 1\n3 0 1 2\n' >"$T/c.off"
"$VNC" "$T/c.off" "$T/c.obj" -q
check "OFF -> OBJ: colours and the loose vertex" [ "$(grep '^v ' "$T/c.obj" | tr '\n' ,)" = "v 0 0 0 1 0 0,v 1 0 0 0 1 0,v 0 1 0 0 0 1,v 5 5 5 1 1 1," ]
run "$VNC" "$T/c.obj" "$T/c2.off" -q
check "OBJ colours are read back (Draco 1.5.5 skips them), the loose vertex too" [ "$(head -2 "$T/c2.off" | tr '\n' ' ')$(tail -2 "$T/c2.off" | head -1)" = "CNOFF 4 1 0 5 5 5 0 0 0 255 255 255 255" ]
# v lines no face uses are vertices, as OFF's and PLY's are (they were
# dropped without a word): after the faces' vertices, in file order, with
# their colours; one equal to a used v line, or to another loose one, is a
# vertex of its own, as every v line is. Through OBJ, OFF and GLB (whose
# vertices a file from it writes once per position, as for any format but
# OBJ).
printf 'v 0 0 0 1 0 0\nv 9 9 9 0 1 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nv 0 0 0 1 0 0\nv 5 5 5 1 1 1\nv 9 9 9 0 1 0\nvt 0.5 0.5\nvn 0 0 1\nf 1/1/1 3/1/1 4/1/1\n' >"$T/loose.obj"
loose_v="v 0 0 0 1 0 0,v 1 0 0 0 1 0,v 0 1 0 0 0 1,v 9 9 9 0 1 0,v 5 5 5 1 1 1,"
run "$VNC" "$T/loose.obj" "$T/loose-out.obj" --stats
check "loose v lines: 7 vertices read" [ "$rc|$(stat vertices)" = "0|7" ]
check "loose v lines: OBJ -> OBJ keeps them, after the faces' vertices" [ "$(grep '^v ' "$T/loose-out.obj" | tr '\n' ,)" = "v 0 0 0 1 0 0,v 1 0 0 0 1 0,v 0 1 0 0 0 1,v 9 9 9 0 1 0,v 0 0 0 1 0 0,v 5 5 5 1 1 1,v 9 9 9 0 1 0," ]
check "loose v lines: no vt or vn line of their own" [ "$(grep -c '^v[tn] ' "$T/loose-out.obj")" = 2 ]
"$VNC" "$T/loose-out.obj" "$T/loose-out2.obj" -q
check "loose v lines: a second OBJ -> OBJ changes no byte" cmp -s "$T/loose-out.obj" "$T/loose-out2.obj"
"$VNC" "$T/loose.obj" "$T/loose.off" -q
check "loose v lines: OBJ -> OFF, zero normals (the weld gives one at a face vertex's position its normal), texture coordinates 0" [ "$(sed -n '2p;6,9p' "$T/loose.off" | tr '\n' ,)" = "7 1 0,9 9 9 0 0 0 0 255 0 255 0 0,0 0 0 0 0 1 255 0 0 255 0 0,5 5 5 0 0 0 255 255 255 255 0 0,9 9 9 0 0 0 0 255 0 255 0 0," ]
"$VNC" "$T/loose.obj" "$T/loose.glb" -q && "$VNC" "$T/loose.glb" "$T/loose-glb.obj" -q
check "loose v lines: OBJ -> GLB -> OBJ keeps them" [ "$(grep '^v ' "$T/loose-glb.obj" | tr '\n' ,)" = "$loose_v" ]
# OBJ colours have no alpha: vnconvert warns when one is not 1, and only then.
printf 'COFF\n3 1 0\n0 0 0 1 0 0 0.5\n1 0 0 0 1 0 1\n0 1 0 0 0 1 1\n3 0 1 2\n' >"$T/alpha.off"
run "$VNC" "$T/alpha.off" "$T/alpha.obj"
check "OFF -> OBJ, alpha 0.5: the warning names alpha" [ "$rc $err" = "0 vnconvert: warning: $T/alpha.obj cannot hold vertex colour alpha: not written" ]
check "OFF -> OBJ, alpha 0.5: r g b written" [ "$(grep '^v ' "$T/alpha.obj" | head -1)" = "v 0 0 0 1 0 0" ]
sed -i 's/ 0\.5$/ 1/' "$T/alpha.off"
run "$VNC" "$T/alpha.off" "$T/alpha.obj"
check "OFF -> OBJ, alpha 1: no warning" [ "$rc:$err" = "0:" ]

# mtllib: each relative name is written from the output's folder, so that it
# names the input's .mtl files wherever the output goes; absolute names stay,
# and an output beside its input (or a name without a folder: standard input
# or output) has the line as read, byte for byte.
L=$T/lib
mkdir -p "$L/A/sub" "$L/B"
touch "$L/A/m.mtl" "$L/A/sub/n.mtl"
face='v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n'
printf "mtllib m.mtl\n$face" >"$L/A/one.obj"
printf "mtllib m.mtl\tsub/n.mtl  /abs/x.mtl\n$face" >"$L/A/many.obj"
mtllib() { grep '^mtllib' "$1"; }
# found FOLDER FILE: every relative name FILE's mtllib line gives is a file from FOLDER.
found() { (cd "$1" && for n in $(mtllib "$2" | cut -c8-); do [ "${n#/}" != "$n" ] || [ -f "$n" ] || exit 1; done); }
"$VNC" "$L/A/one.obj" "$L/B/one.obj" -q
check "mtllib: A to B" [ "$(mtllib "$L/B/one.obj")" = "mtllib ../A/m.mtl" ]
check "mtllib: the .mtl is found from B" found "$L/B" one.obj
"$VNC" "$L/A/one.obj" "$L/A/same.obj" -q
check "mtllib: same folder, the line as read" [ "$(mtllib "$L/A/same.obj")" = "mtllib m.mtl" ]
"$VNC" "$L/A/many.obj" "$L/A/many-same.obj" -q
check "mtllib: same folder, several names, byte for byte" cmp -s <(mtllib "$L/A/many.obj") <(mtllib "$L/A/many-same.obj")
"$VNC" "$L/A/many.obj" "$L/B/many.obj" -q
check "mtllib: several names, each its path; absolute kept" \
  [ "$(mtllib "$L/B/many.obj")" = "$(printf 'mtllib ../A/m.mtl\t../A/sub/n.mtl  /abs/x.mtl')" ]
"$VNC" "$L/B/one.obj" "$L/A/back.obj" -q
check "mtllib: A to B and back, the line as read" [ "$(mtllib "$L/A/back.obj")" = "mtllib m.mtl" ]
mkdir -p "$L/B/deep"
"$VNC" "$L/B/one.obj" "$L/B/deep/one.obj" -q
check "mtllib: from B on deeper" [ "$(mtllib "$L/B/deep/one.obj")" = "mtllib ../../A/m.mtl" ]
(cd "$L" && "$VNC" --out-dir out A/one.obj A/many.obj -q)
check "mtllib: batch into an out-dir" [ "$(mtllib "$L/out/one.obj")" = "mtllib ../A/m.mtl" ]
check "mtllib: batch, the .mtl files are found" found "$L/out" many.obj
check "mtllib: batch, several names" [ "$(mtllib "$L/out/many.obj")" = "$(printf 'mtllib ../A/m.mtl\t../A/sub/n.mtl  /abs/x.mtl')" ]
"$VNC" - "$L/B/stdin.obj" --input-format obj -q <"$L/A/one.obj"
check "mtllib: from standard input, as read" [ "$(mtllib "$L/B/stdin.obj")" = "mtllib m.mtl" ]
check "mtllib: to standard output, as read" [ "$("$VNC" "$L/A/one.obj" - --format obj -q | mtllib -)" = "mtllib m.mtl" ]

# Invalid files: one line naming the file, exit 1, no output.
check_rejected "$VNC" "$DATA/inf_nan.obj" "$T/none.obj" "$T/keep.obj"
check "inf_nan: names line and number" grep -q "inf_nan.obj:1: vertex 1 has the number 'inf', which is not finite" "$T/stderr"
# Lines (l), which Draco skips, are read by vn: OBJ -> OBJ keeps every one,
# its points' positions, after the faces; other formats name them as not
# written. A file of lines only (Draco's test_lines.obj, a wireframe) was
# refused: now a point cloud with its lines.
run "$VNC" "$DATA/test_lines.obj" "$T/lines.obj"
objcheck lines "$DATA/test_lines.obj" >"$T/lines-in"
objcheck lines "$T/lines.obj" >"$T/lines-out"
check "lines only: OBJ -> OBJ keeps the 242 lines and their points" [ "$rc|$(wc -l <"$T/lines-out")" = "0|242" ]
check "lines only: the same points" cmp -s "$T/lines-in" "$T/lines-out"
"$VNC" "$T/lines.obj" "$T/lines2.obj" -q
check "lines only: a second OBJ -> OBJ changes no byte" cmp -s "$T/lines.obj" "$T/lines2.obj"
run "$VNC" "$DATA/test_lines.obj" "$T/lines.ply"
check "lines only: PLY names them as not written" grep -qF "lines.ply cannot hold lines: not written" <<<"$err"
# A line of 1 point, or with a point that is no v line (out of range, not
# a number), is skipped with a warning, not refused: vn read such files
# before it read lines. A point's vt and vn are not kept.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nf 1 2 3\nl 1/1 4\nl -1 -3/9/2 -2\nl 2\nl 1 5\nl 1 2x\np 4\n' >"$T/mixed-lines.obj"
run "$VNC" "$T/mixed-lines.obj" "$T/mixed-lines-out.obj"
check "lines beside faces: after them, by v number (counted back read as such)" [ "$rc|$(grep -E '^[fl] ' "$T/mixed-lines-out.obj" | tr '\n' ,)" = "0|f 1//1 2//1 3//1,l 1 4,l 4 2 3," ]
check "lines beside faces: 3 lines skipped, points left out, both said" [ "$(echo "$err" | grep -cE "3 lines \(l\) skipped: fewer than 2 points, or a point that is not a v line the file has \(the first on line 9\)|left out .*: 1 'p' line \(points\)")" = 2 ]
# Point clouds (no faces, no lines): a vertex a v line, with as many vt and
# vn lines; written as OFF, PLY and OBJ (a line of each a vertex, in order).
grep '^v ' "$DATA/point_cloud_test_pos.obj" >"$T/points.obj"
run "$VNC" "$T/points.obj" "$T/points.off"
check "point cloud to OFF: exit 0" [ $rc -eq 0 ]
check "point cloud to OFF: the 4 vertices, no faces" [ "$(sed -n 2p "$T/points.off")" = "4 0 0" ]
check "point cloud to OFF: positions as the file has them" [ "$(sed -n 3p "$T/points.off" | cut -d' ' -f1-3)" = "38.638046 19.293715 1.344739" ]
# Coordinates are read as the doubles they spell, not as Draco's floats:
# a georeferenced (UTM) mesh kept its metres only to 0.25 (4123456.11 was
# 4123456). Equal v lines still make one vertex; two that only a float
# would confuse stay two.
printf 'v 637012.24 4123456.11 12.34\nv 637013.24 4123456.11 12.34\nv 637012.24 4123457.11 12.34\nv 637012.26 4123457.11 12.34\nvn 0 0 1\nf 1//1 2//1 3//1\nf 3//1 2//1 4//1\n' >"$T/utm.obj"
run "$VNC" "$T/utm.obj" "$T/utm_out.obj"
check "UTM coordinates: OBJ to OBJ keeps every digit" [ "$(grep '^v ' "$T/utm_out.obj" | tr '\n' '|')" = "v 637012.24 4123456.11 12.34|v 637013.24 4123456.11 12.34|v 637012.24 4123457.11 12.34|v 637012.26 4123457.11 12.34|" ]
run "$VNC" "$T/utm.obj" "$T/utm.ply" -q
check "UTM coordinates: to PLY as doubles, 4 vertices" [ "$(/usr/bin/python3 "$HERE/plytool.py" column "$T/utm.ply" y 0) $(/usr/bin/python3 "$HERE/plytool.py" count "$T/utm.ply")" = "4123456.11 4 2 2" ]
# A float is written in the fewest digits that Draco's reader and a
# correctly rounding one (Blender's, MeshLab's, strtof) both read back as
# it: 237666192 was "2.376662e+08", which Draco's arithmetic reads as it
# and every other reader as 237666208, the float above.
printf 'OFF\n3 1 0\n237666192 0 0\n0 1 0\n0 0 1\n3 0 1 2\n' >"$T/far.off"
run "$VNC" "$T/far.off" "$T/far.obj" -q
check "a float far from 1 to OBJ: its text reads back as it" \
  [ "$(head -1 "$T/far.obj")|$(python3 -c 'import struct, sys; print(struct.unpack("f", struct.pack("f", float(sys.argv[1])))[0])' "$(head -1 "$T/far.obj" | cut -d' ' -f2)")" = "v 2.3766619e+08 0 0|237666192.0" ]
# --crease-angle splits a cube's corners (16 copies); a copy keeps its v
# line (vn_io_mesh.position_lines grows with the split), so OBJ output still
# has the file's 8 v lines, and each face its normal.
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n' >"$T/crease.obj"
run "$VNC" "$T/crease.obj" "$T/crease-out.obj" --crease-angle 30 --stats
check "OBJ --crease-angle: 16 split, 8 v lines, 6 vn lines" \
  [ "$rc|$(stat 'split vertices')|$(grep -c '^v ' "$T/crease-out.obj")|$(grep -c '^vn ' "$T/crease-out.obj")" = "0|16|8|6" ]
check "OBJ --crease-angle: each face on the file's v lines" \
  [ "$(grep '^f' "$T/crease-out.obj" | sed 's|//[0-9]*||g' | tr '\n' ,)" = "f 1 2 3 4,f 5 6 7 8,f 1 4 6 5,f 4 3 7 6,f 3 2 8 7,f 2 1 5 8," ]
# Equal v lines are two vertices, as Blender, MeshLab and Assimp read them
# (vn merged them): OBJ -> OFF keeps both, OBJ -> OBJ writes both, and
# --no-weld computes on them apart (a fold along a split edge), where the
# default weld gives them one normal.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\nv 1 0 0\nf 1 2 3\nf 5 4 3\n' >"$T/twice.obj"
run "$VNC" "$T/twice.obj" "$T/twice.off" -q
check "equal v lines: two vertices" [ "$(sed -n 2p "$T/twice.off")" = "5 2 0" ]
check "equal v lines: welded, one normal" [ "$(sed -n 4p "$T/twice.off" | cut -d' ' -f4-)" = "$(sed -n 6p "$T/twice.off" | cut -d' ' -f4-)" ]
run "$VNC" "$T/twice.obj" "$T/twice-apart.off" -q --no-weld
check "equal v lines, --no-weld: each its face's normal" \
  [ "$(sed -n '4p;6p' "$T/twice-apart.off" | cut -d' ' -f4- | tr '\n' ,)" = "0 0 1,-0.577350269 -0.577350269 0.577350269," ]
run "$VNC" "$T/twice.obj" "$T/twice-out.obj" -q
check "equal v lines: OBJ -> OBJ writes both" [ "$(grep -c '^v ' "$T/twice-out.obj")|$(grep '^f' "$T/twice-out.obj" | tr '\n' ,)" = "5|f 1//1 2//2 3//3,f 4//2 5//4 3//3," ]
run "$VNC" "$T/points.obj" "$T/points_out.obj"
vlines() { awk '/^v / { printf "%.6f %.6f %.6f\n", $2, $3, $4 }' "$1"; }
check "point cloud to OBJ: its v lines, the same numbers" [ "$(vlines "$T/points_out.obj")" = "$(vlines "$T/points.obj")" ]
check "point cloud to OBJ: no vn lines (no normals in the input)" not grep -q '^vn' "$T/points_out.obj"
check "point cloud to OBJ: no faces" not grep -q '^f' "$T/points_out.obj"
printf 'v 0 0 0\nv 1 0 0\nv 1 0 0\nvt 0.5 0.25\nvt 1 1\nvt 0 0\nvn 0 0 1\nvn 0 1 0\nvn 1 0 0\n' >"$T/scan.obj"
run "$VNC" "$T/scan.obj" "$T/scan_out.obj"
check "point cloud with vt and vn to OBJ: every line, in order (two points at one place too)" [ "$(cat "$T/scan_out.obj")" = "$(printf 'v 0 0 0\nv 1 0 0\nv 1 0 0\nvt 0.5 0.25\nvt 1 1\nvt 0 0\nvn 0 0 1\nvn 0 1 0\nvn 1 0 0')" ]
check "point cloud with vn: the input's normals kept, said so" grep -q "scan.obj has no faces (a point cloud): vn computes no normals; the input's are kept$" "$T/stderr"
run "$VNC" "$T/scan_out.obj" "$T/scan_again.obj"
check "point cloud OBJ to OBJ again: the same bytes" cmp -s "$T/scan_out.obj" "$T/scan_again.obj"
run "$VNC" "$T/scan.obj" "$T/scan.off"
check "point cloud with vt and vn to OFF" [ "$(sed -n 3,5p "$T/scan.off" | tr '\n' '|')" = "0 0 0 0 0 1 0.5 0.25|1 0 0 0 1 0 1 1|1 0 0 1 0 0 0 0|" ]
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\n' >"$T/onevn.obj"
check_rejected "$VNC" "$T/onevn.obj" "$T/none.off" "$T/keep.off"
check "point cloud with fewer vn lines than v lines: says so" grep -q "onevn.obj: a point cloud (no faces) of 3 v lines and 1 vn lines: without faces, vn (and Draco) read one vn line for each v line" "$T/stderr"
refused() { printf "$2" >"$T/$1.obj"; check_rejected "$VNC" "$T/$1.obj" "$T/none.obj" "$T/keep.obj"; check "$1: $3" grep -qF "$3" "$T/stderr"; }
tri='v 0 0 0\nv 1 0 0\nv 0 1 0\n'
refused range "${tri}f 1 2 9\n" "range.obj:4: face corner 3 refers to vertex 9, but the file has 3 vertices (v)"
refused back "${tri}f -1 -2 -4\n" "back.obj:4: face corner 3 refers to vertex -4 (counting back), but only 3 vertices (v) come before it"
refused pastex "${tri}vt 0 0\nf 1/1 2/1 3/2\n" "pastex.obj:5: face corner 3 refers to texture coordinate 2, but the file has 1 texture coordinates (vt)"
refused zero "${tri}f 0 1 2\n" "zero.obj:4: face corner 1, '0', is not v, v/vt, v/vt/vn or v//vn"
refused huge "${tri}f 1 2 4294967295\n" "huge.obj:4: face corner 3, '4294967295', is not"
refused short 'v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' "short.obj:1: vertex 1 has 2 numbers; it needs 3"
refused word 'v 0 0 x\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' "word.obj:1: vertex 1: 'x' is not a number"
refused big "${tri}vn 0 0 1e40\nf 1//1 2//1 3//1\n" "big.obj:4: normal 1 has the number '1e40', which is not finite"
# Draco's float of this exponent is finite, the double is not (found by
# fuzz_obj: the point cloud was read, then written as 'inf').
refused overflow 'v 0 0 0\nv 1e3914896774291992 0 1\n' "overflow.obj:2: vertex 2 has the number '1e3914896774291992', which is not finite"
refused glued "${tri}f 1 2 3/1/2-4\n" "glued.obj:4: face corner 3, '3/1/2-4', is not v, v/vt, v/vt/vn or v//vn"
# Indices of vt or vn lines in a file that has none of them (an exporter
# wrote the indices but not the lines, as trimesh's test models cubevt.obj
# and face_in_group_name_mid_file.obj have them): read without them, with a
# warning (they were refused; Blender 3.4 reads the second, and the first
# without its faces). A decagon among them, which Draco gets split.
printf '%s\n' "v 1 0 0" "v 0.809 0.588 0" "v 0.309 0.951 0" "v -0.309 0.951 0" "v -0.809 0.588 0" "v -1 0 0" \
  "v -0.809 -0.588 0" "v -0.309 -0.951 0" "v 0.309 -0.951 0" "v 0.809 -0.588 0" "v 0 0 1" \
  "f 1/1/1 2/2/2 3/3/3 4/4/4 5/5/5 6/6/6 7/7/7 8/8/8 9/9/9 10/10/10" "f 1//1 2//2 11//3" "f -1/-1 -2/-2 -3/-3" >"$T/dangling.obj"
run "$VNC" "$T/dangling.obj" "$T/dangling_out.obj"
check "vt and vn lines referred to but absent: read, each named once" [ "$rc|$err" = "0|vnconvert: warning: $T/dangling.obj: 13 face corners refer to texture coordinates (vt), but the file has none: read without them (the first on line 12)
vnconvert: warning: $T/dangling.obj: 13 face corners refer to normals (vn), but the file has none: read without them (the first on line 12)" ]
check "vt and vn lines absent: the decagon and two triangles, without vt" \
  [ "$(grep '^f' "$T/dangling_out.obj" | sed 's|//[0-9]*||g' | tr '\n' '|')" = "f 1 2 3 4 5 6 7 8 9 10|f 1 2 11|f 11 10 9|" ]
check "vt and vn lines absent: no vt lines written" not grep -q '^vt' "$T/dangling_out.obj"
# Draco stops reading a number at the first character not part of it: these
# read as 3, 0, 1.5 and 3.1 (and a triangle 1 2 3) where they are refused.
refused comma 'v 0 0 0\nv 1 0 0\nv 0 1 3,5\nf 1 2 3\n' "comma.obj:3: vertex 3: '3,5' is not a number"
refused hex 'v 0 0 0\nv 0x10 0 0\nv 0 1 0\nf 1 2 3\n' "hex.obj:2: vertex 2: '0x10' is not a number"
refused dots "${tri}vt 1.5.2 0\nf 1/1 2/1 3/1\n" "dots.obj:4: texture coordinate 1: '1.5.2' is not a number"
refused plus_e "v 0 0 3.1+e2\nv 1 0 0\nv 0 1 0\nf 1 2 3\n" "plus_e.obj:1: vertex 1: '3.1+e2' is not a number"
refused tail "${tri}f 1 2 3x4\n" "tail.obj:4: face corner 3, '3x4', is not v, v/vt, v/vt/vn or v//vn"
refused no_uv "${tri}vt\nf 1/1 2/1 3/1\n" "no_uv.obj:4: texture coordinate 1 has 0 numbers; it needs 1"
# vt u [v [w]]: a vt of one number has v = 0 (it was refused: "has 1
# numbers; it needs 2"), also before a comment and among faces Draco takes
# split (a decagon).
printf '%s\n' "v 1 0 0" "v 0.809 0.588 0" "v 0.309 0.951 0" "v -0.309 0.951 0" "v -0.809 0.588 0" "v -1 0 0" \
  "v -0.809 -0.588 0" "v -0.309 -0.951 0" "v 0.309 -0.951 0" "v 0.809 -0.588 0" "vt 0.1" \
  "f 1/1 2/1 3/1 4/1 5/1 6/1 7/1 8/1 9/1 10/1" "vt 0.2 # a comment" "vt 0.3 0.4" "v 0 0 1" "f 1/2 2/3 11/2" >"$T/u.obj"
run "$VNC" "$T/u.obj" "$T/u-out.obj"
check "vt of one number: exits 0" [ $rc -eq 0 ]
check "vt of one number: v is 0" [ "$(grep '^vt' "$T/u-out.obj" | tr '\n' ' ')" = "vt 0.1 0 vt 0.2 0 vt 0.3 0.4 " ]
check "vt of one number: the decagon and the triangle" \
  [ "$(grep '^f' "$T/u-out.obj" | awk '{print NF - 1}' | tr '\n' ' ')" = "10 3 " ]
refused empty "" "empty.obj: the file is empty"
# An OBJ without geometry (comments, a material library) is an
# empty mesh, as an OFF of 0 vertices is (it was refused: "not an OBJ
# mesh"); an empty mesh without comments is written as an OBJ of one
# comment, which reads back.
printf '# exported with nothing selected\nmtllib scene.mtl\n' >"$T/nogeometry.obj"
run "$VNC" "$T/nogeometry.obj" "$T/nogeometry.off"
check "no geometry: an empty OFF with the file's comment, and a warning" \
  [ "$rc|$(tr '\n' '|' <"$T/nogeometry.off")|$err" = "0|OFF|# exported with nothing selected|0 0 0||vnconvert: warning: $T/nogeometry.obj has no vertices and no faces: $T/nogeometry.off is written empty" ]
printf 'OFF\n0 0 0\n' >"$T/nothing.off"
run "$VNC" "$T/nothing.off" "$T/empty-out.obj" -q
check "an empty mesh to OBJ: one comment" [ "$rc|$(cat "$T/empty-out.obj")" = "0|# no vertices and no faces" ]
run "$VNC" "$T/nogeometry.obj" "$T/nogeometry-out.obj" -q
check "no geometry, OBJ to OBJ: the comment and the mtllib line kept" [ "$rc|$(cat "$T/nogeometry-out.obj" | tr '\n' '|')" = "0|# exported with nothing selected|mtllib scene.mtl|" ]
run "$VNC" "$T/empty-out.obj" "$T/empty-back.off" -q
check "an empty OBJ read back" [ "$rc|$(grep -v '^#' "$T/empty-back.off" | sed -n 2p)" = "0|0 0 0" ]
# The comments at the top of an OBJ (exporters' credits, a model's licence)
# are kept, as read, in OBJ, OFF (after the keyword) and PLY output (they
# were dropped); comments after the first other line are not.
printf '# Made by X\r\n#\tlicence CC-BY 4.0\n\n#\nv 0 0 0\nv 1 0 0\nv 0 1 0\n# 3 vertices\nf 1 2 3\n' >"$T/credits.obj"
run "$VNC" "$T/credits.obj" "$T/credits-out.obj"
check "comments at the top: OBJ -> OBJ keeps them, as read" \
  [ "$rc|$(head -3 "$T/credits-out.obj" | tr '\n' '|')|$(grep -c '^#' "$T/credits-out.obj")" = "0|# Made by X|#$(printf '\t')licence CC-BY 4.0|#||3" ]
run "$VNC" "$T/credits-out.obj" "$T/credits-out2.obj"
check "comments at the top: a second OBJ -> OBJ changes no byte" cmp -s "$T/credits-out.obj" "$T/credits-out2.obj"
run "$VNC" "$T/credits.obj" "$T/credits.off"
check "comments at the top: OBJ -> OFF, after the keyword" \
  [ "$(head -5 "$T/credits.off" | tr '\n' '|')" = "NOFF|# Made by X|#$(printf '\t')licence CC-BY 4.0|#|3 1 0|" ]
run "$VNC" "$T/credits.off" "$T/credits-back.obj"
check "comments at the top: OBJ -> OFF -> OBJ keeps them" cmp -s "$T/credits-out.obj" "$T/credits-back.obj"
run "$VNC" "$T/credits.obj" "$T/credits.ply"
check "comments at the top: OBJ -> PLY, comment lines" \
  [ "$(head -c 300 "$T/credits.ply" | grep -a '^comment' | tr '\n' '|')" = "comment written by vn|comment Made by X|comment$(printf '\t')licence CC-BY 4.0|comment |" ]
# Lines OBJ does not define and none it does: another format under .obj
# (pyvista's mni-surface-mesh.obj, an MNI surface), refused; it was written
# as an empty mesh with a warning, as if read.
refused mni '# made by hand\nP 0.3 0.3 0.4 10 1 3\n 0 0 0 1 0 0 0 1 0\n' "mni.obj: not a Wavefront OBJ file: no v, vt, vn or f line, and line 2 starts with 'P', which OBJ does not define (an MNI surface .obj starts so: another format)"
# UTF-16 and UTF-32 text (Windows PowerShell's '>' writes UTF-16LE; assimp's
# box_UTF16BE.obj) is read as its UTF-8, names keeping their letters; it was
# refused. So is a .mtl, and one in UTF-8 with a byte order mark is read past
# it (its first line, newmtl, was not read: the material lost its colour).
printf 'mtllib wide.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\no caf\303\251\nusemtl r\303\251d\nf 1 2 3\n' >"$T/u8.obj"
printf 'newmtl r\303\251d\nKd 1 0 0\n' >"$T/u8.mtl"
wide() { { printf "$1"; iconv -f UTF-8 -t "$2" "$3"; } >"$4"; }
wide '\377\376' UTF-16LE "$T/u8.mtl" "$T/wide.mtl"
run "$VNC" "$T/u8.obj" "$T/u8-out.obj" -q
for e in 'UTF-16LE \377\376' 'UTF-16BE \376\377' 'UTF-32LE \377\376\000\000' 'UTF-32BE \000\000\376\377'; do
  wide "${e#* }" "${e% *}" "$T/u8.obj" "$T/wide.obj"
  run "$VNC" "$T/wide.obj" "$T/wide-out.obj" -q
  check "${e% *} OBJ: read as its UTF-8" [ "$rc|$(cat "$T/wide-out.obj")" = "0|$(cat "$T/u8-out.obj")" ]
done
check "UTF-16 OBJ: the name's letters" grep -q "^o caf$(printf '\303\251')\$" "$T/wide-out.obj"
run "$VNC" "$T/wide.obj" "$T/wide.glb" -q
check "UTF-16 .mtl: the material's colour" grep -qaF '"baseColorFactor":[1.0,0.0,0.0,1.0]' "$T/wide.glb"
{ printf '\357\273\277'; cat "$T/u8.mtl"; } >"$T/wide.mtl"
run "$VNC" "$T/u8.obj" "$T/bom-mtl.glb"
check "UTF-8 .mtl with a byte order mark: the colour, no warning" \
  [ "$rc|$err|$(grep -caF '"baseColorFactor":[1.0,0.0,0.0,1.0]' "$T/bom-mtl.glb")" = "0|vnconvert: warning: $T/bom-mtl.glb cannot hold object names: not written|1" ]
refused lone '\377\376v\000\n\000\000\330v\000' "lone.obj:2: the text is UTF-16LE (it starts with a byte order mark), but a high surrogate without its low one"
refused odd '\377\376v\000 ' "odd.obj:1: the text is UTF-16LE (it starts with a byte order mark), but its last code unit is cut short"
# A UTF-8 byte order mark (Windows editors write one) is read past: before,
# the first v line was skipped and every index moved by one.
printf '\357\273\277v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4\n' >"$T/bom.obj"
run "$VNC" "$T/bom.obj" "$T/bom-out.obj"
check "UTF-8 byte order mark: the first vertex read" [ "$rc $(grep -c '^v ' "$T/bom-out.obj") $(head -1 "$T/bom-out.obj")" = "0 4 v 0 0 0" ]
# What vn does not read is named in one warning (it was dropped without a
# word): points, colours on only some v lines.
printf '%s\n' "o x" "g grp" "s 1" "v 0 0 0 1 0 0" "v 1 0 0 1 0 0" "v 0 1 0" "f 1 2 3" "p 1" "s off" "g g2" "# c" >"$T/left.obj"
run "$VNC" "$T/left.obj" "$T/left-out.obj"
check "left out: exits 0" [ $rc -eq 0 ]
check "left out: one warning names them" [ "$err" = "vnconvert: warning: $T/left.obj: left out (vn reads v, vt, vn, f, l, o, g, s, usemtl and mtllib): 1 'p' line (points), numbers after x y z on 2 'v' lines (w, or colours not on every v line or not in [0, 1])" ]
# Texture coordinates' w where it is not 0 (3D textures), and vt lines no
# face uses (counted back with negative indices), are named there too; a w
# of 0, which exporters write, is not.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0 0\nvt 1 0 0.0\nvt 0 1 0.5\nvt 0.3 0.3 0.5\nvt 0.4 0.4\nf 1/-5 2/-4 3/-3\n' >"$T/left-vt.obj"
run "$VNC" "$T/left-vt.obj" "$T/left-vt-out.obj"
check "left out: vt's w, vt lines no face uses" [ "$rc|$err" = "0|vnconvert: warning: $T/left-vt.obj: left out (vn reads v, vt, vn, f, l, o, g, s, usemtl and mtllib): numbers after u v on 2 'vt' lines (w, not 0), 2 'vt' lines no face uses" ]
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nf 1 2 3\n' >"$T/left-vt2.obj"
run "$VNC" "$T/left-vt2.obj" "$T/left-vt2-out.obj"
check "left out: vt lines of a file whose faces use none" [ "$(echo "$err" | grep -c ": 2 'vt' lines no face uses$")" = 1 ]
# Groups (g) and smoothing groups (s), which Draco skips, are read by vn's
# scan: OBJ to OBJ writes each where it changes, as written (a bare g, the
# default group; two names; "s off"), and a format without them names them
# as not written. A g or s line after the last face sets nothing.
printf '%s\n' "g default" "v 0 0 0" "v 1 0 0" "v 0 1 0" "v 1 1 0" "v 2 1 0" "s 1" "g body  arm" "usemtl m" \
  "f 1 2 3" "s 1" "f 2 4 3" "s off" "f 2 5 4" "g" "s 2" "f 3 4 5" "g late" "s 3" >"$T/groups.obj"
run "$VNC" "$T/groups.obj" "$T/groups-out.obj"
check "groups: OBJ to OBJ, no warning" [ "$rc|$err" = "0|" ]
check "groups: written where they change" [ "$(grep -vE '^(v|vn) ' "$T/groups-out.obj" | tr '\n' '|')" = \
  "g body  arm|usemtl m|s 1|f 1//1 2//1 3//1|f 2//1 4//1 3//1|s off|f 2//1 5//1 4//1|g|s 2|f 3//1 4//1 5//1|" ]
check "groups: each face's, as an independent reader sees them" \
  [ "$(objcheck faces "$T/groups-out.obj" | cut -d'|' -f1-4 | tr '\n' ,)" = "-|body arm|1|m,-|body arm|1|m,-|body arm|off|m,-||2|m," ]
run "$VNC" "$T/groups.obj" "$T/groups.ply"
check "groups: to PLY, named as not written" \
  [ "$rc|$err" = "0|vnconvert: warning: $T/groups.ply cannot hold materials, groups, smoothing groups: not written" ]
# Colours on every v line (MeshLab's and Open3D's "v x y z r g b") are read,
# and kept: OBJ to OBJ, to PLY, a point cloud to GLB as COLOR_0. Two v lines
# at one place with other colours stay two vertices.
printf 'v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nv 1 1 0 0.5 0.25 0.125\nv 1 0 0 0.5 0.5 0.5\nf 1 2 3\nf 5 4 3\n' >"$T/rgb.obj"
run "$VNC" "$T/rgb.obj" "$T/rgb-out.obj"
check "v colours: no warning" [ "$rc $err" = "0 " ]
check "v colours: OBJ to OBJ keeps them, 5 vertices" [ "$(grep '^v ' "$T/rgb-out.obj" | tr '\n' '|')" = "v 0 0 0 1 0 0|v 1 0 0 0 1 0|v 0 1 0 0 0 1|v 1 0 0 0.5 0.5 0.5|v 1 1 0 0.5 0.25 0.125|" ]
run "$VNC" "$T/rgb.obj" "$T/rgb.ply" -q
check "v colours: to PLY as float colours" [ "$(/usr/bin/python3 "$HERE/plytool.py" column "$T/rgb.ply" green 4)" = 0.25 ]
grep -v '^f' "$T/rgb.obj" >"$T/rgbcloud.obj"
run "$VNC" "$T/rgbcloud.obj" "$T/rgbcloud.glb" -q
check "v colours: a point cloud to GLB has COLOR_0" [ "$(q "$T/rgbcloud.glb" "sorted(d['meshes'][0]['primitives'][0]['attributes'])")" = "['COLOR_0', 'POSITION']" ]
# Colours that are bytes printed with 6 decimals (MeshLab's "%f" of 209 /
# 255 and 122 / 255) are written as the bytes where a format has them (PLY
# uchar: MeshLab reads float PLY colours as white, Open3D divides them by
# 255 again; glTF unsigned byte), and OBJ to OBJ keeps their text.
printf 'v 0 0 0 0.819608 0.000000 0.478431\nv 1 0 0 1.000000 1.000000 1.000000\nv 0 1 0 0.000000 0.000000 1.000000\nf 1 2 3\n' >"$T/bytes.obj"
run "$VNC" "$T/bytes.obj" "$T/bytes.ply" -q
check "byte colours: to PLY as uchar" [ "$(grep -a '^property .* red' "$T/bytes.ply") $(/usr/bin/python3 "$HERE/plytool.py" column "$T/bytes.ply" red 0) $(/usr/bin/python3 "$HERE/plytool.py" column "$T/bytes.ply" blue 0)" = "property uchar red 209.0 122.0" ]
run "$VNC" "$T/bytes.obj" "$T/bytes.glb" -q
check "byte colours: to GLB as normalized unsigned bytes" [ "$(q "$T/bytes.glb" "[d['accessors'][d['meshes'][0]['primitives'][0]['attributes']['COLOR_0']][k] for k in ('componentType', 'normalized')]")" = "[5121, True]" ]
run "$VNC" "$T/bytes.obj" "$T/bytes-out.obj" -q
check "byte colours: OBJ to OBJ keeps the text" [ "$(grep '^v ' "$T/bytes-out.obj" | head -1)" = "v 0 0 0 0.819608 0 0.478431" ]
run "$VNC" "$T/bytes.obj" "$T/bytes-again.obj"
check "left out: none, no warning" [ -z "$err" ]

# Materials to glTF (mtl.c): a primitive per material, each with the .mtl
# file's Kd, d, Ns (as roughness) and map_Kd (the image's bytes in the
# file). Blender 3.4's own OBJ import and glTF export of the same files
# (make_textured.py, blender-grid.glb) is the independent conversion: every
# material, factor, image and triangle set the same (gltfcheck.py materials).
TEX=$DATA/textured
gcheck() { python3 "$HERE/gltf/gltfcheck.py" "$@"; }
# valid FILE [CODE]: no error, and no warning but CODE.
valid() {
  python3 -c 'import json, sys; r = json.loads(sys.stdin.read()); sys.exit(bool(r["errors"] or set(r["warnings"]) - set(sys.argv[1:])))' \
    ${2:+"$2"} < <(node "$HERE/gltf/validate.mjs" "$MODULES" "$1")
}
for ext in glb gltf; do
  run "$VNC" "$TEX/grid.obj" "$T/grid.$ext"
  check "textured grid to $ext: only the object name is lost" [ "$rc:$err" = "0:vnconvert: warning: $T/grid.$ext cannot hold object names: not written" ]
  check "textured grid to $ext: Blender's materials, images and triangles" \
    cmp -s <(gcheck materials "$TEX/blender-grid.glb") <(gcheck materials "$T/grid.$ext")
  # The normal map comes without TANGENT, as in Blender's (the validator's
  # MESH_PRIMITIVE_GENERATED_TANGENT_SPACE): nothing Blender's has not.
  check "textured grid to $ext: the Khronos validator finds nothing Blender's GLB has not" \
    quietly node "$HERE/gltf/validate.mjs" "$MODULES" "$TEX/blender-grid.glb" "$T/grid.$ext"
done
check "textured grid: the PNG's and the JPEG's bytes" [ "$(gcheck materials "$T/grid.glb" | cut -d'|' -f6 | tr '\n' ,)" = \
  " image - , image image/jpeg $(sha1sum <"$TEX/tex/checker.jpg" | cut -c1-40) , image image/png $(sha1sum <"$TEX/tex/checker.png" | cut -c1-40) ," ]
check "textured grid: Glass by hand (Kd 0.2 0.4 0.6, d 0.5, Ns 250, Ke 0.1 0.2 0.3)" [ "$(q "$T/grid.glb" "d['materials'][2]")" = \
  "{'name': 'Glass', 'pbrMetallicRoughness': {'metallicFactor': 0.0, 'baseColorFactor': [0.2, 0.4, 0.6, 0.5], 'roughnessFactor': 0.5}, 'alphaMode': 'BLEND', 'emissiveFactor': [0.1, 0.2, 0.3]}" ]
check "textured grid: Jpeg's normal map by hand (-bm 0.5)" [ "$(q "$T/grid.glb" "(d['materials'][1]['normalTexture'], d['textures'][d['materials'][1]['normalTexture']['index']])")" = \
  "({'index': 2, 'scale': 0.5}, {'source': 2})" ]
run "$VNC" "$DATA/blender_cube.obj" "$T/cube-m.glb" -q
check "cube to GLB: Blue and Red as Blender has them" [ "$(q "$T/cube-m.glb" "[(m['name'], m['pbrMetallicRoughness']['baseColorFactor'], round(m['pbrMetallicRoughness']['roughnessFactor'], 9)) for m in d['materials']]")" = "[('Blue', [0.0, 0.0, 1.0, 1.0], 0.4), ('Red', [1.0, 0.0, 0.0, 1.0], 0.4)]" ]
check "cube to GLB: 4 Blue faces, 2 Red" [ "$(q "$T/cube-m.glb" "[(p['material'], d['accessors'][p['indices']]['count']) for p in d['meshes'][0]['primitives']]")" = "[(0, 24), (1, 12)]" ]
# By hand: a library whose name has a blank, in another folder than the
# texture; Kd of one value; d -halo; norm (a normal map) with -bm; Tr (not
# read: MeshLab writes "Tr 1" for opaque, others mean clear); map_Ke (its
# factor 1, not Ke); Pr and Pm over Ns; map_Kd with options and a Windows
# path, its Kd 0.8 not applied (as Blender and obj2gltf read it); a TGA; a
# material it does not define; faces before any usemtl (a primitive
# without material).
M=$T/lib
mkdir -p "$M/textures"
cp "$TEX/tex/checker.png" "$M/textures/a.png"
printf 'TRUEVISION' >"$M/textures/b.tga"
printf '%s\n' "# made by hand" "newmtl Grey" "Kd 0.5" "d -halo 0.25" "norm -bm 2 textures/a.png" "newmtl Clear" "Kd 1 0.5 0" "Tr 0.75" "Ke 0.3" "map_Ke -bm 2 textures/a.png" \
  "newmtl Metal" "Ns 1000" "Pr 0.3" "Pm 1" "Kd 0.8 0.8 0.8" "map_Kd -s 2 2 1 -clamp on textures\\a.png" "newmtl Tga" "map_Kd textures/b.tga" \
  "newmtl Unused" "Kd 0 0 0" >"$M/my lib.mtl"
printf '%s\n' "mtllib my lib.mtl" "v 0 0 0" "v 1 0 0" "v 0 1 0" "v 1 1 0" "vt 0 0" "vt 1 0" "vt 0 1" "vt 1 1" \
  "f 1/1 2/2 3/3" "usemtl Grey" "f 2/2 4/4 3/3" "usemtl Clear" "f 1/1 3/3 4/4" "usemtl Metal" "f 1/1 2/2 4/4" \
  "usemtl Tga" "f 4/4 2/2 1/1" "usemtl Nowhere" "f 3/3 2/2 1/1" >"$M/hand.obj"
run "$VNC" "$M/hand.obj" "$T/hand.glb"
check "by hand: exits 0" [ $rc -eq 0 ]
check "by hand: the options, the TGA and the undefined material named" [ "$err" = "vnconvert: warning: $M/hand.obj: my lib.mtl: material Clear: map_Ke's options (-bm 2) are not carried: its texture is used as it is
vnconvert: warning: $M/hand.obj: my lib.mtl: material Metal: map_Kd's options (-s 2 2 1 -clamp on) are not carried: its texture is used as it is
vnconvert: warning: $M/hand.obj: my lib.mtl: material Tga: texture textures/b.tga is neither PNG nor JPEG, the images glTF holds: written without it
vnconvert: warning: $M/hand.obj: the material library defines no Nowhere: written by name only" ]
check "by hand: a primitive without material, then one a material" [ "$(q "$T/hand.glb" "[p.get('material') for p in d['meshes'][0]['primitives']]")" = "[None, 0, 1, 2, 3, 4]" ]
check "by hand: every material's factors and maps" [ "$(q "$T/hand.glb" "[(m['name'], m['pbrMetallicRoughness'], m.get('alphaMode'), m.get('normalTexture'), m.get('emissiveTexture'), m.get('emissiveFactor')) for m in d['materials']]")" = \
  "[('Grey', {'metallicFactor': 0.0, 'baseColorFactor': [0.5, 0.5, 0.5, 0.25]}, 'BLEND', {'index': 0, 'scale': 2.0}, None, None), ('Clear', {'metallicFactor': 0.0, 'baseColorFactor': [1.0, 0.5, 0.0, 1.0]}, None, None, {'index': 0}, [1.0, 1.0, 1.0]), ('Metal', {'metallicFactor': 1.0, 'roughnessFactor': 0.3, 'baseColorTexture': {'index': 0}}, None, None, None, None), ('Tga', {'metallicFactor': 0.0}, None, None, None, None), ('Nowhere', {'metallicFactor': 0.0}, None, None, None, None)]" ]
check "by hand: the PNG found through the Windows path" [ "$(gcheck materials "$T/hand.glb" | grep '^Metal' | cut -d'|' -f6)" = " image image/png $(sha1sum <"$TEX/tex/checker.png" | cut -c1-40) " ]
check "by hand: passes the Khronos validator (Grey's normal map without TANGENT aside)" valid "$T/hand.glb" MESH_PRIMITIVE_GENERATED_TANGENT_SPACE
# A library that cannot be read: the materials by name, a warning.
sed 's/^mtllib .*/mtllib gone.mtl/' "$M/hand.obj" >"$M/gone.obj"
run "$VNC" "$M/gone.obj" "$T/gone.glb"
check "missing library: named, materials by name" [ "$rc|$err|$(q "$T/gone.glb" "[m['name'] for m in d['materials']]")" = \
  "0|vnconvert: warning: $M/gone.obj: material library gone.mtl cannot be read (No such file or directory): its materials are written by name only|['Grey', 'Clear', 'Metal', 'Tga', 'Nowhere']" ]
# A library or texture that is a folder (or a device: no read that could block).
mkdir "$M/folder.mtl"
sed 's/^mtllib .*/mtllib folder.mtl/' "$M/hand.obj" >"$M/folder.obj"
run "$VNC" "$M/folder.obj" "$T/folder.glb"
check "a folder for a library: named, not read" [ "$rc|$err" = "0|vnconvert: warning: $M/folder.obj: material library folder.mtl cannot be read (not a regular file): its materials are written by name only" ]
# Several mtllib lines whose names have blanks (obj2gltf's box-mtllib-spaces);
# a library and a texture named where they are not (an author's absolute
# paths): found beside the OBJ and the .mtl, and named.
printf '%s\n' "newmtl Grey" "Kd 0.5 0.5 0.5" >"$M/a b.mtl"
printf '%s\n' "newmtl Metal" "map_Kd C:\\Users\\me\\a.png" >"$M/c d.mtl"
cp "$M/textures/a.png" "$M/a.png"
sed 's/^mtllib .*/mtllib a b.mtl\nmtllib \/home\/me\/c d.mtl/' "$M/hand.obj" | grep -v -e Clear -e Tga -e Nowhere >"$M/two.obj"
run "$VNC" "$M/two.obj" "$T/two.glb"
check "two libraries with blanks, moved files: named" [ "$err" = "vnconvert: warning: $M/two.obj: material library /home/me/c d.mtl is not there: $M/c d.mtl is used
vnconvert: warning: $M/two.obj: /home/me/c d.mtl: material Metal: texture C:\\Users\\me\\a.png is not there: $M/a.png is used" ]
check "two libraries with blanks, moved files: both read" [ "$(gcheck materials "$T/two.glb" | cut -d'|' -f1,2,6)" = "(none) | colour 1.000000 1.000000 1.000000 1.000000 | image - 
Grey | colour 0.500000 0.500000 0.500000 1.000000 | image - 
Metal | colour 1.000000 1.000000 1.000000 1.000000 | image image/png $(sha1sum <"$TEX/tex/checker.png" | cut -c1-40) " ]
# Blanks escaped in a name (tinyobjloader reads "a\ b.mtl" so), and an option
# of tinyobjloader's (-colorspace) skipped.
printf '%s\n' "newmtl Grey" "map_Kd -colorspace sRGB textures/a.png" >"$M/a b.mtl"
grep -v '^mtllib /home' "$M/two.obj" | sed 's/^mtllib .*/mtllib a\\ b.mtl/' >"$M/escaped.obj"
run "$VNC" "$M/escaped.obj" "$T/escaped.glb"
check "escaped blanks: read, -colorspace named" [ "$err" = "vnconvert: warning: $M/escaped.obj: a\\ b.mtl: material Grey: map_Kd's options (-colorspace sRGB) are not carried: its texture is used as it is
vnconvert: warning: $M/escaped.obj: the material library defines no Metal: written by name only" ]
check "escaped blanks: Grey's texture" [ "$(gcheck materials "$T/escaped.glb" | grep '^Grey' | cut -d'|' -f6)" = " image image/png $(sha1sum <"$TEX/tex/checker.png" | cut -c1-40) " ]
# Without texture coordinates a texture cannot be drawn (the validator's error).
sed 's#/[0-9]##g' "$M/hand.obj" >"$M/nouv.obj"
run "$VNC" "$M/nouv.obj" "$T/nouv.glb"
check "no texture coordinates: the texture named, left out" [ "$(echo "$err" | grep -c 'texture .*a.png not written: the mesh has no texture coordinates')|$(q "$T/nouv.glb" "'textures' in d")" = "3|False" ]
check "no texture coordinates: passes the Khronos validator" valid "$T/nouv.glb"
# glTF's JSON is UTF-8: a name in Latin-1 (older Windows tools) is read so.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl caf\xe9\nf 1 2 3\n' >"$T/latin.obj"
run "$VNC" "$T/latin.obj" "$T/latin.glb"
check "Latin-1 material name: written as UTF-8" [ "$rc|$err|$(q "$T/latin.glb" "d['materials'][0]['name'].encode('utf-8')")" = "0||b'caf\\xc3\\xa9'" ]
# Formats without materials still say so.
run "$VNC" "$TEX/grid.obj" "$T/grid.ply"
check "to PLY: materials named as lost" grep -q "cannot hold materials, object names: not written" "$T/stderr"
finish
