#!/usr/bin/env bash
# PLY and STL in vnconvert, on files others made: Draco's test files
# (tests/data/ply, tests/data/stl), the Stanford bunny and Blender 3.4's
# exporters. Triangle counts against Draco's own readers, PLY to PLY keeping
# every vertex property exactly, STL ASCII = binary, errors.
#   test_ply_stl.sh PATH/TO/vnconvert
set -u
VNC=$1
HERE=$(cd "$(dirname "$0")" && pwd)
PLY=$HERE/data/ply
STL=$HERE/data/stl
PLYTOOL="/usr/bin/python3 $HERE/plytool.py"
. "$HERE/lib.sh"

# Triangles in a binary STL: (size - 84) / 50.
stl_triangles() { echo $(( ($(stat -c %s "$1") - 84) / 50 )); }
# Triangles Draco's reader sees: draco_encoder (sequential, keeps every
# face), then the face count of draco_decoder's PLY. Draco 1.5.5 reads no
# ASCII STL: its facets are counted.
draco_triangles() {
  if head -c 84 "$1" | grep -q "^solid" && [ $(( ($(stat -c %s "$1") - 84) % 50 )) -ne 0 ]; then
    grep -ci "^ *endfacet" "$1"
    return
  fi
  draco_encoder -i "$1" -o "$T/draco.drc" -cl 0 >/dev/null 2>&1 &&
    draco_decoder -i "$T/draco.drc" -o "$T/draco.ply" >/dev/null 2>&1 &&
    grep -a -m1 "^element face" "$T/draco.ply" | cut -d' ' -f3
}

zcat "$HERE/meshlab/data/bun_zipper.ply.gz" >"$T/bun_zipper.ply"
MESHES="$PLY/cube_att.ply $PLY/cube_quads.ply $PLY/test_pos_color.ply $PLY/test_pos_color_ascii.ply
  $PLY/test_extra_whitespace.ply $PLY/test_generic.ply $PLY/test_more_datatypes.ply $PLY/delim_test.ply
  $PLY/blender_ascii.ply $PLY/blender_binary.ply $T/bun_zipper.ply"

