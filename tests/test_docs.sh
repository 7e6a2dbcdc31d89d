#!/usr/bin/env bash
# The documents stay true to the code:
#  - README.md's "What vnconvert keeps" table is what `vnconvert --list-conversions`
#    makes from the format table (src/io/format.c);
#  - every file docs/ARCHITECTURE.md names exists.
#   test_docs.sh VNCONVERT   (from the repository root or tests/)
set -u
VNC=$1
ROOT=$(cd "$(dirname "$0")/.." && pwd)
fail=0

table=$(sed -n '/^<!-- vnconvert --list-conversions -->$/,/^<!-- end of vnconvert --list-conversions -->$/p' "$ROOT/README.md" | sed '1d;$d')
if [ -z "$table" ]; then
	echo "FAIL: README.md has no table between the --list-conversions markers"
	fail=1
elif ! diff <(echo "$table") <("$VNC" --list-conversions) >/tmp/test_docs.$$; then
	echo "FAIL: README.md's 'What vnconvert keeps' differs from vnconvert --list-conversions (< README, > vnconvert):"
	cat /tmp/test_docs.$$
	fail=1
fi
rm -f /tmp/test_docs.$$

# Paths in backquotes that look like the project's files: src/..., tests/..., addons/..., filters/..., docs/..., .ci/...
names=$(grep -oE '`(src|tests|addons|filters|docs|samples|\.ci|cmake)/[A-Za-z0-9_./-]+`' "$ROOT/docs/ARCHITECTURE.md" | tr -d '`' | sort -u)
[ -n "$names" ] || { echo "FAIL: docs/ARCHITECTURE.md names no file"; fail=1; }
for n in $names; do
	[ -e "$ROOT/$n" ] || { echo "FAIL: docs/ARCHITECTURE.md names $n, which does not exist"; fail=1; }
done
[ $fail = 0 ] && echo "docs: README table matches the format table; docs/ARCHITECTURE.md names $(echo "$names" | wc -l) paths, all present"
exit $fail
