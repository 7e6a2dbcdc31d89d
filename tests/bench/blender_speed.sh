#!/usr/bin/env bash
# Runs tests/bench/blender_speed.py in Blender 3.4 (the machine's blender)
# and in Blender 4.3 (the trixie chroot of .ci/blender43).
#   blender_speed.sh ZIP WORKDIR [ARGS for blender_speed.py, e.g. --runs 3 --small-only]
# Each version's output goes to WORKDIR/blender34.txt and WORKDIR/blender43.txt.
set -euo pipefail
zip=$(realpath "$1") work=$2; shift 2
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$work/34/home" "$work/34/config" "$work/34/scripts" "$work/34/tmp"
env HOME="$work/34/home" TMPDIR="$work/34/tmp" BLENDER_USER_CONFIG="$work/34/config" \
	BLENDER_USER_SCRIPTS="$work/34/scripts" \
	blender -b --factory-startup -noaudio --python-exit-code 1 --python "$here/blender_speed.py" -- \
	--zip "$zip" "$@" 2>&1 | tee "$work/blender34.txt"
bash "$here/../../.ci/blender43" "$zip" "$here/blender_speed.py" "$work/43" "$@"
cp "$work/43/blender43.log" "$work/blender43.txt"
