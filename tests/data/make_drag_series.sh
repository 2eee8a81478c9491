#!/usr/bin/env bash
# Records the real drag series that tests/cpp/test_pull.cpp uses to check the coverage of the
# drag's error bars: independent pulls, each through its own bed (seeds 1..S), so that disjoint
# windows of them are independent repeats.
#
#   tests/data/make_drag_series.sh [BINARY] [SERIES] [D] [V] [MU] [DISTANCE] [JOBS]
#
# Each bed is the smoke study's system I (8 d x 8 d, 800 grains, K_n = 2e4) with a D intruder at
# depth 4, poured at MU; each pull runs at V for DISTANCE with a sample every 0.02, and the
# series after the transient (3 d) is kept, cut to the shortest one's length.
# Writes tests/data/drag_series_D<D>_V<V>_mu<MU>.h5: dataset `drag`, the series one after another
# (-F_x per sample interval, rho d^3 g, float32), and its attribute `series_length`.
# The three recorded sets (tests/cpp/test_observables.cpp):
#   defaults (build/granudrag 48 2 1 0.5 203 2): D = 2, V = 1, mu = 0.5, 203 d; about a minute
#     per series, two at a time on 2 cores (25 min for 48). The drag error's window was chosen on
#     this set.
#   build/granudrag 40 3 0.5 0 79 1: D = 3, V = 0.5, mu = 0, 79 d; about 25 s per series on one
#     core. Recorded to hold out the N/6 fallback window, which failed on it at 64 samples; the
#     N/5 window was then chosen on both sets.
#   build/granudrag 40 1 2 0.25 303 2: D = 1, V = 2, mu = 0.25, 303 d; held out from N/5's choice.
set -euo pipefail
cd "$(dirname "$0")/../.."
gd=$(realpath "${1:-build/granudrag}")
series=${2:-48}
D=${3:-2}
V=${4:-1}
MU=${5:-0.5}
distance=${6:-203}
jobs=${7:-2}
out="tests/data/drag_series_D${D}_V${V}_mu${MU}.h5"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
one() {  # seed
  "$gd" pour --output "$work/bed$1.h5" --lx 8 --ly 8 --grains 800 --intruder_diameter "$D" --depth 4 \
    --kn 2e4 --mu "$MU" --ke_threshold 1e-5 --max_settle_time 15 --seed "$1" --threads 1 --quiet >/dev/null
  "$gd" pull --bed "$work/bed$1.h5" --output "$work/run$1.h5" --speed "$V" --distance "$distance" \
    --sample_interval 0.02 --snapshots 0 --threads 1 --quiet >/dev/null
  rm -f "$work/bed$1.h5"
  echo "make_drag_series: series $1 of $series done" >&2
}
export -f one
export gd work series D V MU distance
seq 1 "$series" | xargs -P "$jobs" -I{} bash -c 'one {}'
/usr/bin/python3 - "$work" "$series" "$out" "$D" "$V" "$MU" "$distance" <<'EOF'
import os, sys
import h5py
import numpy as np

work, series, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
D, V, mu, distance = sys.argv[4:8]
rows = []
for s in range(1, series + 1):
    with h5py.File(f"{work}/run{s}.h5") as f:
        skip = int(f["observables/drag"].attrs["transient_samples"])
        rows.append(-f["observables/intruder_force/value"][skip:, 0])
n = min(len(r) for r in rows)
with h5py.File(out + ".tmp", "w") as f:
    d = f.create_dataset("drag", data=np.concatenate([r[:n] for r in rows]).astype(np.float32),
                         compression="gzip", shuffle=True)
    d.attrs["series_length"] = np.int64(n)
    d.attrs["meaning"] = ("-F_x per sample interval (rho d^3 g) after the 3 d transient; one series "
                          "per pull, each through its own bed (seed = its number, from 1): "
                          f"D = {D} at depth 4, V = {V}, mu = {mu}, K_n = 2e4, 8 d x 8 d bed of 800 "
                          f"grains, {distance} d of travel, sample_interval 0.02 (tests/data/make_drag_series.sh)")
os.replace(out + ".tmp", out)
print(f"make_drag_series: wrote {out}: {len(rows)} series x {n} samples")
EOF