# ---- every mesh: as many triangles as Draco reads; PLY to PLY keeps every vertex property
for f in $MESHES "$STL"/*.stl; do
  n=$(basename "$f")
  run "$VNC" "$f" "$T/out.stl" -q
  check "$n to STL" [ $rc -eq 0 ]
  check "$n: triangles as Draco reads them" [ "$(stl_triangles "$T/out.stl")" = "$(draco_triangles "$f")" ]
done
for f in $MESHES; do
  n=$(basename "$f")
  run "$VNC" "$f" "$T/out.ply" -q
  check "$n to PLY" [ $rc -eq 0 ]
  check "$n: PLY keeps every property, face, element and comment exactly" $PLYTOOL same "$f" "$T/out.ply"
  check "$n: written as binary little endian" [ "$(sed -n 2p "$T/out.ply")" = "format binary_little_endian 1.0" ]
done
# The counts as the files declare them (quads stay quads), and the properties kept.
run "$VNC" "$PLY/cube_quads.ply" "$T/quads.ply" -q
check "cube_quads: 8 vertices, 6 faces, 12 triangles" [ "$($PLYTOOL count "$T/quads.ply")" = "8 6 12" ]
run "$VNC" "$PLY/blender_binary.ply" "$T/blender.ply" -q
check "Blender PLY: 556 vertices, 500 polygons" [ "$($PLYTOOL count "$T/blender.ply")" = "556 500 968" ]
check "Blender PLY: normals, s t, byte colours with alpha" \
  [ "$(grep -a '^property' "$T/blender.ply" | head -12 | tr '\n' ' ')" = "property float x property float y property float z property float nx property float ny property float nz property uchar red property uchar green property uchar blue property uchar alpha property float s property float t " ]
run "$VNC" "$PLY/test_more_datatypes.ply" "$T/types.ply" -q
check "uint8 alpha colour kept as uchar" grep -aq "^property uchar alpha" "$T/types.ply"

# ---- the bunny: confidence and intensity survive PLY to PLY, glb and back
run "$VNC" "$T/bun_zipper.ply" "$T/bun.glb"
check "bunny to glb" [ $rc -eq 0 ]
check "glb has _CONFIDENCE and _INTENSITY" [ "$(q "$T/bun.glb" "sorted(k for k in d['meshes'][0]['primitives'][0]['attributes'] if k[0] == '_')")" = "['_CONFIDENCE', '_INTENSITY']" ]
check "_CONFIDENCE: 35947 floats" [ "$(q "$T/bun.glb" "(lambda a: (a['count'], a['componentType']))(d['accessors'][d['meshes'][0]['primitives'][0]['attributes']['_CONFIDENCE']])")" = "(35947, 5126)" ]
run "$VNC" "$T/bun.glb" "$T/bun_back.ply" -q
check "bunny PLY to glb to PLY: every property and face exactly" $PLYTOOL same_vertices "$T/bun_zipper.ply" "$T/bun_back.ply"
check "confidence of vertex 0 is 0.850855 (as float)" [ "$($PLYTOOL column "$T/bun_back.ply" confidence 0)" = 0.8508549928665161 ]
# PLY to PLY keeps every vertex property's name: characters glTF's names
# lack (my-prop was written my_prop, and the file's own my_prop became
# my_prop_4), case (Quality), names past 62 characters, and names the
# reader gives a role it did not take them in (ushort red green blue are no
# colour to vn, and were written red_0 green_1 blue_2; a short s next to
# float u v was written s_0, and the texture coordinates as s t).
long=$(printf 'p%.0s' $(seq 1 100))
/usr/bin/python3 - "$T/names.ply" "$long" <<'EOF'
import struct, sys
props = [("float", "x"), ("float", "y"), ("float", "z"), ("float", "my-prop"), ("float", "my_prop"),
         ("float", "Quality"), ("float", sys.argv[2]), ("ushort", "red"), ("ushort", "green"), ("ushort", "blue"),
         ("short", "s"), ("float", "u"), ("float", "v")]
verts = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0.5)]
with open(sys.argv[1], "wb") as f:
    f.write(b"ply\nformat binary_little_endian 1.0\nelement vertex 4\n")
    f.write("".join(f"property {t} {n}\n" for t, n in props).encode())
    f.write(b"element face 2\nproperty list uchar int vertex_indices\nend_header\n")
    for i, p in enumerate(verts):
        f.write(struct.pack("<6f", *p, 10 + i, 20 + i, 30 + i) + struct.pack("<f3Hh2f", 40 + i, 1000 * i, 2000 * i,
                                                                            3000 * i, -i, 0.25 * i, 0.5 * i))
    f.write(struct.pack("<B3i", 3, 0, 1, 2) + struct.pack("<B3i", 3, 1, 3, 2))
EOF
run "$VNC" "$T/names.ply" "$T/names-out.ply" -q
check "property names: PLY to PLY exits 0" [ $rc -eq 0 ]
check "property names: every vertex property kept, by name, type and values" $PLYTOOL same "$T/names.ply" "$T/names-out.ply"
check "property names: the texture coordinates as u v" grep -aq "^property float u$" "$T/names-out.ply"
# Forty extra vertex properties: each name was checked against the earlier
# ones by naming those anew, recursively (2^k work: 26 properties took 7 s,
# forty would not finish). A hang past the timeout fails.
/usr/bin/python3 - "$T/wide.ply" <<'EOF'
import struct, sys
k = 40
with open(sys.argv[1], "wb") as f:
    f.write(b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n")
    f.write("".join(f"property float q{i}\n" for i in range(k)).encode())
    f.write(b"element face 1\nproperty list uchar int vertex_indices\nend_header\n")
    for p in [(0, 0, 0), (1, 0, 0), (0, 1, 0)]:
        f.write(struct.pack("<3f", *p) + struct.pack(f"<{k}f", *range(k)))
    f.write(struct.pack("<B3i", 3, 0, 1, 2))
EOF
run timeout 60 "$VNC" "$T/wide.ply" "$T/wide-out.ply" -q
check "forty vertex properties: PLY to PLY within a minute" [ $rc -eq 0 ]
check "forty vertex properties: every one kept" $PLYTOOL same "$T/wide.ply" "$T/wide-out.ply"
# PLY to PLY keeps what vn does not change: every face property besides the
# indices and a colour (MeshLab's per-corner texcoord lists, flags), other
# elements whole, comments and obj_info. A vertex list is named in a
# warning as left out (it was dropped without a word before issue 17).
printf '%s\n' ply "format ascii 1.0" "comment first" "element vertex 3" "property float x" "property float y" "property float z" \
  "property list uchar int near" "obj_info second " "element face 1" "property list uchar int vertex_indices" "property uchar red" \
  "property uchar green" "property uchar blue" "property int label" "element material 2" "property float k" \
  "property list uchar ushort ids" "element edge 0" "property int a" end_header "0 0 0 1 1" "1 0 0 0" "0 1 0 0" \
  "3 0 1 2 255 0 0 7" "0.5 2 1 65535" "0.25 0" >"$T/extra.ply"
run "$VNC" "$T/extra.ply" "$T/extra-out.ply"
check "extras: exits 0, the triangle read" [ "$rc $($PLYTOOL count "$T/extra-out.ply")" = "0 3 1 1" ]
check "extras: one warning names the vertex list" [ "$err" = "vnconvert: warning: $T/extra.ply: left out (vn keeps the rest): vertex list 'near'" ]
check "extras: label, material (k, ids), edge, comments kept" $PLYTOOL same "$T/extra.ply" "$T/extra-out.ply"
check "extras: in the header as declared" [ "$(grep -a -A6 '^property uchar alpha' "$T/extra-out.ply" | tr '\n' '|')" = "property uchar alpha|property int label|element material 2|property float k|property list uchar ushort ids|element edge 0|property int a|" ]
check "extras: comments after vn's, blanks kept" [ "$(grep -a -m3 -n '^comment\|^obj_info' "$T/extra-out.ply" | tr '\n' '|')" = "3:comment written by vn|4:comment first|5:obj_info second |" ]
run "$VNC" "$T/extra-out.ply" "$T/extra-again.ply" -q
check "extras: a second round trip gives the same file" cmp "$T/extra-out.ply" "$T/extra-again.ply"
run "$VNC" "$T/extra.ply" "$T/extra.off"
check "extras to OFF: named as not written" grep -q "extra.off cannot hold face property 'label', element 'material' (2): not written" "$T/stderr"
# A face property named as a colour the writer writes (an alpha of another
# kind than the red, green and blue it goes with) is left out, and named.
printf '%s\n' ply "format ascii 1.0" "element vertex 3" "property float x" "property float y" "property float z" \
  "element face 1" "property list uchar int vertex_indices" "property uchar red" "property uchar green" \
  "property uchar blue" "property float alpha" end_header "0 0 0" "1 0 0" "0 1 0" "3 0 1 2 255 0 0 0.5" >"$T/alpha.ply"
run "$VNC" "$T/alpha.ply" "$T/alpha-out.ply"
check "float alpha beside uchar colours: named as left out" [ "$err" = "vnconvert: warning: $T/alpha.ply: left out (vn keeps the rest): face property 'alpha'" ]
check "float alpha beside uchar colours: one alpha written" [ "$(grep -ac '^property .* alpha' "$T/alpha-out.ply")" = 1 ]
# Paul Bourke's example of the format (greg_turk_example2): an edge element
# with colours, three comments.
printf '%s\n' ply "format ascii 1.0" "comment author: Greg Turk" "comment object: another cube" \
  "element vertex 8" "property float x" "property float y" "property float z" "property uchar red" "property uchar green" \
  "property uchar blue" "element face 7" "property list uchar int vertex_index" "element edge 5" "property int vertex1" \
  "property int vertex2" "property uchar red" "property uchar green" "property uchar blue" end_header \
  "0 0 0 255 0 0" "0 0 1 255 0 0" "0 1 1 255 0 0" "0 1 0 255 0 0" "1 0 0 0 0 255" "1 0 1 0 0 255" "1 1 1 0 0 255" \
  "1 1 0 0 0 255" "3 0 1 2" "3 0 2 3" "4 7 6 5 4" "4 0 4 5 1" "4 1 5 6 2" "4 2 6 7 3" "4 3 7 4 0" "0 1 255 255 255" \
  "1 2 255 255 255" "2 3 255 255 255" "3 0 255 255 255" "2 0 0 0 0" >"$T/turk.ply"
run "$VNC" "$T/turk.ply" "$T/turk-out.ply"
check "Bourke's example: the edges and comments kept" $PLYTOOL same "$T/turk.ply" "$T/turk-out.ply"
run "$VNC" "$T/turk.ply" "$T/turk-crease.ply" --crease-angle 30 -q
check "Bourke's example with creases: vertices split (appended), the edges kept" \
  [ "$($PLYTOOL count "$T/turk-crease.ply" | cut -d' ' -f1) $(tail -c 55 "$T/turk-crease.ply" | od -An -tx1 | tr -d ' \n')" = "24 $(tail -c 55 "$T/turk-out.ply" | od -An -tx1 | tr -d ' \n')" ]
run "$VNC" "$T/turk.ply" "$T/turk.glb"
check "Bourke's example to GLB: the edges named" grep -q "turk.glb cannot hold element 'edge' (5): not written" "$T/stderr"
# MeshLab reads the texture coordinates vn keeps as MeshLab wrote them: VCG's
# cube_att.ply, and vn's PLY of it, saved by meshlabserver as OBJ with wedge
# texture coordinates, give the same vt and f lines.
run "$VNC" "$PLY/cube_att.ply" "$T/cube_att.ply" -q
xvfb-run -a meshlabserver -i "$PLY/cube_att.ply" -o "$T/ml_in.obj" -m wt >/dev/null 2>&1
xvfb-run -a meshlabserver -i "$T/cube_att.ply" -o "$T/ml_out.obj" -m wt >/dev/null 2>&1
check "MeshLab: cube_att's 4 texture coordinates from vn's PLY" [ "$(grep -c '^vt' "$T/ml_out.obj" 2>/dev/null)" = 4 ]
check "MeshLab: the same vt and f lines as from cube_att.ply" cmp -s <(grep '^vt\|^f' "$T/ml_in.obj") <(grep '^vt\|^f' "$T/ml_out.obj")
# MeshLab's coloured OBJ (test_pos_color.ply saved with vertex colours,
# "%f" of the bytes) through vn's PLY: MeshLab reads back every v line,
# position and colour (vn wrote float colours, which MeshLab read as white).
xvfb-run -a meshlabserver -i "$PLY/test_pos_color.ply" -o "$T/mlc.obj" -m vc >/dev/null 2>&1
run "$VNC" "$T/mlc.obj" "$T/mlc.ply" -q
xvfb-run -a meshlabserver -i "$T/mlc.ply" -o "$T/mlc2.obj" -m vc >/dev/null 2>&1
check "MeshLab: its coloured OBJ through vn's PLY, every v line back" \
  cmp -s <(grep '^v ' "$T/mlc.obj" | sort) <(grep '^v ' "$T/mlc2.obj" | sort)
# Formats without face properties get those texture coordinates per vertex,
# a vertex split where its corners' pairs differ (they were dropped, named as
# not written). MeshLab parametrizes the torus (one square of the texture a
# triangle pair, so every vertex is split), saves it as PLY with a texcoord
# list and that PLY as OBJ: vn's OBJ, and its GLB read back, have the same
# corners (positions and pairs, at the 6 decimals MeshLab writes) as
# MeshLab's OBJ.
FACES="/usr/bin/python3 $HERE/objcheck.py faces"
cat >"$T/param.mlx" <<'EOF'
<!DOCTYPE FilterScript>
<FilterScript>
 <filter name="Parametrization: Trivial Per-Triangle">
  <Param type="RichInt" name="sidedim" value="0"/>
  <Param type="RichInt" name="textdim" value="1024"/>
  <Param type="RichInt" name="border" value="2"/>
  <Param type="RichEnum" name="method" value="0" enum_val0="Basic" enum_val1="Space-optimizing" enum_cardinality="2"/>
 </filter>
</FilterScript>
EOF
xvfb-run -a meshlabserver -i "$HERE/../samples/torus.off" -o "$T/torus_tex.ply" -m wt -s "$T/param.mlx" >/dev/null 2>&1
xvfb-run -a meshlabserver -i "$T/torus_tex.ply" -o "$T/ml_torus.obj" -m wt >/dev/null 2>&1
check "MeshLab: the torus parametrized, with a texcoord list" grep -aq "^property list uchar float texcoord" "$T/torus_tex.ply"
run "$VNC" "$T/torus_tex.ply" "$T/torus_tex.obj" --stats
check "textured PLY to OBJ: 4800 vertices split by texcoord, nothing lost" \
  [ "$rc|$err|$(grep '^split by texcoord' "$T/stdout")" = "0||split by texcoord:  4800 (the face list 'texcoord' written per vertex)" ]
check "textured PLY to OBJ: the corners of MeshLab's OBJ" \
  cmp -s <($FACES "$T/torus_tex.obj" 6 | cut -d'|' -f5) <($FACES "$T/ml_torus.obj" 6 | cut -d'|' -f5)
run "$VNC" "$T/torus_tex.ply" "$T/torus_tex.glb" -q
run "$VNC" "$T/torus_tex.glb" "$T/torus_glb.obj" -q
# glTF's v is 1 - v (its origin at the image's top left): through GLB, a
# coordinate below 0.5 moves by float rounding (at most 3e-8), and MeshLab
# prints 6 decimals.
check "textured PLY to GLB: the corners of MeshLab's OBJ" \
  /usr/bin/python3 "$HERE/objcheck.py" close "$T/torus_glb.obj" "$T/ml_torus.obj" 6e-7
# Its texture ("comment TextureFile", as MeshLab and Metashape name it) is a
# glTF material: MeshLab's own reading, its OBJ export (material_0, map_Kd),
# through vn to GLB, has the same material but for the name: image bytes,
# factors, triangles (the positions at MeshLab's 6 decimals aside).
mkdir "$T/texply"
cp "$HERE/data/obj/textured/tex/checker.png" "$T/texply/"
sed 's/^comment VCGLIB generated$/&\ncomment TextureFile checker.png/' "$T/torus_tex.ply" >"$T/texply/torus.ply"
xvfb-run -a meshlabserver -i "$T/texply/torus.ply" -o "$T/texply/ml.obj" -m wt >/dev/null 2>&1
check "MeshLab: the textured torus as OBJ with map_Kd" grep -q "^map_Kd checker.png" "$T/texply/ml.obj.mtl"
run "$VNC" "$T/texply/torus.ply" "$T/texply/vn.glb"
"$VNC" "$T/texply/ml.obj" "$T/texply/ml.glb" -q
material() { python3 "$HERE/gltf/gltfcheck.py" materials "$1" | cut -d'|' -f2-7; }
check "textured PLY to GLB: no warning" [ "$rc|$err" = "0|" ]
check "textured PLY to GLB: MeshLab's material" [ "$(material "$T/texply/vn.glb")" = "$(material "$T/texply/ml.glb")" ]
check "textured PLY to GLB: the PNG's bytes, named by its file" [ "$(python3 "$HERE/gltf/gltfcheck.py" materials "$T/texply/vn.glb" | cut -d'|' -f1,6)" = \
  "checker.png | image image/png $(sha1sum <"$HERE/data/obj/textured/tex/checker.png" | cut -c1-40) " ]
# MeshLab's several textures: a face's texnumber picks its TextureFile (and
# is no longer named as lost); one out of range has none.
printf '%s\n' ply "format ascii 1.0" "comment TextureFile checker.png" "comment TextureFile gone.png" "element vertex 4" \
  "property float x" "property float y" "property float z" "element face 3" "property list uchar int vertex_indices" \
  "property list uchar float texcoord" "property int texnumber" end_header "0 0 0" "1 0 0" "1 1 0" "0 1 0" \
  "3 0 1 2 6 0 0 1 0 1 1 1" "3 0 2 3 6 0 0 1 1 0 1 0" "3 0 1 3 6 0 0 1 0 0 1 7" >"$T/texply/two.ply"
run "$VNC" "$T/texply/two.ply" "$T/texply/two.glb"
check "texnumber: a primitive per texture, the missing one named" [ "$rc|$err|$(q "$T/texply/two.glb" "[(p.get('material'), d['accessors'][p['indices']]['count']) for p in d['meshes'][0]['primitives']]")" = \
  "0|vnconvert: warning: $T/texply/two.ply: comment TextureFile: material gone.png: texture gone.png cannot be read (No such file or directory): written without it|[(0, 3), (1, 3), (None, 3)]" ]
check "texnumber: the faces' textures" [ "$(q "$T/texply/two.glb" "[(m['name'], 'baseColorTexture' in m['pbrMetallicRoughness']) for m in d['materials']]")" = "[('gone.png', False), ('checker.png', True)]" ]
# A file named twice (texnumbers 0 and 2, one image) is one material, which
# both numbers pick: the second was a material of its own, never defined
# (no texture: fuzz_ply's check that every material is defined caught it).
sed 's/^comment TextureFile gone.png$/&\ncomment TextureFile checker.png/; s/^3 0 1 3 6 0 0 1 0 0 1 7$/3 0 1 3 6 0 0 1 0 0 1 2/' \
  "$T/texply/two.ply" >"$T/texply/twice.ply"
run "$VNC" "$T/texply/twice.ply" "$T/texply/twice.glb" -q
check "a TextureFile named twice: one material, its faces in one primitive" [ "$rc|$(q "$T/texply/twice.glb" "[(p.get('material'), d['accessors'][p['indices']]['count']) for p in d['meshes'][0]['primitives']]")|$(q "$T/texply/twice.glb" "[(m['name'], 'baseColorTexture' in m['pbrMetallicRoughness']) for m in d['materials']]")" = \
  "0|[(0, 3), (1, 6)]|[('gone.png', False), ('checker.png', True)]" ]
# By hand: a seam at vertex 0 (its two corners differ), vertex 2 shared.
# Copies share their vertex's normal, with --no-weld too: the file gave
# them one vertex. A list that is not a pair per corner stays a face list,
# named as not written.
printf '%s\n' ply "format ascii 1.0" "element vertex 4" "property float x" "property float y" "property float z" \
  "element face 2" "property list uchar int vertex_indices" "property list uchar float texcoord" end_header \
  "0 0 0" "1 0 0" "1 1 0.5" "0 1 0" "3 0 1 2 6 0 0 1 0 1 1" "3 0 2 3 6 0.5 0.5 1 1 0 1" >"$T/seam.ply"
run "$VNC" "$T/seam.ply" "$T/seam.obj" --no-weld --stats
check "a seam: one vertex split" grep -q "^split by texcoord:  1 " "$T/stdout"
check "a seam: the corners' pairs" [ "$($FACES "$T/seam.obj" | cut -d'|' -f5 | tr '\n' '|')" = \
  "3: 0.0,0.0,0.0,0.0,0.0 1.0,0.0,0.0,1.0,0.0 1.0,1.0,0.5,1.0,1.0|3: 0.0,0.0,0.0,0.5,0.5 1.0,1.0,0.5,1.0,1.0 0.0,1.0,0.0,0.0,1.0|" ]
check "a seam: one normal at vertex 0 (one position, one vn)" \
  [ "$(grep -c '^v ' "$T/seam.obj") $(grep '^f' "$T/seam.obj" | awk '{split($2, a, "/"); print a[3]}' | sort -u | wc -l)" = "4 1" ]
run "$VNC" "$T/seam.ply" "$T/seam.off" -q
check "a seam to OFF: 5 vertices with ST" [ "$(head -2 "$T/seam.off" | tr '\n' ' ')" = "STNOFF 5 2 0 " ]
sed 's/^3 0 2 3 6 .*/3 0 2 3 4 0.5 0.5 1 1/' "$T/seam.ply" >"$T/short.ply"
run "$VNC" "$T/short.ply" "$T/short.obj"
check "a texcoord list not a pair per corner: named, no vt" \
  [ "$err|$(grep -c '^vt' "$T/short.obj")" = "vnconvert: warning: $T/short.obj cannot hold face list 'texcoord': not written|0" ]
