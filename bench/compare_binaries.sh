#!/usr/bin/env bash
# Two or more engine builds on the default study's small beds, to tell an engine regression from a
# slower host (issue 74: the default study's CPU rose 0.67 -> 0.92 core-hours between two hosts).
#
#   bench/compare_binaries.sh [--rounds N] BINARY_A BINARY_B [BINARY ...]
#
# Pours, with the first binary, the two beds the default study pulls through (config/config.yaml:
# system I, 10 d x 10 d, 1,500 grains, D = 2 at h = 6.5 d; system II, 14 d x 8 d, 3,000 grains,
# D = 3 at h = 10 d; K_n = 2e4, seed 1), then pulls each bed with every binary at the study's two
# kinds of pull (V = 1 over 5 d; a yield pull, V = 0.1 over 0.5 d), one thread, the binaries in an
# order that rotates every round (default 6), so that a shared machine's drift falls on all alike.
# Measures each pull's process CPU (user + system, /usr/bin/time): a job's cost as the workflow's
# benchmarks count it, start and output included. Prints per bed and pull the median CPU seconds of
# each binary and, per binary, the median and range of its per-round ratio to the first. The beds
# must be readable by every binary (pour with the oldest).
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=6
while [ $# -gt 0 ]; do
  case "$1" in
    --rounds) rounds=$2; shift 2 ;;
    -h | --help) sed -n '2,15p' "$0"; exit 0 ;;
    -*) echo "compare_binaries.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
    *) break ;;
  esac
done
[ $# -ge 2 ] || { echo "compare_binaries.sh: give two or more granudrag binaries (see --help)" >&2; exit 2; }
bins=()
for b in "$@"; do
  [ -x "$b" ] || { echo "compare_binaries.sh: no executable $b (build one: cmake -S SRC -B DIR && cmake --build DIR --target granudrag)" >&2; exit 1; }
  bins+=("$(realpath "$b")")
done
run=bench/out/compare_binaries
rm -rf "$run" && mkdir -p "$run"
n=${#bins[@]}
echo "pouring the two beds with ${bins[0]} ..." >&2
"${bins[0]}" pour --output "$run/bed1500.h5" --lx 10 --ly 10 --grains 1500 --intruder_diameter 2 --depth 6.5 \
  --kn 2e4 --ke_threshold 1e-6 --max_settle_time 40 --seed 1 --threads 1 --quiet >/dev/null
"${bins[0]}" pour --output "$run/bed3000.h5" --lx 14 --ly 8 --grains 3000 --intruder_diameter 3 --depth 10 \
  --kn 2e4 --ke_threshold 1e-6 --max_settle_time 40 --seed 1 --threads 1 --quiet >/dev/null
for r in $(seq "$rounds"); do
  echo "round $r of $rounds ..." >&2
  for bed in bed1500 bed3000; do
    for pull in "1 5" "0.1 0.5"; do
      read -r speed distance <<<"$pull"
      for k in $(seq 0 $((n - 1))); do
        i=$(((k + r) % n))
        OMP_NUM_THREADS=1 /usr/bin/time -o "$run/time.txt" -f "%U %S" "${bins[$i]}" pull --bed "$run/$bed.h5" \
          --output "$run/pull.h5" --speed "$speed" --distance "$distance" --snapshots 0 --threads 1 --quiet \
          >/dev/null 2>&1
        rm -f "$run"/pull.h5*
        echo "$r $i $bed $speed $(tail -n 1 "$run/time.txt")" >>"$run/cpu.txt"
      done
    done
  done
done
/usr/bin/python3 - "$run/cpu.txt" "${bins[@]}" <<'PYEOF'
import statistics as st
import sys
from collections import defaultdict

rows, bins = sys.argv[1], sys.argv[2:]
cpu = defaultdict(dict)                      # (bed, V, round) -> {binary: CPU s}
for line in open(rows):
    r, i, bed, v, user, system = line.split()
    cpu[(bed, v, r)][int(i)] = float(user) + float(system)
print("binaries: " + ", ".join(f"{i}: {b}" for i, b in enumerate(bins)))
for bed, v in sorted({k[:2] for k in cpu}):
    rounds = [c for k, c in cpu.items() if k[:2] == (bed, v) and len(c) == len(bins)]
    med = "  ".join(f"{i}: {st.median(c[i] for c in rounds):.3f} s" for i in range(len(bins)))
    print(f"{bed}, V = {v} ({len(rounds)} rounds): median CPU per pull  {med}")
    for i in range(1, len(bins)):
        q = [c[i] / c[0] for c in rounds]
        print(f"    {i} / 0: median {st.median(q):.3f}, range {min(q):.3f}-{max(q):.3f}")
PYEOF
