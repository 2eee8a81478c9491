#!/usr/bin/env bash
# Where the active region pays: the CPU of a pull without it over the same pull with it, through
# the same bed, over box size, K_n and speed (issue 74's map; docs/pour-and-pull.md, "Where it
# pays"). Each box gets one bed poured as the validation studies pour theirs (16 grains per d^2
# of floor, settle_damping 1, D = 2 held 7 d deep, mu = 0.5), and each pull runs without and with
# the region in alternating order, --rounds times, one thread: the ratio is the median of the
# rounds' own ratios, so a machine shared with other work loads both sides alike.
#
#   bench/region_map.sh [--boxes "10 20 40"] [--kn 2e4] [--rounds 3] [--diameters 3]
#                       [--pulls "yield fr1 fr5 fr10"] [--granudrag BIN] [--dir DIR]
#
# The pulls: yield = V 0.1 over 2 d; frN = Froude number N over 5 d (N = 1) or 10 d (faster),
# each at most one box length, with max_overlap 0.2 d as the studies at K_n = 2e4. Prints one row
# per box and pull: grains, CPU seconds without and with the region (medians), the ratio (and
# its range over the rounds), and the share of grains asleep at the end.
set -euo pipefail
cd "$(dirname "$0")/.."
boxes="10 20 40" kn=2e4 rounds=3 diameters=3 pulls="yield fr1 fr5 fr10" gd=build/granudrag dir=""
while [ $# -gt 0 ]; do
  case $1 in
    --boxes) boxes=$2; shift 2 ;;
    --kn) kn=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    --diameters) diameters=$2; shift 2 ;;
    --pulls) pulls=$2; shift 2 ;;
    --granudrag) gd=$2; shift 2 ;;
    --dir) dir=$2; shift 2 ;;
    -h|--help) sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "bench/region_map.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[ -x "$gd" ] || { echo "bench/region_map.sh: no granudrag at '$gd' (build it: cmake --build build --target granudrag, or --granudrag BIN)" >&2; exit 2; }
[ "$rounds" -ge 1 ] 2>/dev/null || { echo "bench/region_map.sh: --rounds must be a whole number >= 1, got '$rounds'" >&2; exit 2; }
dir=${dir:-$(mktemp -d /tmp/region_map.XXXXXX)}
mkdir -p "$dir"
export OMP_NUM_THREADS=1
rows=$dir/rows.tsv
: > "$rows"

# pull_args NAME BOX: the pull's speed and travel
pull_args() {
  local travel
  case $1 in
    yield) echo "--speed 0.1 --distance $(/usr/bin/python3 -c "print(min(2, $2))")" ;;
    fr1) echo "--froude 1 --distance $(/usr/bin/python3 -c "print(min(5, $2))")" ;;
    fr[0-9]*) travel=$(/usr/bin/python3 -c "print(min(10, $2))"); echo "--froude ${1#fr} --distance $travel" ;;
    *) echo "bench/region_map.sh: unknown pull '$1' (yield, fr1, fr5, ...)" >&2; exit 2 ;;
  esac
}

# Refuse an unknown pull before pouring anything (pull_args's exit only leaves its $( )).
for p in $pulls; do pull_args "$p" 10 > /dev/null || exit 2; done

# cpu_of CMD...: runs it, prints its user + system CPU seconds
cpu_of() {
  local t
  t=$(mktemp "$dir/time.XXXXXX")
  /usr/bin/time -f "%U %S" -o "$t" "$@" > /dev/null 2>&1 || { echo "bench/region_map.sh: failed: $*" >&2; exit 1; }
  awk '{print $1 + $2}' "$t"
  rm -f "$t"
}

for box in $boxes; do
  grains=$((box * box * 16))
  bed=$dir/bed_${box}_${kn}.h5
  if [ ! -f "$bed" ]; then
    echo "region_map: pouring $grains grains in a $box d box, K_n $kn" >&2
    "$gd" pour --output "$bed" --lx "$box" --ly "$box" --grains "$grains" --intruder_diameter 2 --depth 7 \
      --mu 0.5 --kn "$kn" --seed 1 --settle_damping 1 --ke_threshold 1e-6 --max_settle_time 40 \
      --threads 1 --quiet > /dev/null
  fi
  for p in $pulls; do
    read -r -a args <<< "$(pull_args "$p" "$box")"
    for ((r = 1; r <= rounds; r++)); do
      order="off on"
      [ $((r % 2)) -eq 0 ] && order="on off"
      for side in $order; do
        out=$dir/${box}_${p}_${side}_$r.h5
        rm -f "$out" "$out.checkpoint.h5"
        extra=()
        [ "$side" = on ] && extra=(--active_diameters "$diameters")
        cpu=$(cpu_of "$gd" pull --bed "$bed" --output "$out" "${args[@]}" "${extra[@]}" --max_overlap 0.2 --threads 1 --quiet) || exit 1
        printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$box" "$grains" "$p" "$side" "$r" "$cpu" "$out" >> "$rows"
        echo "region_map: box $box, $p, region $side, round $r/$rounds: $cpu CPU s" >&2
      done
    done
  done
done

/usr/bin/python3 - "$rows" "$kn" "$diameters" <<'EOF'
import statistics as st, sys
import h5py, numpy as np
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1]) if l.strip()]
print(f"# the active region's saving, K_n {sys.argv[2]}, R = {sys.argv[3]} D, one thread; "
      "CPU s medians over rounds, ratio = median of the rounds' without / with")
print("| box (d) | grains | pull | without (s) | with (s) | without / with | asleep at the end |")
print("|---|---|---|---|---|---|---|")
keys = list(dict.fromkeys((int(r[0]), int(r[1]), r[2]) for r in rows))  # in the order run
for box, grains, pull in keys:
    mine = [r for r in rows if int(r[0]) == box and r[2] == pull]
    cpu = {(r[3], r[4]): float(r[5]) for r in mine}
    rounds = sorted({r[4] for r in mine})
    ratios = [cpu[("off", k)] / cpu[("on", k)] for k in rounds if ("off", k) in cpu and ("on", k) in cpu]
    asleep = ""
    with h5py.File([r[6] for r in mine if r[3] == "on"][-1]) as f:
        if "/observables/sleeping_grains/value" in f:
            asleep = f"{float(np.asarray(f['/observables/sleeping_grains/value'])[-1]) / grains:.0%}"
    print(f"| {box} | {grains} | {pull} | {st.median(cpu[k] for k in cpu if k[0] == 'off'):.1f} | "
          f"{st.median(cpu[k] for k in cpu if k[0] == 'on'):.1f} | {st.median(ratios):.2f} "
          f"({min(ratios):.2f}-{max(ratios):.2f}) | {asleep} |")
EOF