run "$VNC" "$T/seam.ply" "$T/seam.stl"
check "a texcoord list to STL: named as not written" grep -q "seam.stl cannot hold vertex normals, face list 'texcoord': not written" "$T/stderr"
run "$VNC" "$T/names-out.ply" "$T/names-again.ply" -q
check "property names: a second round trip gives the same file" cmp "$T/names-out.ply" "$T/names-again.ply"

# ---- in place, as issue 17 asks
cp "$T/bun_zipper.ply" "$T/scan.ply"
run "$VNC" "$T/scan.ply" "$T/scan.ply" --method mwselr --in-place -q
check "--in-place exits 0" [ $rc -eq 0 ]
check "--in-place: normals added, the rest exact" $PLYTOOL same "$T/bun_zipper.ply" "$T/scan.ply"
check "--in-place: has nx" grep -aq "^property float nx" "$T/scan.ply"
run "$VNC" "$T/scan.ply" "$T/scan.ply" -q
check "the same file without --in-place is refused" [ $rc -eq 2 ]

# ---- big endian reads as little endian does
$PLYTOOL big "$PLY/test_pos_color.ply" "$T/big.ply"
run "$VNC" "$T/big.ply" "$T/big_out.ply" -q
run "$VNC" "$PLY/test_pos_color.ply" "$T/little_out.ply" -q
check "big endian PLY: same output as little endian" cmp -s "$T/big_out.ply" "$T/little_out.ply"

