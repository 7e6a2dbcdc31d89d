# Shared by the end-to-end test scripts (sourced): a scratch folder removed
# on exit, and pass/fail counting with the closing line ctest's log shows.
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }
# check WHAT CMD...: counts CMD's success; WHAT names it on failure.
check() { local what=$1; shift; if "$@"; then ok; else bad "$what"; fi; }
not() { ! "$@"; }
# quietly CMD...: CMD without its standard output (its status stays).
quietly() { "$@" >/dev/null; }
# run CMD...: sets $rc, $out (stdout) and $err (stderr); both also stay in $T.
run() { "$@" >"$T/stdout" 2>"$T/stderr"; rc=$?; out=$(cat "$T/stdout"); err=$(cat "$T/stderr"); }
one_line_err() { [ "$(wc -l <"$T/stderr")" -eq 1 ] && grep -q "^vnconvert: error: " "$T/stderr"; }
# check_rejected VNCONVERT BAD OUT KEEP: converting the bad input BAD exits 1
# with one line on stderr naming it, creates no OUT, and leaves an existing
# KEEP byte for byte as it was.
check_rejected() {
  local vnc=$1 bad=$2 none=$3 keep=$4 name
  name=$(basename "$bad")
  run "$vnc" "$bad" "$none"
  check "$name exits 1" [ $rc -eq 1 ]; check "$name: one line" one_line_err
  check "$name: names the file" grep -q "$name" "$T/stderr"
  check "$name: no output" [ ! -e "$none" ]
  echo precious >"$keep"
  run "$vnc" "$bad" "$keep"
  check "$name: existing output untouched" [ "$(cat "$keep")" = precious ]
}
# q FILE EXPR: EXPR (Python, over the document d) of a .gltf or .glb's JSON.
q() {
  python3 - "$1" "$2" <<'EOF'
import json, struct, sys
raw = open(sys.argv[1], "rb").read()
d = json.loads(raw[20:20 + struct.unpack("<I", raw[12:16])[0]] if raw[:4] == b"glTF" else raw)
print(eval(sys.argv[2]))
EOF
}
# The last command of a script: "N passed, N failed" and the exit status.
finish() { echo "$pass passed, $fail failed"; [ $fail -eq 0 ]; }
