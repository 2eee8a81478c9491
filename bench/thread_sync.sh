#!/usr/bin/env bash
# Two builds of granudrag on the same threaded pull, under libgomp's default wait policy and
# under OMP_WAIT_POLICY=passive: how much the threads' synchronisation points per step (forks,
# joins, barriers) cost, and how steady the time is, on a machine whose cores are shared.
#
#   bench/thread_sync.sh OLD NEW [--bed BED.h5] [--runs N] [--threads T] [--distance L]
#
# OLD and NEW are granudrag binaries (e.g. build-ref/granudrag built from the commit before,
# build/granudrag). Pours the bed with NEW (3,000 grains in 12 d x 12 d, a D = 3 intruder at
# depth 6 d, K_n = 2e5), cached in bench/out/, or takes --bed. Then N rounds (default 5), each
# running `granudrag pull --froude 1 --threads T` (default 2) once per binary and policy, old
# and new alternating (their order swapped every round, so neither always runs first), and
# prints per binary and policy the median, least and greatest loop time (the pull's "timing:
# loop X s" line: the step loop without reading the bed or writing the run file) and their
# spread (greatest / least), the median of the per-round ratios new / old, and per binary
# passive / default (medians). --distance L pulls L d (default: one box length, 12 d). Each
# run's output is kept in bench/out/thread_sync/.
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 2 ] || { sed -n '2,17p' "$0"; exit 2; }
case "$1" in -h | --help) sed -n '2,17p' "$0"; exit 0 ;; esac
old=$(realpath "$1") new=$(realpath "$2")
shift 2
bed="" runs=5 threads=2 distance=0
while [ $# -gt 0 ]; do
  case "$1" in
    --bed) bed=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --distance) distance=$2; shift 2 ;;
    -h | --help) sed -n '2,17p' "$0"; exit 0 ;;
    *) echo "thread_sync.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
for gd in "$old" "$new"; do
  [ -x "$gd" ] || { echo "thread_sync.sh: $gd is not an executable" >&2; exit 2; }
done
out=bench/out/thread_sync
mkdir -p "$out"
if [ -z "$bed" ]; then
  bed=bench/out/bed-thread-sync.h5
  if [ ! -f "$bed" ]; then
    echo "pouring $bed (3,000 grains, 12 x 12 d) ..." >&2
    "$new" pour --output "$bed" --lx 12 --ly 12 --grains 3000 --intruder_diameter 3 --depth 6 --kn 2e5 \
      --ke_threshold 1e-5 --threads "$threads" --quiet >/dev/null
  fi
fi
bed=$(realpath "$bed")

times=$out/times.txt  # binary policy round seconds
: >"$times"
pull() {  # pull BINARY-LABEL POLICY ROUND
  local label=$1 policy=$2 round=$3 gd log
  gd=$old
  [ "$label" = new ] && gd=$new
  log=$out/$label-$policy-$round.log
  local env=(env -u OMP_WAIT_POLICY)
  [ "$policy" = passive ] && env=(env OMP_WAIT_POLICY=passive)
  "${env[@]}" "$gd" pull --bed "$bed" --output "$out/run.h5" --froude 1 --distance "$distance" \
    --threads "$threads" --quiet >"$log" 2>&1 || { echo "thread_sync.sh: $log:" >&2; cat "$log" >&2; exit 1; }
  local seconds
  seconds=$(sed -nE 's/^timing: loop ([0-9.eE+-]+) s .*/\1/p' "$log")
  [ -n "$seconds" ] || { echo "thread_sync.sh: no 'timing: loop' line in $log" >&2; exit 1; }
  echo "$label $policy $round $seconds" >>"$times"
  echo "round $round: $label, $policy wait policy: loop $seconds s" >&2
}
for round in $(seq "$runs"); do
  order="old new"
  [ $((round % 2)) -eq 0 ] && order="new old"
  for policy in default passive; do
    for label in $order; do pull "$label" "$policy" "$round"; done
  done
done
rm -f "$out/run.h5"

/usr/bin/python3 - "$times" "$threads" <<'EOF'
import statistics
import sys

rows = [line.split() for line in open(sys.argv[1])]
t = {}
for label, policy, rnd, seconds in rows:
    t.setdefault((label, policy), {})[int(rnd)] = float(seconds)
print(f"pull loop times (s), {sys.argv[2]} threads, {len(t[('old', 'default')])} per build and wait policy:")
print(f"{'binary':6} {'wait policy':11} {'median':>7} {'least':>7} {'most':>7} {'spread':>7}")
for label in ("old", "new"):
    for policy in ("default", "passive"):
        v = list(t[(label, policy)].values())
        print(f"{label:6} {policy:11} {statistics.median(v):7.3f} {min(v):7.3f} {max(v):7.3f} {max(v) / min(v):7.2f}")
for policy in ("default", "passive"):
    old, new = t[("old", policy)], t[("new", policy)]
    ratios = [new[r] / old[r] for r in old]
    print(f"new / old, {policy} wait policy: median of the per-round ratios {statistics.median(ratios):.3f} "
          f"(least {min(ratios):.3f}, most {max(ratios):.3f})")
for label in ("old", "new"):
    passive = statistics.median(t[(label, "passive")].values())
    default = statistics.median(t[(label, "default")].values())
    print(f"{label}: passive / default (medians) {passive / default:.3f}")
EOF