# ---- tristrips (Stanford's and MeshLab's older files: no face element): two
# strips, the second after a -1 and ending in a repeated index (a triangle
# without surface, left out, as strips are joined); every other triangle
# turned, so that all face the same way (-z: a 2 x 2 grid of unit squares).
# Also in binary big endian.
cat >"$T/strips.ply" <<'PLYEOF'
ply
format ascii 1.0
element vertex 9
property float x
property float y
property float z
element tristrips 1
property list int int vertex_indices
end_header
0 0 0
1 0 0
2 0 0
0 1 0
1 1 0
2 1 0
0 2 0
1 2 0
2 2 0
14 0 3 1 4 2 5 -1 3 6 4 7 5 8 8
PLYEOF
run "$VNC" "$T/strips.ply" "$T/strips.off" --stats
check "tristrips: 8 triangles, none degenerate" [ "$rc $(echo "$out" | grep -cE '^(faces: +8 \(triangles\)|degenerate faces: +0)$')" = "0 2" ]
check "tristrips: the triangles" [ "$(tail -8 "$T/strips.off" | tr '\n' ,)" = "3 0 3 1,3 1 3 4,3 1 4 2,3 2 4 5,3 3 6 4,3 4 6 7,3 4 7 5,3 5 7 8," ]
check "tristrips: every normal -z" [ "$(sed -n '3,11p' "$T/strips.off" | awk '{print $4, $5, $6}' | sort -u)" = "0 0 -1" ]
$PLYTOOL big "$T/strips.ply" "$T/strips_big.ply"
run "$VNC" "$T/strips_big.ply" "$T/strips_big.off"
check "tristrips, binary big endian: the same" cmp -s "$T/strips.off" "$T/strips_big.off"
sed 's/^14 0 3 1 4 2 5 -1 3 6 4 7 5 8 8$/4 0 3 1 9/' "$T/strips.ply" >"$T/strips_range.ply"
check_rejected "$VNC" "$T/strips_range.ply" "$T/none.off" "$T/keep.off"
check "tristrips: an index out of range names it" grep -q "tristrips 0 has index 9, but the file has 9 vertices" "$T/stderr"

