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
echo "install: 1 passed, 0 failed"
