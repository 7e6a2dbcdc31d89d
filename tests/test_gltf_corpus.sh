#!/usr/bin/env bash
# Public files (tests/data/corpus, 64 chosen from about 3,000 for their
# variety): each converts to .glb and to .gltf in another folder, with
# default options, and neither output has a Khronos glTF-Validator code the
# input did not have. The exceptions are stated below, with their reason.
#   test_gltf_corpus.sh PATH/TO/vnconvert NODE_MODULES_DIR
set -u
VNC=$1
MODULES=$2
HERE=$(cd "$(dirname "$0")" && pwd)
C=$HERE/data/corpus
. "$HERE/lib.sh"
if [ ! -d "$MODULES/gltf-validator" ]; then
  echo "FAIL: $MODULES/gltf-validator is missing: run .ci/setup (npm install gltf-validator)"
  exit 1
fi

# Images a GLB's bufferView may not hold (a Basis Universal file, a KTX2
# without KHR_texture_basisu) stay files beside the GLB: URI_GLB (information).
declare -A glb_allows=(
  ["mosra+magnum-plugins/src/MagnumPlugins/GltfImporter/Test/image-basis.gltf"]=URI_GLB
  ["KhronosGroup+glTF-Validator/test/base/data/image/unrecognized_format.gltf"]=URI_GLB
)
# Files with no geometry data at all (a buffer without uri, nothing giving it
# data), refused in one line: every output, or the .glb (its buffer 0
# would be a BIN chunk). Output type, then what the line says.
declare -A refused=(
  ["CesiumGS+3d-tiles-tools/specs/data/migration/golden_gltf/Composite/Composite/composite.gltf"]="glb gltf:bufferViews\[0\] is in buffers\[0\], which has no data"
  ["microsoft+glTF-SDK/GLTFSDK.Test/Resources/gltf/Transforms.gltf"]="glb:buffers\[0\] has no data .*write .gltf"
)

count=0
while IFS= read -r in; do
  rel=${in#"$C/"}
  name=$(echo "$rel" | tr '/ ' '__')
  dir=$T/$name
  mkdir -p "$dir"
  count=$((count + 1))
  expect=${refused[$rel]:-}
  for e in glb gltf; do
    run "$VNC" -q "$in" "$dir/out.$e"
    if [[ " ${expect%%:*} " == *" $e "* ]]; then
      check "$rel -> .$e: refused in one line" one_line_err
      check "$rel -> .$e: says why" grep -q "${expect#*:}" "$T/stderr"
      check "$rel -> .$e: nothing written" [ ! -e "$dir/out.$e" ]
      continue
    fi
    check "$rel -> .$e: exit 0 ($(head -c 300 "$T/stderr"))" [ $rc -eq 0 ]
    allow=()
    [ $e = glb ] && [ -n "${glb_allows[$rel]:-}" ] && allow=(--allow "${glb_allows[$rel]}")
    check "$rel -> .$e: no new validator code" quietly node "$HERE/gltf/validate.mjs" "${allow[@]}" "$MODULES" "$in" "$dir/out.$e"
  done
done < <(find "$C" \( -name '*.gltf' -o -name '*.glb' \) | LC_ALL=C sort)
check "found the corpus ($count files)" [ $count -ge 60 ]

finish
