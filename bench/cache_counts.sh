#!/usr/bin/env bash
# A pull's cost per particle-step counted, not timed: the instructions and the simulated cache
# misses of its steps (valgrind's cachegrind), per particle-step, for beds of any size. The counts
# are the same on every run of one build, so they settle what a timing on a shared machine cannot
# (docs/benchmark.md): whether a step touches memory as locally in a large bed as in a small one.
#   bench/cache_counts.sh [--l2 BYTES] [--steps A B] [--binary GRANUDRAG] BED.h5 [BED.h5 ...]
# Each bed is pulled (its intruder at V = 1, one thread, no output but the run file) for A and for
# B steps under cachegrind; the difference, over (B - A) x bodies, leaves out the start (reading
# the bed, the first list build, the checks of the end). Printed per particle-step, for the
# contact loop (the scan of the Verlet rows and the batched law), the integrator (its two passes)
# and the whole step: instructions (Ir), data reads and writes (Dr, Dw), misses in a 32 KiB L1
# (D1mr, D1mw) and in an L2 of --l2 bytes simulated as the last level (L2mr, L2mw; default 1 MiB,
# this development machine's per core). A miss of the simulated L2 is a line fetched from the next
# level, whatever that is on the machine that runs the bed: the counts say how much a step
# fetches, not what a fetch costs.
#   e.g. bench/cache_counts.sh bench/out/bed-7.7k.h5 bench/out/bed-70k.h5   (compare_lammps.sh's
#   recipe beds; 5-10 minutes on one core)
# Needs valgrind (apt-get install valgrind); uses build/granudrag (built if missing) or --binary.
set -euo pipefail
l2=1048576 steps_a=100 steps_b=400 beds=() gd=build/granudrag
while [ $# -gt 0 ]; do
  case "$1" in
    --l2) l2=$2; shift 2 ;;
    --steps) steps_a=$2 steps_b=$3; shift 3 ;;
    --binary) gd=$(realpath -m "$2"); shift 2 ;;
    -h | --help) sed -n '2,18p' "$0"; exit 0 ;;
    -*) echo "cache_counts.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
    *) beds+=("$(realpath -m "$1")"); shift ;;
  esac
done
cd "$(dirname "$0")/.."  # the beds and --binary are resolved from where the script was called
[ ${#beds[@]} -gt 0 ] || { echo "cache_counts.sh: name at least one bed file (see --help)" >&2; exit 2; }
[ "$steps_b" -gt "$steps_a" ] || { echo "cache_counts.sh: --steps A B needs B > A (got $steps_a $steps_b)" >&2; exit 2; }
[ "$gd" = build/granudrag ] || [ -x "$gd" ] || { echo "cache_counts.sh: --binary '$gd' is not an executable" >&2; exit 2; }
command -v valgrind >/dev/null || { echo "cache_counts.sh: valgrind not found: apt-get install valgrind" >&2; exit 1; }
[ "$gd" != build/granudrag ] || [ -x "$gd" ] || { cmake -S . -B build >/dev/null && cmake --build build -j "$(nproc)" >/dev/null; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for bed in "${beds[@]}"; do
  [ -f "$bed" ] || { echo "cache_counts.sh: no bed file '$bed'" >&2; exit 2; }
  dt=$(/usr/bin/python3 -c "import h5py; print(repr(float(h5py.File('$bed')['/contact'].attrs['dt'])))")
  name=$(basename "$bed" .h5)
  for steps in "$steps_a" "$steps_b"; do
    echo "cachegrind: $name, $steps steps ..." >&2
    # Half a step short of `steps` steps at V = 1: the pull rounds up to exactly that many.
    distance=$(/usr/bin/python3 -c "print(repr(($steps - 0.5) * $dt))")
    valgrind --tool=cachegrind --cache-sim=yes --D1=32768,8,64 --LL="$l2",16,64 \
      --cachegrind-out-file="$out/$name-$steps.cg" "$gd" pull --bed "$bed" --output "$out/$name-$steps.h5" \
      --speed 1 --fresh_start --distance "$distance" --snapshots 0 --checkpoint_interval 1e6 --threads 1 --quiet >"$out/$name-$steps.txt" 2>&1 ||
      { cat "$out/$name-$steps.txt" >&2; exit 1; }
  done
done
/usr/bin/python3 - "$out" "$steps_a" "$steps_b" "$l2" "${beds[@]}" <<'EOF'
import re, subprocess, sys, os
import h5py
out, a, b, l2, beds = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), sys.argv[5:]
EVENTS = ["Ir", "Dr", "Dw", "D1mr", "D1mw", "DLmr", "DLmw"]
GROUPS = {  # function names as cachegrind reports them
    "contact loop": ("VerletContacts::scan_rows", "VerletContacts::evaluate_batch", "evaluate_baseline",
                     "evaluate_avx2", "evaluate_avx512"),
    "integrator": ("Simulation::initial_integrate", "Simulation::final_integrate"),
}

def counts(path):
    """{group: {event: count}} of one cachegrind file, 'step' for the program's totals."""
    text = subprocess.run(["cg_annotate", "--threshold=0", "--auto=no", path], check=True,
                          capture_output=True, text=True).stdout
    shown = next(l.split(":", 1)[1].split() for l in text.splitlines() if l.startswith("Events shown:"))
    result = {g: dict.fromkeys(shown, 0) for g in [*GROUPS, "step"]}
    for line in text.splitlines():
        # A count, then its share in parentheses, which cg_annotate leaves out for a zero.
        m = re.match(r"^\s*((?:[\d,]+(?: \(\s*[\d.]+%\))?\s+)+)\S", line)
        numbers = re.findall(r"([\d,]+)(?: \(\s*[\d.]+%\))?", m.group(1)) if m else []
        if len(numbers) != len(shown):
            continue
        values = dict(zip(shown, (int(n.replace(",", "")) for n in numbers)))
        if "PROGRAM TOTALS" in line:
            result["step"] = values
            continue
        for group, names in GROUPS.items():
            if any(n in line for n in names):
                for e in shown:
                    result[group][e] += values[e]
    if any(result[g]["Ir"] == 0 for g in GROUPS):
        sys.exit(f"cache_counts.sh: {path} names no function of a part in GROUPS: the engine's names "
                 "changed, update GROUPS in bench/cache_counts.sh")
    return result

print(f"per particle-step, the difference of {a} and {b} steps; L1 32 KiB, L2 {l2 / 2**20:g} MiB (simulated)")
print(f"{'bed':24} {'bodies':>7} {'part':13}" + "".join(f"{e.replace('DL', 'L2'):>8}" for e in EVENTS))
for bed in beds:
    name = os.path.splitext(os.path.basename(bed))[0]
    with h5py.File(bed, "r") as f:
        bodies = f["/particles/all/position/value"].shape[-2]
    first, second = counts(f"{out}/{name}-{a}.cg"), counts(f"{out}/{name}-{b}.cg")
    for group in [*GROUPS, "step"]:
        per = [(second[group][e] - first[group][e]) / ((b - a) * bodies) for e in EVENTS]
        print(f"{name:24} {bodies:7d} {group:13}" + "".join(f"{x:8.2f}" for x in per))
EOF
