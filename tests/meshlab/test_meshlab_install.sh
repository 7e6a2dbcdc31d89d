#!/usr/bin/env bash
# cmake --install puts libfilter_vn.so where MeshLab looks for plugins: with
# the configured prefix, into MeshLab's own plugin folder (checked here under
# DESTDIR); with another --prefix, into PREFIX/lib/<arch>/meshlab/plugins.
#   test_meshlab_install.sh BUILD_DIR PLUGIN_DIR
set -euo pipefail
B=$1 PLUGIN_DIR=$2
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail=0
DESTDIR="$T/destdir" cmake --install "$B" >/dev/null
if [ -f "$T/destdir$PLUGIN_DIR/libfilter_vn.so" ]; then echo "ok   DESTDIR install: $PLUGIN_DIR/libfilter_vn.so"
else echo "FAIL DESTDIR install: no $PLUGIN_DIR/libfilter_vn.so"; find "$T/destdir" -name 'libfilter_vn*'; fail=1; fi
cmake --install "$B" --prefix "$T/prefix" >/dev/null
got=$(cd "$T/prefix" && find . -name libfilter_vn.so)
if [ "$got" = "./lib/$(basename "$(dirname "$(dirname "$PLUGIN_DIR")")")/meshlab/plugins/libfilter_vn.so" ]; then
  echo "ok   --prefix install: PREFIX/${got#./}"
else echo "FAIL --prefix install: found '${got}'"; fail=1; fi
# loadable the way MeshLab loads it: every symbol resolved (built with -Wl,--no-undefined)
if LD_LIBRARY_PATH="$(dirname "$PLUGIN_DIR")" ldd -r "$T/prefix/${got#./}" 2>&1 | grep -q "undefined symbol"; then echo "FAIL undefined symbols"; fail=1
else echo "ok   no undefined symbols (ldd -r)"; fi
exit $fail
