#!/usr/bin/env bash
# granudrag vs LAMMPS gran/hertz/history on the real workload: the pull of an intruder through a
# poured bed, the same bed, contact law, steps and force sampling in both codes.
#
#   bench/compare_lammps.sh [--size quick|7.7k|30k|70k] [--bed BED.h5] [--steps N] [--pairs P]
#                           [--cores "1 2"] [--every K] [--binary build/granudrag]
#                           [--speed V] [--active_radius R [--sleep_time T]]
#                           [--poured_by granudrag|lammps] [--keep_history]
#
# 1. Pours the bed with `granudrag pour` (grains 0.9-1.1 d, frozen base, a D = 2 intruder at
#    depth 9 d, K_n = 2e5 with the paper's ratios, dt = 5e-4), cached in bench/out/, or takes --bed.
#    --poured_by lammps pours it with LAMMPS instead (bench/lammps_pour.in, the same recipe with
#    fix pour) and imports it with `granudrag import-lammps` (which sorts it): a bed from elsewhere.
# 2. Exports it with `granudrag export-lammps` (data file + input running the same pull).
# 3. Times the pull, whole process (/usr/bin/time) and loop alone (granudrag's "timing:" line,
#    LAMMPS's "Loop time"), granudrag on 1 and 2 OpenMP threads, LAMMPS (Debian's `lmp`, no
#    OPENMP package) on 1 and 2 MPI ranks, interleaved: granudrag, LAMMPS, granudrag, LAMMPS ...
#    for P pairs per core count. Prints the medians, the median of the per-pair ratios, peak
#    memory and bytes per particle, and granudrag's time split by phase.
# Both codes average the force on the intruder over K steps (granudrag --sample_interval K dt,
# LAMMPS fix ave/time); K defaults to a study's sampling, `granudrag pull`'s default
# sample_interval (0.02 sqrt(d/g), 40 steps at dt = 5e-4), at the end of which granudrag also
# runs its checks (non-finite numbers, lost grains, overlap, energy) and coordination numbers.
# granudrag writes one checkpoint, half-way: more than a study's pull
# writes in as many steps (the workflow asks for one per `checkpoint_minutes` of wall time, 60
# by default; a pull of one box length with no interval given writes one per tenth of it, 4,000
# steps on the 7.7k bed), where `granudrag pull`'s default for these short distances would
# write ten. OMP_WAIT_POLICY is passed through unchanged (libgomp's default: spin, then sleep);
# on a machine shared with other jobs OMP_WAIT_POLICY=passive gives steadier figures, but where
# sleeping threads wake slowly (a virtual machine: about 22 us a barrier, 2026-12-05) it costs
# the 2-thread pull a quarter of its speed: time 2 threads at the default policy.
# --speed V pulls at V (sqrt(g d); default 1), e.g. 0.03 for a yield pull. --active_radius R adds
# a third command to each round, the same granudrag pull with `--active_radius R` (grains
# farther than R d from the intruder may fall asleep; they need sleep_time, 1 sqrt(d/g) = 2,000
# steps here, at rest first, so give --steps well past that), and prints its loop time against
# the pull without the region and against LAMMPS, with the mean and final fraction of the
# bodies asleep (the run file's /observables/sleeping_grains), and the same for the second half
# of the steps alone (`granudrag pull`'s "timing: second half" line), the steady cost once the bed
# has fallen asleep. --sleep_time T gives that pull `--sleep_time T` (config/faithful.yaml's 0.5).
# granudrag starts like LAMMPS after read_data, the bed's tangential springs dropped
# (`--fresh_start`); --keep_history starts it from them instead, as a study's pulls start. A bed
# whose springs are dropped slips and re-settles for about 10 time units before an active region
# can hold it (measured on a 70,000-grain bed at rest), so time the region with --keep_history.
# Needs: apt-get install lammps openmpi-bin.
set -euo pipefail
cd "$(dirname "$0")/.."
size=7.7k bed="" steps="" pairs=3 cores="1 2" every="" gd=build/granudrag speed=1 radius="" dwell="" poured_by=granudrag
fresh=--fresh_start
while [ $# -gt 0 ]; do
  case "$1" in
    --size) size=$2; shift 2 ;;
    --bed) bed=$2; shift 2 ;;
    --steps) steps=$2; shift 2 ;;
    --pairs) pairs=$2; shift 2 ;;
    --cores) cores=$2; shift 2 ;;
    --every) every=$2; shift 2 ;;
    --binary) gd=$2; shift 2 ;;
    --speed) speed=$2; shift 2 ;;
    --active_radius) radius=$2; shift 2 ;;
    --sleep_time) dwell=$2; shift 2 ;;
    --poured_by) poured_by=$2; shift 2 ;;
    --keep_history) fresh=""; shift ;;
    -h | --help) sed -n '2,42p' "$0"; exit 0 ;;
    *) echo "compare_lammps.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
