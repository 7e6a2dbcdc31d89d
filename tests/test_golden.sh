#!/usr/bin/env bash
# Byte-for-byte outputs: converts every model in samples/ and tests/data/ with
# every method to every output format, plus the glTF and Draco options that
# take other code paths, and compares each output (every file written, the
# exit status, stdout and stderr) with the checksums in tests/data/golden.tsv.
# A change meant to leave behaviour alone (a refactoring) must pass as is; a
# change of behaviour re-records the cases it changes and says why.
#
#   test_golden.sh VNCONVERT            check (run from the repository root or tests/)
#   test_golden.sh VNCONVERT --record   write tests/data/golden.tsv anew
set -euo pipefail
VNCONVERT=$(realpath "$1")
MODE=${2:-check}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
MANIFEST=$ROOT/tests/data/golden.tsv
cd "$ROOT"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT

# The cases, one a line: input, output extension, options (space-separated, may be empty).
cases() {
	local inputs methods m in f
	inputs=$( { ls samples/*.off tests/data/off/*.off tests/data/gltf/*.glb tests/data/models/gltf/*.glb \
		tests/data/draco/*.drc tests/data/draco/*.obj tests/data/draco/*.ply tests/data/models/draco/*.drc \
		tests/data/obj/textured/grid.obj
		find tests/data/models/gltf -mindepth 2 -name '*.gltf'; } | LC_ALL=C sort)
	methods=$("$VNCONVERT" --list-methods | awk '{ print $1 }' | head -7)
	for in in $inputs; do
		for m in $methods; do
			for f in off gltf glb drc; do
				printf '%s\t%s\t--method %s\n' "$in" "$f" "$m"
			done
		done
		case $in in
		*.gltf | *.glb)
			for o in "--crease-angle 30" "--crease-angle 30 --method mwselr" "--no-weld" "--weld-scope mesh" \
				"--weld-epsilon 0.001" "--tangents drop" "--draco on" "--draco off" "--draco on --draco-qn 12 --draco-cl 4" \
				"--crease-angle 60 --draco on" "--weld-scope mesh --crease-angle 45"; do
				printf '%s\t%s\t%s\n' "$in" glb "$o"
			done
			printf '%s\t%s\t%s\n' "$in" gltf "--crease-angle 30"
			;;
		*.drc)
			printf '%s\t%s\t%s\n' "$in" drc "--draco-qp 11 --draco-qn 8"
			printf '%s\t%s\t%s\n' "$in" glb "--draco-qp 11"
			;;
		*.off)
			printf '%s\t%s\t%s\n' "$in" drc "--draco-qp 16 --draco-qn 12 --draco-qt 10 --draco-qc 6 --draco-cl 3"
			;;
		esac
	done
}

# One case: its line with the outputs' checksums.
run_case() {
	local in f opts dir status files streams
	IFS=$'\t' read -r in f opts <<<"$1"
	dir=$(mktemp -d "$T/c.XXXXXX")
	# shellcheck disable=SC2086 # opts are words
	status=0
	"$VNCONVERT" "$in" "$dir/out.$f" $opts >"$dir.stdout" 2>"$dir.stderr" || status=$?
	files=$(cd "$dir" && find . -type f | LC_ALL=C sort | xargs -r sha256sum | sha256sum | cut -c1-16)
	streams=$(cat "$dir.stdout" <(printf '\0') "$dir.stderr" | sed "s|$dir|OUTDIR|g" | sha256sum | cut -c1-16)
	rm -rf "$dir" "$dir.stdout" "$dir.stderr"
	printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$in" "$f" "$opts" "$status" "$files" "$streams"
}
export -f run_case
export VNCONVERT T

cases | xargs -d '\n' -n1 -P "$(nproc)" bash -c 'run_case "$0"' | LC_ALL=C sort >"$T/now.tsv"

if [ "$MODE" = --record ]; then
	{
		echo "# tests/test_golden.sh --record: input, output format, options, exit status, checksum of the files written, of stdout+stderr"
		cat "$T/now.tsv"
	} >"$MANIFEST"
	echo "golden: recorded $(wc -l <"$T/now.tsv") cases in tests/data/golden.tsv"
	exit 0
fi

grep -v '^#' "$MANIFEST" | LC_ALL=C sort >"$T/then.tsv"
if ! diff "$T/then.tsv" "$T/now.tsv" >"$T/diff"; then
	echo "FAIL: outputs differ from tests/data/golden.tsv (< recorded, > now):"
	head -40 "$T/diff"
	echo "golden: $(grep -c '^<' "$T/diff") of $(wc -l <"$T/then.tsv") cases differ"
	exit 1
fi
echo "golden: $(wc -l <"$T/now.tsv") cases, every output byte for byte as recorded"
