#!/usr/bin/env bash
# Installs the build into a scratch prefix, then builds and runs a consumer
# through find_package(vn) (shared and static) and through pkg-config, and
# checks that libvn.so exports nothing but the vn_ API.
#   test_install.sh BUILD_DIR SOURCE_DIR
set -eu
B=$1 S=$2
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cmake --install "$B" --prefix "$T/prefix" >/dev/null
lib=$(find "$T/prefix" -name 'libvn.so.*.*.*' | head -1)
[ -f "$T/prefix/include/vn.h" ] || { echo "FAIL: vn.h not installed"; exit 1; }
[ -n "$lib" ] || { echo "FAIL: libvn.so not installed"; exit 1; }
[ -n "$(find "$T/prefix" -name libvn.a)" ] || { echo "FAIL: libvn.a not installed"; exit 1; }

other=$(nm -D --defined-only "$lib" | awk '$2 ~ /^[TDBR]$/ && $3 !~ /^vn_/ { print $3 }')
[ -z "$other" ] || { echo "FAIL: libvn.so exports non-API symbols: $other"; exit 1; }
# Exactly the functions vn.h declares with VN_API.
declared=$(grep -oE '^VN_API [^(]*\b(vn_[a-z0-9_]+)\(' "$S/src/vn.h" | grep -oE 'vn_[a-z0-9_]+\($' | tr -d '(' | sort)
exported=$(nm -D --defined-only "$lib" | awk '$3 ~ /^vn_/ { print $3 }' | sort)
[ -n "$declared" ] && [ "$declared" = "$exported" ] || { echo "FAIL: exported API differs from vn.h:"; diff <(echo "$declared") <(echo "$exported"); exit 1; }

# libvnio.so, for bindings: exactly the functions vn_io.h and vn_convert.h
# mark VN_IO_API, and it converts when loaded from the prefix alone (it
# finds libvn.so beside it).
io=$(find "$T/prefix" -name 'libvnio.so.*.*.*' | head -1)
[ -n "$io" ] || { echo "FAIL: libvnio.so not installed"; exit 1; }
declared=$(grep -hoE '^VN_IO_API [^(]*\b(vn_[a-z0-9_]+)\(' "$S/src/io/vn_io.h" "$S/src/io/vn_convert.h" | grep -oE 'vn_[a-z0-9_]+\($' | tr -d '(' | sort)
exported=$(nm -D --defined-only "$io" | awk '$2 != "A" { print $3 }' | sort)
[ -n "$declared" ] && [ "$declared" = "$exported" ] || { echo "FAIL: libvnio.so's exports differ from VN_IO_API:"; diff <(echo "$declared") <(echo "$exported"); exit 1; }
env -u LD_LIBRARY_PATH python3 - "$io" "$S/samples/torus.off" "$T/torus.glb" <<'PY' || { echo "FAIL: libvnio.so from the prefix"; exit 1; }
import ctypes, sys
lib = ctypes.CDLL(sys.argv[1])
error = ctypes.create_string_buffer(512)
status = lib.vn_io_convert(sys.argv[2].encode(), sys.argv[3].encode(), None, None, error)
assert status == 0, (status, error.value)
assert open(sys.argv[3], "rb").read(4) == b"glTF"
PY

cmake -S "$S/tests/consumer" -B "$T/consumer" -DCMAKE_PREFIX_PATH="$T/prefix" >/dev/null
cmake --build "$T/consumer" >/dev/null
LD_LIBRARY_PATH="$T/prefix/lib:$T/prefix/lib64" "$T/consumer/consumer" | grep -qx "success 0 0 1" || { echo "FAIL: shared consumer"; exit 1; }
"$T/consumer/consumer_static" | grep -qx "success 0 0 1" || { echo "FAIL: static consumer"; exit 1; }

pc=$(find "$T/prefix" -name vn.pc | head -1)
export PKG_CONFIG_PATH=$(dirname "$pc")
[ "$(pkg-config --modversion vn)" = "$(awk '/^#define VN_VERSION_STRING/ { gsub(/"/, "", $3); print $3 }' "$S/src/vn.h")" ] || { echo "FAIL: vn.pc version"; exit 1; }
cc -o "$T/pc" "$S/tests/consumer/main.c" $(pkg-config --define-variable=prefix="$T/prefix" --cflags --libs vn)
LD_LIBRARY_PATH=$(dirname "$lib") "$T/pc" | grep -qx "success 0 0 1" || { echo "FAIL: pkg-config consumer"; exit 1; }
# The Python package beside the library: /usr/bin/python3 imports it from the
# prefix's dist-packages and loads the installed libvn, no VN_LIBRARY needed.
py=$(find "$T/prefix" -path '*-packages/vn/__init__.py' | head -1)
[ -n "$py" ] && [ -f "$(dirname "$py")/_install.py" ] || { echo "FAIL: Python package not installed"; exit 1; }
got=$(cd "$T" && env -u VN_LIBRARY PYTHONPATH="$(dirname "$(dirname "$py")")" /usr/bin/python3 -c \
  'import vn; print(vn.library().path); print(vn.vertex_normals([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]]).tolist())')
[ "$got" = "$(readlink -f "$lib" | sed 's/\.[0-9]*$//')
[[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0]]" ] || { echo "FAIL: installed Python package: $got"; exit 1; }
# vn.convert through the installed libvnio.so (found beside libvn): the bytes
# of the conversion libvnio.so made above.
(cd "$T" && env -u VN_LIBRARY -u VN_LIBVNIO PYTHONPATH="$(dirname "$(dirname "$py")")" /usr/bin/python3 -c \
  'import sys, vn; vn.convert(sys.argv[1], "py.glb")' "$S/samples/torus.off") && cmp -s "$T/py.glb" "$T/torus.glb" \
  || { echo "FAIL: vn.convert of the installed package"; exit 1; }
# vn.dask installed with it: a batch on a local cluster, vnconvert's bytes.
if /usr/bin/python3 -c 'import distributed' 2>/dev/null; then
  (cd "$T" && env -u VN_LIBRARY -u VN_LIBVNIO PYTHONPATH="$(dirname "$(dirname "$py")")" /usr/bin/python3 -m vn.dask \
    --local 1 -q --out-dir dask -f glb "$S/samples/torus.off") && cmp -s "$T/dask/torus.glb" "$T/torus.glb" \
    || { echo "FAIL: python3 -m vn.dask of the installed package"; exit 1; }
fi
# pip install --no-build-isolation of python/ (a copy: pip writes build/ beside it) into a venv
if /usr/bin/python3 -m venv --system-site-packages "$T/venv" 2>/dev/null; then
  cp -r "$S/python" "$T/python"
  "$T/venv/bin/pip" install -q --no-index --no-build-isolation "$T/python" >/dev/null || { echo "FAIL: pip install ./python"; exit 1; }
  v=$(cd "$T" && VN_LIBRARY="$lib" "$T/venv/bin/python" -c 'import vn; print(vn.__version__, vn.__file__)')
  case $v in "$(pkg-config --modversion vn) $T/venv/"*) ;; *) echo "FAIL: pip-installed package: $v"; exit 1 ;; esac
fi
echo "install: 1 passed, 0 failed"
