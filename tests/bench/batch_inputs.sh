# Sourced by the batch benchmarks (batch_speed.sh, dask_speed.sh), with
# ROOT (the repository), VNC (vnconvert) and PEERS (../shared/bench/peers)
# set:
#
#   batch_inputs BASE IN
#
# makes IN, a folder of 200 mixed models: the samples and test files of this
# repository (OFF, OBJ, PLY, STL, GLB, .gltf with its buffer and texture,
# Draco) and jittered tori of 1,000 to 200,000 triangles
# (PEERS/genmesh.py, or the samples alone when it is missing), each
# converted with vnconvert itself into OFF, OBJ, PLY, STL, GLB and Draco
# copies (in BASE), numbered on to 200 files.
batch_inputs() {
  local base=$1 in=$2 k f stem ext files
  mkdir -p "$base" "$in"
  # The base models, each in its own folder (a .gltf keeps its files beside it).
  cp "$ROOT/samples/"*.off "$ROOT/tests/data/off/"*.off "$ROOT/tests/data/gltf/"*.glb "$base/"
  cp "$ROOT/tests/data/models/gltf/"*.glb "$ROOT/tests/data/draco/cube.drc" "$ROOT/tests/data/draco/colored.drc" "$base/"
  cp "$ROOT/tests/data/obj/blender_"*.obj "$ROOT/tests/data/obj/mat_test.obj" "$ROOT/tests/data/ply/blender_"*.ply \
    "$ROOT/tests/data/stl/test_sphere"*.stl "$base/"
  if [ -f "$PEERS/genmesh.py" ]; then
    for n in 1000 5000 20000 50000 200000; do python3 "$PEERS/genmesh.py" $n "$base/torus$n.off"; done
  fi
  # OFF, OBJ, PLY, STL, GLB and Draco copies of each (those a format cannot hold are left out).
  k=0
  for f in "$base/"*; do
    stem=$(basename "${f%.*}")
    for ext in off obj ply stl glb drc; do
      "$VNC" "$f" "$base/copies_$stem.$ext" -q 2>/dev/null || true
    done
  done
  mkdir "$in/Duck"
  cp "$ROOT/tests/data/models/gltf/Duck/"* "$in/Duck/"
  files=("$base/"*)
  while [ "$(find "$in" -name '*.off' -o -name '*.obj' -o -name '*.ply' -o -name '*.stl' -o -name '*.glb' -o -name '*.drc' -o -name '*.gltf' | wc -l)" -lt 200 ]; do
    f=${files[$((k % ${#files[@]}))]}
    cp "$f" "$in/$(printf %03d $k)_$(basename "$f")"
    k=$((k + 1))
  done
}
