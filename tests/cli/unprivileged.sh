#!/usr/bin/env bash
# The file guarantees as an ordinary user, where permissions hold (root ignores them, and every
# other test runs as root): an output directory that is not writable, an output or checkpoint
# that may not be replaced, an unreadable bed. Each ends in exit 1 and a message naming the
# file and the way out; the protected files are unchanged. Run as root, it drops to `nobody`
# with setpriv for every command; as another user, it runs them as that user. Prints the table
# of cases: case | exit code | message.
#   unprivileged.sh path/to/granudrag
set -uo pipefail
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
chmod 755 "$work"
if [ "$(id -u)" -eq 0 ]; then
  as_user() { setpriv --reuid=nobody --regid=nogroup --clear-groups -- "$@"; }
  owner=nobody:nogroup
else
  as_user() { "$@"; }
  owner=$(id -un):$(id -gn)
fi
# A copy of the binary the user can reach whatever the checkout's permissions (a clone under
# /root is not searchable by nobody).
cp "$gd" "$work/granudrag" && chmod 755 "$work/granudrag"
gd=$work/granudrag
as_user test -x "$gd" || { echo "unprivileged.sh: $gd is not executable as the test user" >&2; exit 1; }
expect() {  # expect CASE "what it should say" command...
  local what=$1 want=$2; shift 2
  local out code
  out=$(cd "$work" && as_user timeout 300 "$@" 2>&1); code=$?  # not capture: as_user is a function
  table "$what" "$code" "$(grep -F 'error' <<<"$out" | head -1)"
  said "$want" || { fail "$what: exit $code, expected 1 and a message containing '$want'; got:"; echo "$out"; }
}

mkdir ok && chown "$owner" ok
small=(--lx 8 --ly 8 --depth 2 --grains 400 --kn 2e4 --max_settle_time 1 --quiet)
as_user "$gd" pour --output ok/b.h5 "${small[@]}" >/dev/null 2>&1 || fail "a good pour as the test user failed"
as_user "$gd" pull --bed ok/b.h5 --output ok/r.h5 --distance 0.2 --quiet >/dev/null 2>&1 ||
  fail "a good pull as the test user failed"

# 1. An output directory the user may not write into: refused before any work.
mkdir locked && chown "$owner" locked && chmod 555 locked
expect "pull into a read-only directory" "locked" \
  "$gd" pull --bed ok/b.h5 --output locked/r.h5 --distance 0.2 --quiet
expect "pour into a read-only directory" "locked" "$gd" pour --output locked/b.h5 "${small[@]}"
[ -z "$(ls locked)" ] || fail "something was written into the read-only directory: $(ls locked)"

# 2. A bed the user may not read.
cp ok/b.h5 secret.h5 && chmod 600 secret.h5  # owned by root: unreadable to nobody
if [ "$(id -u)" -eq 0 ]; then
  expect "pull from an unreadable bed" "secret.h5" \
    "$gd" pull --bed secret.h5 --output ok/r2.h5 --distance 0.2 --quiet
  [ ! -e ok/r2.h5 ] || fail "a run file was written from an unreadable bed"
fi

# 3. An existing output the user may not replace (a read-only file in a directory it does not
# own): refused, the file unchanged.
mkdir kept && cp ok/r.h5 kept/r.h5 && chmod 444 kept/r.h5 && chmod 755 kept
sum=$(md5sum <kept/r.h5)
expect "pull over an output in a directory the user may not write" "kept" \
  "$gd" pull --bed ok/b.h5 --output kept/r.h5 --distance 0.2 --quiet
[ "$(md5sum <kept/r.h5)" = "$sum" ] || fail "the protected output changed"

# 4. An output the user made read-only (chmod a-w) in its own directory: kept, as cp and shells
# keep it, not replaced by the rename that writes outputs atomically.
cp ok/r.h5 ok/mine.h5 && chown "$owner" ok/mine.h5 && chmod 444 ok/mine.h5
sum=$(md5sum <ok/mine.h5)
expect "pull over a read-only output" "mine.h5" \
  "$gd" pull --bed ok/b.h5 --output ok/mine.h5 --distance 0.2 --quiet
[ "$(md5sum <ok/mine.h5)" = "$sum" ] || fail "the read-only output was replaced"

if [ "$fails" -gt 0 ]; then
  echo "FAIL: $fails case(s)"
  exit 1
fi
echo "PASS: as an unprivileged user, unwritable and unreadable files are refused by name and left as they were"