case "$size" in  # grains, box side (d), default steps
  quick) set -- 2000 12 1000 ;;
  7.7k) set -- 7700 20 4000 ;;
  30k) set -- 30000 40 2000 ;;
  70k) set -- 70000 60 1000 ;;
  *) echo "compare_lammps.sh: --size must be quick, 7.7k, 30k or 70k (got '$size')" >&2; exit 2 ;;
esac
grains=$1 side=$2
steps=${steps:-$3}
case "$poured_by" in
  granudrag | lammps) ;;
  *) echo "compare_lammps.sh: --poured_by must be granudrag or lammps (got '$poured_by')" >&2; exit 2 ;;
esac
command -v lmp >/dev/null || { echo "LAMMPS not found: apt-get install lammps openmpi-bin" >&2; exit 1; }
[ -x "$gd" ] || { cmake -S . -B build >/dev/null && cmake --build build -j "$(nproc)" >/dev/null; }
gd=$(realpath "$gd")
out=bench/out
mkdir -p "$out"
if [ -z "$bed" ] && [ "$poured_by" = lammps ]; then
  bed=$out/bed-$size-lammps.h5
  if [ ! -f "$bed" ]; then
    # The intruder's centre 9 d below the surface: grains of mean volume 0.529 d^3 settle to a
    # packing of 0.62 in this recipe (7,700 grains in 20 d x 20 d: surface at 16.4 d).
    zi=$(/usr/bin/python3 -c "print(round(0.529 * $grains / (0.62 * $side * $side) - 9, 2))")
    echo "pouring $bed with LAMMPS ($grains grains, $side x $side d, intruder at z = $zi d) ..." >&2
    (cd "$out" && lmp -in ../lammps_pour.in -log "lammps_pour-$size.log" -screen none -var grains "$grains" \
      -var side "$side" -var zi "$zi" -var kn 2e5 -var dt 5e-4 -var data "bed-$size-lammps.data")
    "$gd" import-lammps --data "$out/bed-$size-lammps.data" --output "$bed" --kn 2e5 --dt 5e-4 >&2
  fi
elif [ -z "$bed" ]; then
  bed=$out/bed-$size.h5
  if [ ! -f "$bed" ]; then
    echo "pouring $bed ($grains grains, $side x $side d) ..." >&2
    "$gd" pour --output "$bed" --grains "$grains" --lx "$side" --ly "$side" --intruder_diameter 2 \
      --depth 9 --kn 2e5 --dt 5e-4 --ke_threshold 1e-4 --max_settle_time 15 --quiet >/dev/null
  fi
fi
bed=$(realpath "$bed")
label="$size"  # the bed's name in the table: the recipe's size, or the file given with --bed
[ "$bed" = "$(realpath "$out/bed-$size.h5")" ] || label=$(basename "$bed")
[ "$bed" != "$(realpath -m "$out/bed-$size-lammps.h5")" ] || label="$size, poured by LAMMPS"
# shellcheck source=bench/recipe_pull.sh
. bench/recipe_pull.sh
recipe_pull "$gd" "$bed" "$steps" "$speed" "$every"
run=$out/run-$size
rm -rf "$run" && mkdir -p "$run"
"$gd" export-lammps --bed "$bed" --output "$run/pull" --speed "$speed" --steps "$steps" --every "$every" >/dev/null
mpi_root=""
[ "$(id -u)" -eq 0 ] && mpi_root="--allow-run-as-root"

