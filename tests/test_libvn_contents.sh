#!/usr/bin/env bash
# libvn holds normals only: no symbol of the paper library (libvnpaper.a:
# test ensemble, marching tetrahedra, Perlin noise) and none of its text is
# in libvn.so, in the libvn.so inside the Blender add-on's zip, or in the
# MeshLab plugin when it is built.
#   test_libvn_contents.sh LIBVN_SO LIBVNPAPER_A BLENDER_ZIP [PLUGIN_SO]
set -eu
so=$(realpath "$1") paper=$(realpath "$2") zip=$(realpath "$3") plugin=${4:+$(realpath "$4")}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
(cd "$T" && cmake -E tar xf "$zip")
binaries=("$so" "$T/vn_normals/lib/libvn.so")
[ -z "$plugin" ] || binaries+=("$plugin")

# Every global symbol the paper library defines, and text only it holds.
mapfile -t symbols < <(nm --defined-only "$paper" | awk '$2 ~ /^[TDBR]$/ { print $3 }' | sort -u)
[ "${#symbols[@]}" -ge 6 ] || { echo "FAIL: found only ${#symbols[@]} symbols in $paper"; exit 1; }
for s in vn_model_generate vn_marching_tetrahedra vn_perlin_noise; do
	printf '%s\n' "${symbols[@]}" | grep -qx "$s" || { echo "FAIL: $paper does not define $s"; exit 1; }
done
texts=("by marching tetrahedra" "height field of Perlin" "turbulence_mt")

fail=0
for b in "${binaries[@]}"; do
	[ -f "$b" ] || { echo "FAIL: $b is missing"; exit 1; }
	defined=$(nm --defined-only "$b" 2>/dev/null; nm -D --defined-only "$b")
	for s in "${symbols[@]}"; do
		if awk -v s="$s" '$NF == s { found = 1 } END { exit !found }' <<<"$defined"; then
			echo "FAIL: $b defines $s (paper library)"
			fail=1
		fi
	done
	for t in "${texts[@]}"; do
		if grep -qaF "$t" "$b"; then
			echo "FAIL: $b holds the paper library's text '$t'"
			fail=1
		fi
	done
done
[ "$fail" = 0 ] || exit 1
echo "libvn contents: ${#binaries[@]} binaries hold none of the paper library's ${#symbols[@]} symbols"
