#!/usr/bin/env bash
# How the cost of a particle-step grows with the bed's size (issue 29: "within 5 % from 7.7k to
# 70k bodies"), measured in one run so that a shared machine's drift falls on both sizes alike.
#
#   bench/size_growth.sh [--rounds N] [--threads T] [--lammps] [--small BED.h5] [--large BED.h5]
#                        [--binary build/granudrag]
#
# Takes the two beds of bench/compare_lammps.sh's recipe (bench/out/bed-7.7k.h5 and bed-70k.h5;
# run `bench/compare_lammps.sh --size 7.7k` and `--size 70k` once to pour them, or pass --small
# and --large) and pulls the intruder through each as that bench does (V = 1, 4,000 steps on the
# small bed and 1,000 on the large one, the springs dropped, a study's sampling and one
# checkpoint), N rounds (default 4), the two sizes alternating and their order swapped every
# round. --lammps adds LAMMPS (`gran/hertz/history`, the bed exported with `granudrag
# export-lammps`) on T MPI ranks to each round, so both codes' growth comes from the same rounds.
# Prints per code and size the loop's cost per particle-step (ns; for T > 1 threads, core-ns:
# wall time x T), the growth large / small per round (median, least, greatest), also for
# granudrag less its one checkpoint (a cost per run, which the large bed's 4x fewer steps weigh
# 4x as much per particle-step; LAMMPS writes none), and granudrag's phases per particle-step
# (its "timing: loop" line).
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=4 threads=1 lammps="" small=bench/out/bed-7.7k.h5 large=bench/out/bed-70k.h5 gd=build/granudrag
while [ $# -gt 0 ]; do
  case "$1" in
    --rounds) rounds=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --lammps) lammps=1; shift ;;
    --small) small=$2; shift 2 ;;
    --large) large=$2; shift 2 ;;
    --binary) gd=$2; shift 2 ;;
    -h | --help) sed -n '2,19p' "$0"; exit 0 ;;
    *) echo "size_growth.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
for b in "$small" "$large"; do
  [ -f "$b" ] || { echo "size_growth.sh: no bed $b: pour it with bench/compare_lammps.sh --size 7.7k (or 70k), or pass --small/--large" >&2; exit 1; }
done
[ -x "$gd" ] || { echo "size_growth.sh: no binary $gd: cmake -S . -B build && cmake --build build -j" >&2; exit 1; }
[ -z "$lammps" ] || command -v lmp >/dev/null || { echo "size_growth.sh: --lammps needs LAMMPS: apt-get install lammps openmpi-bin" >&2; exit 1; }
gd=$(realpath "$gd")
run=bench/out/size_growth
rm -rf "$run" && mkdir -p "$run"
mpi_root=""
[ "$(id -u)" -eq 0 ] && mpi_root="--allow-run-as-root"
# shellcheck source=bench/recipe_pull.sh
. bench/recipe_pull.sh

# Per size: the bed, its steps, and the pull's arguments (bench/compare_lammps.sh's pull).
declare -A bed steps args
bed[small]=$(realpath "$small") steps[small]=4000
bed[large]=$(realpath "$large") steps[large]=1000
for s in small large; do
  recipe_pull "$gd" "${bed[$s]}" "${steps[$s]}" 1
  args[$s]="--distance $distance --sample_interval $interval --checkpoint_interval $checkpoint"
  if [ -n "$lammps" ]; then
    mkdir -p "$run/$s"
    "$gd" export-lammps --bed "${bed[$s]}" --output "$run/$s/pull" --speed 1 --steps "${steps[$s]}" --every "$every" >/dev/null
  fi
done

for k in $(seq "$rounds"); do
  order="small large"
  [ $((k % 2)) -eq 1 ] || order="large small"
  for s in $order; do
    echo "round $k of $rounds: $s bed ..." >&2
    # shellcheck disable=SC2086  # args holds several options
    OMP_NUM_THREADS=$threads "$gd" pull --bed "${bed[$s]}" --output "$run/gd.h5" --speed 1 --fresh_start \
      --snapshots 0 --threads "$threads" --quiet ${args[$s]} >"$run/gd-$s-$k.txt"
    rm -f "$run/gd.h5"
    [ -z "$lammps" ] || (cd "$run/$s" && OMP_NUM_THREADS=1 mpirun $mpi_root -np "$threads" lmp -in pull.in \
      -log "lmp-$k.log" -screen none)
  done
done

/usr/bin/python3 - "$run" "$rounds" "$threads" "${lammps:-0}" <<'PYEOF'
import re
import statistics as st
import sys
from pathlib import Path

run, rounds, threads, lammps = Path(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), sys.argv[4] == "1"

def gd(size, k):
    t = (run / f"gd-{size}-{k}.txt").read_text()
    m = re.search(r"timing: loop ([\d.e+-]+) s for (\d+) steps, ([\d.e+-]+) particle-steps/s;(.*) s$", t, re.M)
    loop, steps, rate = float(m.group(1)), int(m.group(2)), float(m.group(3))
    ps = rate * loop  # particle-steps
    phases = {name: float(v) * threads / ps * 1e9 for name, v in re.findall(r"(\S+) ([\d.e+-]+)", m.group(4))}
    return loop * threads / ps * 1e9, phases, ps

def lmp(size, k, ps):
    t = (run / size / f"lmp-{k}.log").read_text()
    return float(re.search(r"^Loop time of ([\d.e+-]+)", t, re.M).group(1)) * threads / ps * 1e9

cores = "core-" if threads > 1 else ""
print(f"# cost per particle-step of the loop ({cores}ns; {threads} thread(s)/rank(s)), {rounds} rounds, sizes alternating")
print("| code | small bed | large bed | growth large / small: median (least-greatest) |")
print("|---|---|---|---|")
codes = {"granudrag": {}}
for s in ("small", "large"):
    codes["granudrag"][s] = [gd(s, k) for k in range(1, rounds + 1)]
# The bench's one checkpoint is a cost per run, not per step: spread over 1,000 steps of the
# large bed and 4,000 of the small one, it weighs 4x as much per particle-step in the large.
codes["granudrag, less its checkpoint (I/O)"] = {
    s: [x[0] - x[1].get("I/O", 0.0) for x in codes["granudrag"][s]] for s in ("small", "large")}
if lammps:
    codes["LAMMPS"] = {s: [lmp(s, k, codes["granudrag"][s][k - 1][2]) for k in range(1, rounds + 1)]
                       for s in ("small", "large")}
for name, by in codes.items():
    cost = {s: [x[0] if isinstance(x, tuple) else x for x in by[s]] for s in by}
    growth = [b / a for a, b in zip(cost["small"], cost["large"])]
    print(f"| {name} | {st.median(cost['small']):.1f} ({min(cost['small']):.1f}-{max(cost['small']):.1f}) | "
          f"{st.median(cost['large']):.1f} ({min(cost['large']):.1f}-{max(cost['large']):.1f}) | "
          f"**{st.median(growth):.3f}×** ({min(growth):.3f}-{max(growth):.3f}) |")
for s in ("small", "large"):
    runs = codes["granudrag"][s]
    names = [n for n in runs[0][1] if st.median(r[1][n] for r in runs) > 0]
    print(f"#   granudrag, {s} bed, {cores}ns per particle-step by phase (medians): " +
          ", ".join(f"{n} {st.median(r[1][n] for r in runs):.1f}" for n in names))
PYEOF