# ---- a UTF-8 byte order mark (Windows editors write one) is read past; UTF-16
# text is read as its UTF-8 (it was refused), but for a binary body
{ printf '\357\273\277'; cat "$T/strips.ply"; } >"$T/bom.ply"
run "$VNC" "$T/bom.ply" "$T/bom_ply.off"
check "PLY with a UTF-8 byte order mark: read" cmp -s "$T/strips.off" "$T/bom_ply.off"
printf '\357\273\277solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n' >"$T/bom.stl"
run "$VNC" "$T/bom.stl" "$T/bom_stl.off"
check "ASCII STL with a UTF-8 byte order mark: one triangle" [ "$rc $(sed -n 2p "$T/bom_stl.off")" = "0 3 1 0" ]
{ printf '\376\377'; iconv -f UTF-8 -t UTF-16BE "$T/strips.ply"; } >"$T/utf16.ply"
run "$VNC" "$T/utf16.ply" "$T/utf16_ply.off"
check "UTF-16 ASCII PLY: read" cmp -s "$T/strips.off" "$T/utf16_ply.off"
{ printf '\376\377'; sed 's/^format ascii/format binary_little_endian/' "$T/strips.ply" | iconv -f UTF-8 -t UTF-16BE; } >"$T/utf16.ply"
check_rejected "$VNC" "$T/utf16.ply" "$T/none.off" "$T/keep.off"
check "UTF-16 binary PLY: says why not" grep -qF "utf16.ply:2: the header is UTF-16BE text (it starts with a byte order mark), but the format is binary_little_endian: binary data cannot be read as text" "$T/stderr"
{ printf '\377\376'; tail -c +4 "$T/bom.stl" | iconv -f UTF-8 -t UTF-16LE; } >"$T/utf16.stl"
run "$VNC" "$T/utf16.stl" "$T/utf16_stl.off"
check "UTF-16 ASCII STL: read" cmp -s "$T/bom_stl.off" "$T/utf16_stl.off"
printf '\377\376h\000i\000\n\000' >"$T/utf16.stl"
check_rejected "$VNC" "$T/utf16.stl" "$T/none.off" "$T/keep.off"
check "UTF-16 text that is no STL: says so" grep -qF "utf16.stl: the text is UTF-16LE (it starts with a byte order mark), but does not start with 'solid', as an ASCII STL does" "$T/stderr"

# ---- double positions stay double; a double property is rounded to float, with a warning
cat >"$T/double.ply" <<'PLYEOF'
ply
format ascii 1.0
element vertex 3
property double x
property double y
property double z
property double quality
element face 1
property list uchar int vertex_indices
end_header
0.1 0 0 0.1
0 1 0 1
0 0 1 2
3 0 1 2
PLYEOF
run "$VNC" "$T/double.ply" "$T/double_out.ply"
check "double x stays double" grep -aq "^property double x" "$T/double_out.ply"
check "x = 0.1 exactly" [ "$($PLYTOOL column "$T/double_out.ply" x 0)" = 0.1 ]
# A double property stays double (it was read as float, 0.1 rounded); glTF,
# which has no double, says what it rounds.
check "quality stays double" grep -aq "^property double quality" "$T/double_out.ply"
check "quality = 0.1 exactly" [ "$($PLYTOOL column "$T/double_out.ply" quality 0)" = 0.1 ]
check "PLY to PLY: no warning" [ ! -s "$T/stderr" ]
run "$VNC" "$T/double.ply" "$T/double_out.glb"
check "double property to glTF: rounding said" grep -qx "vnconvert: warning: $T/double_out.glb: quality is double, written as float: 1 of its 3 values rounded" "$T/stderr"

