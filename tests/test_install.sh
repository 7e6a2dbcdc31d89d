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
