#!/usr/bin/env bash
# The Khronos glTF-Validator on vnconvert's output: for every sample model and
# every method, the .glb and .gltf outputs have no error, warning or
# information code that the input did not already have (CesiumMan and sphere have some of their own).
#   test_gltf_validate.sh PATH/TO/vnconvert NODE_MODULES_DIR GLTF_SAMPLE_DIR
# NODE_MODULES_DIR holds the npm package gltf-validator (.ci/setup installs it).
set -u
VNC=$1
MODULES=$2
DATA=$3
HERE=$(cd "$(dirname "$0")" && pwd)
if [ ! -d "$MODULES/gltf-validator" ]; then
  echo "FAIL: $MODULES/gltf-validator is missing: run .ci/setup (npm install gltf-validator)"
  exit 1
fi
. "$(dirname "$0")/lib.sh"

models=()
while IFS= read -r f; do models+=("$f"); done < <(find "$DATA" \( -name '*.gltf' -o -name '*.glb' \) | sort)
python3 "$HERE/gltf/gltfcheck.py" shapes "$T/shapes.gltf"
python3 "$HERE/gltf/gltfcheck.py" sphere "$T/seam.gltf"
python3 "$HERE/gltf/gltfcheck.py" quantized "$T/quantized.gltf"
python3 "$HERE/gltf/gltfcheck.py" morphsphere "$T/morph.gltf"
python3 "$HERE/gltf/gltfcheck.py" cylinder "$T/cyl.gltf"
models+=("$T/shapes.gltf" "$T/seam.gltf" "$T/quantized.gltf" "$T/morph.gltf" "$T/cyl.gltf")
check "found the sample models" [ ${#models[@]} -ge 15 ]
for f in "${models[@]}"; do
  name=$(basename "${f%.*}")
  outputs=()
  for m in $("$VNC" --list-methods | cut -d' ' -f1); do
    mkdir -p "$T/$name/$m"
    for out in "$T/$name/$m/$name.glb" "$T/$name/$m/${name}_out.gltf"; do
      check "$name -> $(basename "$out") ($m)" "$VNC" "$f" "$out" -m "$m" -q
      outputs+=("$out")
    done
  done
  check "$name: no new validator issues" node "$HERE/gltf/validate.mjs" "$MODULES" "$f" "${outputs[@]}"
  # Without tangents a normal-mapped material makes renderers generate them,
  # which the validator warns about: that is what --tangents drop asks for.
  drops=()
  for out in "$T/$name/drop.glb" "$T/$name/drop.gltf"; do
    check "$name -> $(basename "$out")" "$VNC" "$f" "$out" -q --tangents drop --weld-scope mesh
    drops+=("$out")
  done
  check "$name --tangents drop: no new validator issues" node "$HERE/gltf/validate.mjs" \
    --allow MESH_PRIMITIVE_GENERATED_TANGENT_SPACE "$MODULES" "$f" "${drops[@]}"
  # --crease-angle splits vertices: new accessors for every attribute, morph
  # target and the indices (the old ones are removed).
  creases=()
  for out in "$T/$name/crease.glb" "$T/$name/crease.gltf"; do
    check "$name -> $(basename "$out") --crease-angle" "$VNC" "$f" "$out" -q --crease-angle 30 \
      $([ "${out##*.}" = gltf ] && echo --weld-scope mesh)
    creases+=("$out")
  done
  check "$name --crease-angle: no new validator issues" node "$HERE/gltf/validate.mjs" "$MODULES" "$f" "${creases[@]}"
  # KHR_draco_mesh_compression: every primitive written uncompressed, or compressed.
  dracos=()
  for mode in off on; do
    for out in "$T/$name/draco-$mode.glb" "$T/$name/draco-$mode.gltf"; do
      check "$name -> $(basename "$out")" "$VNC" "$f" "$out" -q --draco $mode
      dracos+=("$out")
    done
  done
  # The validator does not read Draco data: it calls the compressed bufferView
  # unused and the extension unsupported, which --draco on cannot avoid.
  check "$name --draco off/on: no new validator issues" node "$HERE/gltf/validate.mjs" \
    --allow UNUSED_OBJECT --allow UNSUPPORTED_EXTENSION "$MODULES" "$f" "${dracos[@]}"
  check "$name --draco off: no new validator issues, information included" node "$HERE/gltf/validate.mjs" \
    "$MODULES" "$f" "${dracos[0]}" "${dracos[1]}"
done
# A material that needs a tangent space renderers cannot generate (an
# anisotropy texture, no normal map): its primitive keeps TANGENT, which
# the validator would otherwise miss (MESH_PRIMITIVE_NO_TANGENT_SPACE, an
# error), and a warning says why.
mkdir -p "$T/aniso" && cp "$DATA/sphere/"* "$T/aniso/"
python3 - "$T/aniso/sphere.gltf" <<'EOF'
import json, sys
doc = json.load(open(sys.argv[1]))
material = doc["materials"][0]
del material["normalTexture"]
material["extensions"] = {"KHR_materials_anisotropy": {"anisotropyStrength": 0.5, "anisotropyTexture": {"index": 0}}}
doc["extensionsUsed"] = ["KHR_materials_anisotropy"]
json.dump(doc, open(sys.argv[1], "w"))
EOF
run "$VNC" "$T/aniso/sphere.gltf" "$T/aniso.glb" --tangents drop --stats
check "--tangents drop, anisotropy without a normal map: TANGENT kept, saying why" [ "$rc|$(cat "$T/stderr")|$(grep '^tangent primitives' "$T/stdout" | tr -s ' ')" = "0|vnconvert: warning: 1 primitive keeps TANGENT despite --tangents drop: its material needs a tangent space (an anisotropy texture or a clearcoat normal map) and has no normal map to generate one from, so the file would be invalid without it (MESH_PRIMITIVE_NO_TANGENT_SPACE); it no longer matches the new normals|tangent primitives: 1 (0 dropped, 1 kept: needed)" ]
check "--tangents drop, anisotropy without a normal map: valid" node "$HERE/gltf/validate.mjs" "$MODULES" "$T/aniso/sphere.gltf" "$T/aniso.glb"
# OFF -> glTF is valid on its own.
"$VNC" "$HERE/../samples/sphere-quads.off" "$T/sq.glb" -q && "$VNC" "$HERE/../samples/torus.off" "$T/torus.gltf" -q
check "OFF -> GLB/glTF valid" node "$HERE/gltf/validate.mjs" "$MODULES" "$T/seam.gltf" "$T/sq.glb" "$T/torus.gltf"
# An empty mesh: a scene without nodes, no buffer.
printf 'ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n' >"$T/empty.ply"
"$VNC" "$T/empty.ply" "$T/empty.glb" -q && "$VNC" "$T/empty.ply" "$T/empty.gltf" -q
check "empty PLY -> GLB/glTF valid" node "$HERE/gltf/validate.mjs" "$MODULES" "$T/seam.gltf" "$T/empty.glb" "$T/empty.gltf"

finish
