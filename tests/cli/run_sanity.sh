#!/usr/bin/env bash
# Runs that cannot be trusted are refused before any work, or stopped with exit 1 and their last
# checkpoint kept; prints each case as "input | message | exit code".
#   run_sanity.sh path/to/granudrag
set -uo pipefail
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
expect() {  # expect "what it should say" command...
  local want=$1; shift
  local out code
  capture 600 "$@"
  echo "${*/#$gd/granudrag} | $(grep -m1 -o 'error: .*' <<<"$out" | cut -c8-200) | $code"
  said "$want" || { fail "expected exit 1 and a message containing '$want'; got:"; echo "$out"; }
}
"$gd" pour --output b.h5 --lx 10 --ly 10 --grains 1200 --intruder_diameter 2 --depth 4 --kn 2e4 \
  --ke_threshold 1e-4 --max_settle_time 40 --quiet >/dev/null || { echo "FAIL: the pour failed"; exit 1; }
# Too fast for the bed (kn = 2e4, dt = 4.2e-4): refused at once with the largest speed that works.
expect "the largest speed that works is 6.58" "$gd" pull --bed b.h5 --output r.h5 --speed 1e6
expect "overlaps them by 0.50" "$gd" pull --bed b.h5 --output r.h5 --speed 50
expect "the largest speed that works is 6.58" "$gd" pull --bed b.h5 --output r.h5 --froude 20
expect "'max_overlap'" "$gd" pull --bed b.h5 --output r.h5 --speed 1 --max_overlap 0
expect "'max_overlap'" "$gd" pull --bed b.h5 --output r.h5 --speed 1 --max_overlap 0.7
expect "'max_overlap'" "$gd" pour --output p.h5 --grains 100 --lx 5 --ly 5 --depth 2 --max_overlap -1
expect "'checkpoint_interval'" "$gd" pour --output p.h5 --grains 100 --lx 5 --ly 5 --depth 2 --checkpoint_interval -1
# Within the speed limit, but the grain ahead of the intruder is pushed 0.113 d deep: stopped,
# no run file, the checkpoints written before are kept.
expect "exceeds max_overlap = 0.1 d" "$gd" pull --bed b.h5 --output r.h5 --speed 6 --distance 2 \
  --checkpoint_interval 0.02 --quiet
[ -f r.h5 ] && fail "a stopped pull left a run file"
[ -f r.h5.checkpoint.h5 ] || fail "the stopped pull's checkpoint is gone"
# A pour whose falling grains overlap the wall by more than its bound stops.
expect "exceeds max_overlap = 0.01 d" "$gd" pour --output p.h5 --lx 8 --ly 8 --grains 500 --depth 3 --kn 2e4 \
  --max_overlap 0.01 --checkpoint_interval 0.5 --quiet
[ -f p.h5 ] && fail "a stopped pour left a bed file"
[ -f p.h5.checkpoint.h5 ] || fail "the stopped pour's checkpoint (t = 0.5) is gone"
[ "$fails" -eq 0 ] && echo "PASS: every untrustworthy run was refused or stopped"
exit "$fails"