# ---- STL: ASCII and binary of the same sphere give the same mesh; welded; positions kept
# The ASCII file has 6 decimals: the same faces, positions within 1e-6.
run "$VNC" "$STL/test_sphere.stl" "$T/bin.off" -q
run "$VNC" "$STL/test_sphere_ascii.stl" "$T/ascii.off" -q
check "STL ASCII and binary: the same vertices and faces" /usr/bin/python3 - "$T/bin.off" "$T/ascii.off" <<'PYEOF'
import sys, numpy as np
(a, fa), (b, fb) = ((np.array([l.split()[:3] for l in t[2:116]], float), t[116:]) for t in (open(f).read().splitlines() for f in sys.argv[1:]))
sys.exit(not (fa == fb and len(fa) == 224 and np.abs(a - b).max() <= 1e-6))
PYEOF
run "$VNC" "$STL/test_sphere.stl" "$T/bin.stl" -q
run "$VNC" "$STL/test_sphere.stl" "$T/sphere.ply" -q
check "sphere: corners welded into 114 vertices, 224 triangles" [ "$($PLYTOOL count "$T/sphere.ply")" = "114 224 224" ]
check "STL to STL keeps every corner's position" /usr/bin/python3 - "$STL/test_sphere.stl" "$T/bin.stl" <<'PYEOF'
import sys, numpy as np
a, b = (np.frombuffer(open(f, "rb").read()[84:], np.dtype([("n", "<f4", 3), ("p", "<f4", 9), ("a", "<u2")])) for f in sys.argv[1:])
sys.exit(not (np.array_equal(a["p"], b["p"]) and np.allclose(np.linalg.norm(b["n"], axis=1), 1, atol=1e-6)))
PYEOF
check "STL to STL: the input's header" [ "$(head -c 26 "$T/bin.stl")" = "Exported from Blender-3.0." ]
run "$VNC" "$T/sphere.ply" "$T/from-ply.stl" -q
check "STL header of vn's own, not starting with solid" [ "$(head -c 24 "$T/from-ply.stl")" = "binary STL written by vn" ]
run "$VNC" "$STL/blender_ascii.stl" "$T/b1.stl" -q
run "$VNC" "$STL/blender_binary.stl" "$T/b2.stl" -q
check "Blender STL ASCII and binary: same triangles" [ "$(stl_triangles "$T/b1.stl")" = 968 ] && check "Blender STL: 968 both" [ "$(stl_triangles "$T/b2.stl")" = 968 ]
# ASCII that ends after a whole facet without 'endsolid' (writers that leave
# it out; Blender 3.4, Open3D and meshio read such a file): read, with a
# warning. Cut inside a facet, or with no facet at all, it is refused.
printf 'solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n' >"$T/unended.stl"
run "$VNC" "$T/unended.stl" "$T/unended.off"
check "ASCII STL without endsolid: read, with a warning" [ "$rc|$err|$(sed -n 2p "$T/unended.off")" = "0|vnconvert: warning: $T/unended.stl: the file ends after 1 triangle without 'endsolid': read (a writer left it out, or the file was cut after a whole triangle)|3 1 0" ]
printf 'solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n' >"$T/cut.stl"
check_rejected "$VNC" "$T/cut.stl" "$T/none.off" "$T/keep.off"
check "ASCII STL cut inside a facet: refused, saying where" grep -q "cut.stl:6: the file ends where 'vertex' was expected (triangle 0)" "$T/stderr"
# A binary STL whose header starts with "solid" (as some exporters write) is binary by its size.
{ printf 'solid but binary'; head -c 64 /dev/zero; tail -c +81 "$STL/test_sphere.stl"; } >"$T/solid_binary.stl"
run "$VNC" "$T/solid_binary.stl" "$T/sb.stl" -q
check "binary STL starting with 'solid' is read as binary" cmp -s <(tail -c +81 "$T/sb.stl") <(tail -c +81 "$T/bin.stl")
check "binary STL starting with 'solid': its header kept" [ "$(head -c 16 "$T/sb.stl")" = "solid but binary" ]
# ... and so is one with padding after its triangles (it was read as ASCII:
# "the file ends after 0 triangles, before 'endsolid'").
{ cat "$T/solid_binary.stl"; printf '\0\0'; } >"$T/solid_padded.stl"
run "$VNC" "$T/solid_padded.stl" "$T/sp.stl"
check "binary STL starting with 'solid', padded: read as binary" cmp -s "$T/sp.stl" "$T/sb.stl"
check "binary STL starting with 'solid', padded: says so" grep -q "solid_padded.stl: 2 bytes after the last triangle, not read" "$T/stderr"
# A count of 0 with triangles after it (a writer that never filled it in).
{ head -c 80 "$STL/test_sphere.stl"; printf '\0\0\0\0'; tail -c +85 "$STL/test_sphere.stl"; } >"$T/count0.stl"
run "$VNC" "$T/count0.stl" "$T/c0.stl"
check "binary STL with count 0: its triangles read" cmp -s "$T/c0.stl" "$T/bin.stl"
check "binary STL with count 0: says so" grep -q "count0.stl: binary STL announces 0 triangles, but 224 triangles follow its header: read" "$T/stderr"
# Colours in a binary STL are read as face colours: VisCAM's and SolidView's
# (bit 15 of a triangle's attribute bytes marks a colour: red in bits 10-14,
# green 5-9, blue 0-4), Materialise Magics' (COLOR= RGBA in the header, as
# trimesh's 20mm-xyz-cube.stl has it: bit 15 clear, the triangle's own colour,
# red in bits 0-4; set, the header's); 5 bits are the bytes k * 255 / 31. The
# two spaces an old Blender exporter left there are no colour.
stl_with() { # HEADER ATTRIBUTE-HEX OUT: two triangles
  /usr/bin/python3 -c 'import struct, sys
h, a = sys.argv[1].encode().ljust(80), bytes.fromhex(sys.argv[2])
t = [(0, 0, 0, 1, 0, 0, 0, 1, 0), (1, 0, 0, 1, 1, 0, 0, 1, 0)]
open(sys.argv[3], "wb").write(h + struct.pack("<I", 2) + b"".join(struct.pack("<12f", 0, 0, 1, *c) + a for c in t))' "$@"
}
face_colours() { tail -n 2 "$1" | cut -d' ' -f5- | tr '\n' '|'; }
stl_with "VisCAM" 1f80 "$T/viscam.stl"
run "$VNC" "$T/viscam.stl" "$T/viscam.off"
check "STL colours (VisCAM, 0x801f): blue faces, no warning" [ "$rc|$err|$(face_colours "$T/viscam.off")" = "0||0 0 255 255|0 0 255 255|" ]
stl_with "COLOR=abcd" 1f00 "$T/magics.stl"
run "$VNC" "$T/magics.stl" "$T/magics.off"
check "STL colours (Magics, 0x001f): red faces" [ "$rc|$err|$(face_colours "$T/magics.off")" = "0||255 0 0 255|255 0 0 255|" ]
stl_with "COLOR=abcd" 0a81 "$T/magics-object.stl"
run "$VNC" "$T/magics-object.stl" "$T/magics-object.off"
check "STL colours (Magics, bit 15 set): the header's COLOR=abcd" [ "$rc|$(face_colours "$T/magics-object.off")" = "0|97 98 99 100|97 98 99 100|" ]
run "$VNC" "$T/viscam.stl" "$T/viscam.glb"
check "STL colours to glTF: named as not written" grep -q "viscam.glb cannot hold face colours: not written" "$T/stderr"
# STL to STL: the header and the attribute bytes as they were.
run "$VNC" "$T/magics.stl" "$T/magics2.stl" -q
check "STL to STL keeps the header and attribute bytes" /usr/bin/python3 - "$T/magics.stl" "$T/magics2.stl" <<'PYEOF'
import sys
a, b = (open(p, "rb").read() for p in sys.argv[1:])
sys.exit(not (len(a) == len(b) == 184 and a[:84] == b[:84] and all(a[84 + 50 * t + 12:134 + 50 * t] == b[84 + 50 * t + 12:134 + 50 * t] for t in range(2))))
PYEOF
# Face colours from another format: VisCAM's, as MeshLab writes them (97,
# 98, 99 are 12 in 5 bits: 0x8000 | 12 << 10 | 12 << 5 | 12 = 0xb18c); an
# STL's own VisCAM colours come back as they were.
stl_attributes() { /usr/bin/python3 -c 'import struct, sys
b = open(sys.argv[1], "rb").read()
print(" ".join("%04x" % struct.unpack_from("<H", b, 84 + 50 * t + 48) for t in range(struct.unpack_from("<I", b, 80)[0])))' "$1"; }
run "$VNC" "$T/magics-object.off" "$T/from-off.stl" -q
check "OFF face colours to STL: VisCAM's 0xb18c" [ "$(stl_attributes "$T/from-off.stl")" = "b18c b18c" ]
run "$VNC" "$T/viscam.off" "$T/viscam-back.stl" -q
check "STL (VisCAM) to OFF to STL: the colours as they were" [ "$(stl_attributes "$T/viscam-back.stl")" = "801f 801f" ]
stl_with "Binary STL output from Blender" 2020 "$T/padding.stl"
run "$VNC" "$T/padding.stl" "$T/padding.off"
check "STL attribute bytes of blanks: no colour, no warning" [ "$rc|$err|$(sed -n 2p "$T/padding.off")|$(face_colours "$T/padding.off")" = "0||4 2 0|||" ]
run "$VNC" "$PLY/blender_binary.ply" "$T/lost.stl"
check "PLY to STL warns that the vertex normals are not written" grep -q "cannot hold vertex normals, vertex colours, texture coordinates: not written" "$T/stderr"

# ---- bad input: one line naming the file, no output
check_rejected "$VNC" "$PLY/float_inf_point_cloud.ply" "$T/none.ply" "$T/keep.ply"
check "infinite coordinate: says so" grep -q "float_inf_point_cloud.ply: vertex 0 is at (-409, 249, inf)" "$T/stderr"
# ---- point clouds (no faces): read, written as PLY and OFF with every vertex property, refused for STL
for f in point_cloud_test_pos int_point_cloud; do
  run "$VNC" "$PLY/$f.ply" "$T/cloud.ply"
  check "$f to PLY: exit 0" [ $rc -eq 0 ]
  check "$f to PLY: nothing said left out" not grep -q "left out" "$T/stderr"
  check "$f to PLY: every vertex, no faces" [ "$($PLYTOOL count "$T/cloud.ply")" = "$($PLYTOOL count "$PLY/$f.ply")" ]
  [ $f = int_point_cloud ] || check "$f to PLY: every property kept" $PLYTOOL same "$PLY/$f.ply" "$T/cloud.ply"
  run "$VNC" "$T/cloud.ply" "$T/cloud2.ply"
  check "$f to PLY and again: the same bytes" cmp -s "$T/cloud.ply" "$T/cloud2.ply"
  run "$VNC" "$PLY/$f.ply" "$T/cloud.off"
  check "$f to OFF: exit 0" [ $rc -eq 0 ]
  check "$f to OFF: every vertex, no faces" [ "$(sed -n 2p "$T/cloud.off" | cut -d' ' -f1-2)" = "$(head -c 300 "$PLY/$f.ply" | grep -a -m1 "^element vertex" | cut -d' ' -f3) 0" ]
done
check "int_point_cloud to OFF: the file's coordinates" [ "$(sed -n 3p "$T/cloud.off" | cut -d' ' -f1-3)" = "-409 249 4" ]
# normals, colours and another property of a point cloud, through PLY and OFF
printf 'ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nproperty float intensity\nend_header\n0 0 0 0 0 1 255 0 0 0.5\n1 0 0 0 1 0 0 255 0 0.25\n' >"$T/scan.ply"
run "$VNC" "$T/scan.ply" "$T/scan_out.ply" --stats
check "scanned point cloud to PLY: exit 0" [ $rc -eq 0 ]
check "scanned point cloud: the input's normals kept, said so" grep -q "scan.ply has no faces (a point cloud): vn computes no normals; the input's are kept$" "$T/stderr"
check "scanned point cloud: --stats says the input's normals are kept" grep -q "^zero normals: *2 (the input's kept)$" "$T/stdout"
check "scanned point cloud: colours and intensity kept" $PLYTOOL same "$T/scan.ply" "$T/scan_out.ply"
check "scanned point cloud: normals kept" [ "$($PLYTOOL column "$T/scan_out.ply" nz 0) $($PLYTOOL column "$T/scan_out.ply" ny 1)" = "1.0 1.0" ]
run "$VNC" "$T/scan.ply" "$T/scan_out.off"
check "scanned point cloud to OFF: normals and colours" [ "$(sed -n 3p "$T/scan_out.off")" = "0 0 0 0 0 1 255 0 0 255" ]
# double normals (Open3D's writer makes them) are the file's: kept exactly
# in PLY and OFF; a double property beyond float's range is said to be
printf 'ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\nproperty double z\nproperty double nx\nproperty double ny\nproperty double nz\nproperty double big\nend_header\n0 0 0 0.1 0.2 0.9746794344808963 1e300\n1 0 0 0.6 0 0.8 1e-320\n' >"$T/dn.ply"
run "$VNC" "$T/dn.ply" "$T/dn_out.ply"
check "double normals of a point cloud: written as double" grep -aq "^property double nx$" "$T/dn_out.ply"
check "double normals of a point cloud: kept exactly" [ "$($PLYTOOL column "$T/dn_out.ply" nz 0) $($PLYTOOL column "$T/dn_out.ply" nx 1)" = "0.9746794344808963 0.6" ]
check "a double beyond float's range: kept exactly in PLY" [ "$($PLYTOOL column "$T/dn_out.ply" big 0) $($PLYTOOL column "$T/dn_out.ply" big 1)" = "1e+300 1e-320" ]
run "$VNC" "$T/dn.ply" "$T/dn_out.gltf"
check "a double beyond float's range: said so for glTF" grep -q "dn_out.gltf: big is double, written as float: 2 of its 2 values rounded, 2 of them beyond float's range (now infinite, or 0)" "$T/stderr"
run "$VNC" "$T/dn.ply" "$T/dn_out.off"
check "double normals of a point cloud to OFF: kept exactly" [ "$(sed -n 3p "$T/dn_out.off")" = "0 0 0 0.1 0.2 0.9746794344808963" ]
rejected_text() { printf "$2" >"$T/$1"; check_rejected "$VNC" "$T/$1" "$T/none.off" "$T/keep.off"; }
HEADER='ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n'
rejected_text ctrlname.ply 'ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nproperty float \001q\nend_header\n0 0 0 1\n'
check "a property name with a control character (fuzz_ply): file, line, why" grep -q "ctrlname.ply:7: property name '.q' has a control character" "$T/stderr"
rejected_text ctrlelement.ply 'ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement m\001 1\nend_header\n0 0 0\n'
check "an element name with a control character (fuzz_ply): file, line, why" grep -q "ctrlelement.ply:7: element name 'm.' has a control character" "$T/stderr"
# Blender 2.4x's exporter wrote its credit line without "comment" (assimp's
# Wuson.ply): a line of no keyword before the first element is a comment,
# kept as one (PLY to PLY writes "comment Created by ..."), with a warning.
# After an element line such a line is refused: it would hide a misspelt
# property.
printf 'ply\nformat ascii 1.0\nCreated by Blender3D 247 - www.blender.org, source file: x.blend\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >"$T/credit.ply"
run "$VNC" "$T/credit.ply" "$T/credit-out.ply"
check "Blender 2.4x credit line: read, with a warning" [ "$rc|$err" = "0|vnconvert: warning: $T/credit.ply: header line 3 ('Created by Blender3D 247...') has no keyword: read as a comment (Blender 2.4x wrote its credit line so)" ]
check "Blender 2.4x credit line: kept as a comment" grep -aqx "comment Created by Blender3D 247 - www.blender.org, source file: x.blend" "$T/credit-out.ply"
check "Blender 2.4x credit line: the triangle read" [ "$($PLYTOOL count "$T/credit-out.ply")" = "$($PLYTOOL count "$T/credit.ply")" ]
rejected_text misspelt.ply 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproprety float z\nend_header\n'
check "a line of no keyword after an element: refused" grep -q "misspelt.ply:6: unexpected 'proprety' in the header" "$T/stderr"
rejected_text index.ply "${HEADER}0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"
check "index out of range: file, line, face" grep -q "index.ply:13: face 0 has index 3, but the file has 3 vertices" "$T/stderr"
rejected_text short.ply "${HEADER}0 0 0\n1 0 0\n"
check "ASCII cut short: counts the bytes" grep -q "short.ply:10: element 'vertex' announces 3 entries, more than the 12 bytes after the header can hold" "$T/stderr"
rejected_text shortface.ply "${HEADER}0 0 0\n1 0 0\n0 1 0\n3 0 1\n"
check "ASCII cut short in a face: says where" grep -q "shortface.ply:14: the file ends in face 0 of 1 (property 'vertex_indices')" "$T/stderr"
rejected_text word.ply "${HEADER}0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n"
check "not a number: line and property" grep -q "word.ply:11: vertex 1, property 'y': 'zero' is not a number" "$T/stderr"
# Data that does not follow its header (trimesh's fuze_ascii.ply: each face
# line has values its header declares no property for; MeshLab, Open3D and
# meshio refuse it too): the message names the first line that held more
# than its entry took, where the failure comes later.
rejected_text extra.ply "${HEADER}0 0 0\n1 0 0\n0 1 0 7 7\n3 0 1 2\n"
check "values left on a line: named with the failure" grep -q "extra.ply:12: face 0, list 'vertex_indices' has 7 values, more than the rest of the file holds; vertex 2 ends on line 12 with 2 values left on that line: the data does not follow the header" "$T/stderr"
# And the other way round (assimp's issue623.ply: a vertex list property
# its lines lack): the entry whose property came from the next line.
rejected_text shortline.ply 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty uchar flag\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0.5 0 0\n1.5 0 0\n0 1.5 0\n3 0 1 2\n'
check "values missing from a line: named with the failure" grep -q "shortline.ply:12: vertex 0, property 'flag': '1.5' is not of type uchar (a whole number from 0 to 255); vertex 0 begins on line 11, but its property 'flag' is read from a later line: the data does not follow the header" "$T/stderr"
rejected_text nan.ply "${HEADER}0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n"
check "NaN coordinate: names the vertex" grep -q "nan.ply: vertex 1 is at (1, nan, 0)" "$T/stderr"
rejected_text noply.ply 'PLY\nformat ascii 1.0\n'
rejected_text noend.ply 'ply\nformat ascii 1.0\nelement vertex 3\n'
rejected_text counts.ply 'ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\0\0\0\0'
check "counts larger than the file" grep -q "counts.ply:.*element 'vertex' announces 1000000000 entries" "$T/stderr"
head -c 3000 "$PLY/test_pos_color.ply" >"$T/truncated.ply"
check_rejected "$VNC" "$T/truncated.ply" "$T/none.glb" "$T/keep.glb"
check "binary PLY cut short: byte offset" grep -q "truncated.ply: byte 3000: the file ends in" "$T/stderr"
head -c 5000 "$STL/test_sphere.stl" >"$T/truncated.stl"
check_rejected "$VNC" "$T/truncated.stl" "$T/none.ply" "$T/keep.ply"
check "binary STL cut short" grep -q "truncated.stl: binary STL announces 224 triangles (11284 bytes), but the file has 5000 bytes" "$T/stderr"
sed '20s/vertex/vertec/' "$STL/test_sphere_ascii.stl" >"$T/typo.stl"
check_rejected "$VNC" "$T/typo.stl" "$T/none.ply" "$T/keep.ply"
check "ASCII STL: line of the typo" grep -q "typo.stl:20: expected 'vertex', found 'vertec'" "$T/stderr"
head -n 30 "$STL/test_sphere_ascii.stl" >"$T/cut.stl"
check_rejected "$VNC" "$T/cut.stl" "$T/none.ply" "$T/keep.ply"
: >"$T/empty.stl"
check_rejected "$VNC" "$T/empty.stl" "$T/none.ply" "$T/keep.ply"
check "a file of no bytes: not an STL" grep -q "empty.stl: not an STL file: 0 bytes" "$T/stderr"
# An STL of no triangles (a binary count of 0, or "solid" then "endsolid")
# is an empty mesh: written, with a warning (it was refused, "has no
# triangles: a mesh is needed").
{ head -c 80 /dev/zero | tr '\0' ' '; printf '\0\0\0\0'; } >"$T/none-binary.stl"
printf 'solid nothing\nendsolid nothing\n' >"$T/none-ascii.stl"
for f in none-binary none-ascii; do
  run "$VNC" "$T/$f.stl" "$T/$f.ply"
  check "$f.stl: an empty PLY, and a warning" \
    [ "$rc|$($PLYTOOL count "$T/$f.ply")|$err" = "0|0 0 0|vnconvert: warning: $T/$f.stl has no vertices and no faces: $T/$f.ply is written empty" ]
done
# A point cloud (an OFF without faces) written as STL: refused, not an empty
# STL; as PLY: written, and read back.
printf 'OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n' >"$T/cloud.off"
rm -f "$T/cloud.stl" "$T/cloud.ply"
run "$VNC" "$T/cloud.off" "$T/cloud.stl"
check "point cloud to STL: exit 1" [ $rc -eq 1 ]
check "point cloud to STL: no file" [ ! -e "$T/cloud.stl" ]
check "point cloud to STL: one line" one_line_err
check "point cloud to STL: says why" grep -q "cloud.stl: .*cloud.off has 3 vertices and no faces (a point cloud), and vn writes STL only with faces: write OFF, PLY, OBJ, glTF or Draco" "$T/stderr"
run "$VNC" "$T/cloud.off" "$T/cloud.ply"
check "point cloud to PLY: exit 0" [ $rc -eq 0 ]
check "point cloud to PLY: 3 vertices, no faces" [ "$($PLYTOOL count "$T/cloud.ply")" = "3 0 0" ]
run "$VNC" "$T/cloud.ply" "$T/cloud_back.off"
check "point cloud to PLY and back: the same positions" [ "$(sed -n '3,5p' "$T/cloud_back.off" | cut -d' ' -f1-3 | tr '\n' ' ')" = "0 0 0 1 0 0 0 1 0 " ]
# Attributes named "x_1" and "x" (Draco GENERIC names, found by a hunt):
# "x" is the position's, and its "x_1" the first's; the second becomes
# "x_2", not a second "x_1" (a header no reader takes), and a second pass
# gives the same bytes.
run "$VNC" "$HERE/data/draco/generic-names.drc" "$T/names.ply" -q
check "attribute names x_1 and x: distinct properties" \
  [ "$(grep -a '^property float' "$T/names.ply" | cut -d' ' -f3 | tr '\n' ' ')" = "x y z x_1 x_2 " ]
run "$VNC" "$T/names.ply" "$T/names2.ply" -q
check "attribute names x_1 and x: PLY again, the same bytes" cmp -s "$T/names.ply" "$T/names2.ply"
finish