run_gd() {  # threads tag [extra pull options]: the run file is kept only with extra options
  local threads=$1 tag=$2
  shift 2
  OMP_NUM_THREADS=$threads /usr/bin/time -f "%e %M" -o "$run/gd$tag.time" "$gd" pull --bed "$bed" \
    --output "$run/gd$tag.h5" --speed "$speed" $fresh --distance "$distance" \
    --sample_interval "$interval" --checkpoint_interval "$checkpoint" --snapshots 0 \
    --threads "$threads" --quiet "$@" >"$run/gd$tag.txt"
  [ $# -gt 0 ] || rm -f "$run/gd$tag.h5"
}
run_lmp() {  # ranks tag
  (cd "$run" && OMP_NUM_THREADS=1 /usr/bin/time -f "%e %M" -o "lmp$2.time" \
    mpirun $mpi_root -np "$1" lmp -in pull.in -log "lmp$2.log" -screen none)
}
for c in $cores; do
  for k in $(seq "$pairs"); do
    echo "pair $k of $pairs on $c core(s) ..." >&2
    run_gd "$c" "$c-$k"
    [ -z "$radius" ] || run_gd "$c" "R$c-$k" --active_radius "$radius" ${dwell:+--sleep_time "$dwell"}
    run_lmp "$c" "$c-$k"
  done
done

/usr/bin/python3 - "$run" "$grains" "$steps" "$pairs" "$cores" "$label" "$speed" "$radius" "${fresh:-kept}" "$dwell" <<'PYEOF'
import re
import statistics as st
import sys
from pathlib import Path

run, steps, pairs = Path(sys.argv[1]), int(sys.argv[3]), int(sys.argv[4])
cores, size = [int(c) for c in sys.argv[5].split()], sys.argv[6]
speed, radius = sys.argv[7], sys.argv[8]
region = f"active radius {radius} d" + (f", sleep_time {sys.argv[10]}" if sys.argv[10] else "")
springs = "kept" if sys.argv[9] == "kept" else "dropped, as LAMMPS's read_data does"
gd_txt = (run / f"gd{cores[0]}-1.txt").read_text()
n = int(re.search(r"loop [\d.e+-]+ s for (\d+) steps", gd_txt).group(1))
natoms = int(re.search(r"^\s*(\d+) atoms", (run / "pull.data").read_text(), re.M).group(1))

def whole(path):
    wall, rss = path.read_text().split()[-2:]
    return float(wall), int(rss) * 1024

def gd_loop(path):
    t = path.read_text()
    m = re.search(r"timing: loop ([\d.e+-]+) s for (\d+) steps, [\d.e+-]+ particle-steps/s;(.*) s$", t, re.M)
    split = dict(re.findall(r"(\S+) ([\d.e+-]+)", m.group(3)))
    return float(m.group(1)), {k: float(v) for k, v in split.items()}

def gd_second_half(path):
    m = re.search(r"^timing: second half ([\d.e+-]+) s for (\d+) steps", path.read_text(), re.M)
    return float(m.group(1)), int(m.group(2))

def lmp_loop(path):
    return float(re.search(r"^Loop time of ([\d.e+-]+)", path.read_text(), re.M).group(1))

ps = natoms * n
print(f"# pull of a D = 2 intruder at V = {speed} through the {size} bed: {natoms} bodies, {n} steps, "
      f"median of {pairs} interleaved pairs; granudrag's start: the bed's springs {springs}")
print("| code | cores | loop [s] | loop particle-steps/s | whole process [s] | peak RSS [MB] | bytes/particle |"
      " granudrag / LAMMPS (loop) | (whole) |")
print("|---|---|---|---|---|---|---|---|---|")
rows = {}
for c in cores:
    g = [gd_loop(run / f"gd{c}-{k}.txt") for k in range(1, pairs + 1)]
    gw = [whole(run / f"gd{c}-{k}.time") for k in range(1, pairs + 1)]
    lw = [whole(run / f"lmp{c}-{k}.time") for k in range(1, pairs + 1)]
    ll = [lmp_loop(run / f"lmp{c}-{k}.log") for k in range(1, pairs + 1)]
    ratio_loop = st.median(l / x[0] for l, x in zip(ll, g))
    ratio_whole = st.median(l[0] / x[0] for l, x in zip(lw, gw))
    gl = st.median(x[0] for x in g)
    rss_g = max(x[1] for x in gw)
    # LAMMPS: /usr/bin/time sees mpirun; with ranks it reports the largest process, so scale.
    rss_l = max(x[1] for x in lw) * (c if c > 1 else 1)
    rows[c] = (gl, st.median(ll))
    print(f"| granudrag (OpenMP) | {c} | {gl:.3f} | {ps / gl:.3g} | {st.median(x[0] for x in gw):.2f} | "
          f"{rss_g / 2**20:.0f} | {rss_g / natoms:.0f} | **{ratio_loop:.2f}×** | {ratio_whole:.2f}× |")
    print(f"| LAMMPS ({'serial' if c == 1 else 'MPI'}) | {c} | {st.median(ll):.3f} | {ps / st.median(ll):.3g} | "
          f"{st.median(x[0] for x in lw):.2f} | {rss_l / 2**20:.0f} | {rss_l / natoms:.0f} | | |")
    if radius:
        import h5py
        rl = [gd_loop(run / f"gdR{c}-{k}.txt")[0] for k in range(1, pairs + 1)]
        rw = [whole(run / f"gdR{c}-{k}.time") for k in range(1, pairs + 1)]
        with h5py.File(run / f"gdR{c}-1.h5", "r") as f:
            asleep = f["/observables/sleeping_grains/value"][()] / natoms
        saving = st.median(x[0] / r for x, r in zip(g, rl))
        print(f"| granudrag, {region} | {c} | {st.median(rl):.3f} | "
              f"{ps / st.median(rl):.3g} | {st.median(x[0] for x in rw):.2f} | "
              f"{max(x[1] for x in rw) / 2**20:.0f} | | **{st.median(l / r for l, r in zip(ll, rl)):.2f}×** | "
              f"{st.median(l[0] / r[0] for l, r in zip(lw, rw)):.2f}× |")
        print(f"#   {region} on {c} thread(s): {saving:.2f}x faster than without it "
              f"(loop, median of the per-round ratios); bodies asleep: {asleep.mean():.1%} on "
              f"average over the pull, {asleep[-1]:.1%} at its end")
        # The second half of the steps: the steady cost once the bed has fallen asleep (a study's
        # pull of a box length spends about 1 % of its time falling asleep). LAMMPS's share is
        # its loop scaled by the steps, its cost per step being steady.
        gh = [gd_second_half(run / f"gd{c}-{k}.txt") for k in range(1, pairs + 1)]
        rh = [gd_second_half(run / f"gdR{c}-{k}.txt") for k in range(1, pairs + 1)]
        half = rh[0][1] / n
        asleep_half = asleep[len(asleep) // 2:].mean()
        print(f"#   second half ({rh[0][1]} steps): granudrag {st.median(x[0] for x in gh):.3f} s, with the region "
              f"{st.median(x[0] for x in rh):.3f} s: {st.median(x[0] / r[0] for x, r in zip(gh, rh)):.2f}x faster "
              f"than without it, {st.median(l * half / r[0] for l, r in zip(ll, rh)):.2f}x LAMMPS "
              f"(its loop x {half:.3f}); bodies asleep {asleep_half:.1%} on average over it")
    split = {k: st.median(x[1][k] for x in g) for k in g[0][1]}
    tot = sum(split.values())
    print(f"#   granudrag {c} thread(s), loop split: " +
          ", ".join(f"{k} {v / tot:.1%}" for k, v in split.items() if v > 0))
if 1 in rows and 2 in rows:
    print(f"# 1 -> 2 speed-up (loop): granudrag {rows[1][0] / rows[2][0]:.2f}x, "
          f"LAMMPS {rows[1][1] / rows[2][1]:.2f}x")
PYEOF
