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
# The last command of a script: "N passed, N failed" and the exit status.
finish() { echo "$pass passed, $fail failed"; [ $fail -eq 0 ]; }
