#!/usr/bin/env bash
# Runs tests/blender/test_addon.py in Blender, headless, with HOME,
# BLENDER_USER_* and TMPDIR in a fresh folder of the build tree.
#   run.sh host ZIP WORKDIR      the machine's blender (Debian bookworm: 3.4)
#   run.sh trixie ZIP WORKDIR    Blender 4.3 in the trixie chroot (.ci/blender43)
set -euo pipefail
mode=$1 zip=$2 work=$3
here=$(cd "$(dirname "$0")" && pwd)
[ -f "$zip" ] || { echo "no add-on zip at $zip (cmake --build builds it)" >&2; exit 1; }
case $mode in
host)
	command -v blender >/dev/null || { echo "blender is not installed (bash .ci/setup installs it)" >&2; exit 1; }
	rm -rf "$work" && mkdir -p "$work/home" "$work/config" "$work/scripts" "$work/datafiles" "$work/tmp"
	env HOME="$work/home" TMPDIR="$work/tmp" BLENDER_USER_CONFIG="$work/config" \
		BLENDER_USER_SCRIPTS="$work/scripts" BLENDER_USER_DATAFILES="$work/datafiles" \
		BLENDER_USER_EXTENSIONS="$work/extensions" \
		blender -b --factory-startup -noaudio --python-exit-code 1 --python "$here/test_addon.py" -- --zip "$zip"
	;;
trixie)
	exec bash "$here/../../.ci/blender43" "$zip" "$here/test_addon.py" "$work"
	;;
*) echo "usage: $0 host|trixie ZIP WORKDIR" >&2; exit 2 ;;
esac
