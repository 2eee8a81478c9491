# shellcheck shell=bash
# The command-line tests' shared preamble, sourced by each tests/cli/*.sh after its `set` line:
#   . "$(dirname "$0")/lib.sh"      (the test's own arguments: path/to/granudrag [...])
# It sets
#   gd     the granudrag binary, an absolute path (the test's first argument)
#   work   a fresh temporary directory, made the current one; removed on exit, made writable
#          first (a test may leave read-only parts in it)
#   fails  0: the count of failed cases, for the tests that go on after a failure
# and defines
#   fail MESSAGE               print "FAIL: MESSAGE" and count it in fails
#   table CASE CODE MESSAGE    one row of a test's printed table of cases (MESSAGE cut to 300 bytes)
#   capture SECONDS COMMAND... run COMMAND for at most SECONDS: its output (stdout and stderr) in
#                              $out, its exit code in $code (the caller's locals, if it has them)
#   said WANT                  true when the command captured last exited 1 and its output
#                              contains WANT
#   wait_for_file FILE PID     until FILE exists or process PID has ended (600 s bounds only a hang)
#   same_dataset DATASET A B   true when DATASET is the same, bit for bit, in HDF5 files A and B
#   drag_of FILE               the drag of run file FILE, to 17 digits
if [ $# -lt 1 ]; then
  echo "usage: $(basename "$0") path/to/granudrag ..." >&2
  exit 2
fi
# shellcheck disable=SC2034  # gd is the sourcing test's
gd=$(realpath "$1") || exit 1
work=$(mktemp -d) || exit 1
trap 'chmod -R u+rwX "$work" 2>/dev/null; rm -rf "$work"' EXIT
cd "$work" || exit 1
fails=0

fail() { echo "FAIL: $*"; fails=$((fails + 1)); }

table() { printf '| %s | %s | %s |\n' "$1" "$2" "$(head -c 300 <<<"$3" | tr '\n' ' ')"; }

capture() {
  local seconds=$1
  shift
  if out=$(timeout "$seconds" "$@" 2>&1); then code=0; else code=$?; fi
}

said() { [ "$code" -eq 1 ] && grep -qF -- "$1" <<<"$out"; }

wait_for_file() {
  for _ in $(seq 6000); do
    { [ -f "$1" ] || ! kill -0 "$2" 2>/dev/null; } && return 0
    sleep 0.1
  done
}

same_dataset() {
  diff <(h5dump -m %.17g -d "$1" "$2" | tail -n +3) <(h5dump -m %.17g -d "$1" "$3" | tail -n +3) >/dev/null
}

drag_of() { h5dump -m %.17g -a /observables/drag/value "$1" | grep -A1 DATA | tail -1; }
