#!/usr/bin/env bash
# Records the held-out yield pulls that tests/python/test_yield_errors.py uses to check the
# error bars of yield forces where the studies use them: independent pulls, each bed its own
# (seeds 1..S), at mu = 0 and 0.5, V = 0.03 and 0.1, with the default study's yield protocol
# (config/config.yaml, sweep yield_depth: 1.2 d of travel, the first 0.6 d discarded as
# transient, so 0.6 d averaged). Not used to choose any estimator or window.
#
#   tests/data/make_yield_pulls.sh [BINARY] [BEDS] [JOBS]     (defaults: build/granudrag, 48, 1)
#
# Each bed is the smoke study's system I (8 d x 8 d, 800 grains, K_n = 2e4) with a D = 2
# intruder at depth 4, poured at the pull's friction; both speeds are pulled through it.
# Writes tests/data/yield_pulls_D2.h5: per pull (one row each) the datasets seed, mu, V, drag,
# drag_err, drag_dof (the engine's estimate: integrated autocorrelation time, automatic window)
# and, one after another, the drag series after the transient (`series`, -F_x per sample
# interval, rho d^3 g, float32; `series_length` per pull). About 7 s per bed and friction on
# one core (20 min for 48 beds at 2 frictions).
set -euo pipefail
cd "$(dirname "$0")/../.."
gd=$(realpath "${1:-build/granudrag}")
beds=${2:-48}
jobs=${3:-1}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
one() {  # seed mu
  local bed="$work/bed_$1_$2.h5"
  "$gd" pour --output "$bed" --lx 8 --ly 8 --grains 800 --intruder_diameter 2 --depth 4 \
    --kn 2e4 --mu "$2" --ke_threshold 1e-5 --max_settle_time 15 --seed "$1" --threads 1 --quiet >/dev/null
  for v in 0.03 0.1; do
    "$gd" pull --bed "$bed" --output "$work/run_$1_$2_$v.h5" --speed "$v" --distance 1.2 \
      --transient 0.6 --snapshots 0 --threads 1 --quiet >/dev/null
  done
  rm -f "$bed"
  echo "make_yield_pulls: bed $1 at mu = $2 done" >&2
}
export -f one
export gd work
# shellcheck disable=SC2016  # $0 and $1 are the inner shell's: the seed and mu xargs passes
for s in $(seq 1 "$beds"); do for mu in 0 0.5; do echo "$s $mu"; done; done | xargs -P "$jobs" -L 1 bash -c 'one $0 $1'
/usr/bin/python3 - "$work" "$beds" <<'PY'
import os, sys
import h5py
import numpy as np

work, beds = sys.argv[1], int(sys.argv[2])
cols = {k: [] for k in ("seed", "mu", "V", "drag", "drag_err", "drag_dof", "series_length")}
series = []
for s in range(1, beds + 1):
    for mu in ("0", "0.5"):
        for v in ("0.03", "0.1"):
            with h5py.File(f"{work}/run_{s}_{mu}_{v}.h5") as f:
                d = f["observables/drag"].attrs
                skip = int(d["transient_samples"])
                x = -f["observables/intruder_force/value"][skip:, 0]
                for k, val in (("seed", s), ("mu", float(mu)), ("V", float(v)), ("drag", d["value"]),
                               ("drag_err", d["error"]), ("drag_dof", d["error_dof"]),
                               ("series_length", len(x))):
                    cols[k].append(val)
                series.append(x.astype(np.float32))
out = "tests/data/yield_pulls_D2.h5"
with h5py.File(out + ".tmp", "w") as f:
    for k, v in cols.items():
        f.create_dataset(k, data=np.asarray(v))
    f.create_dataset("series", data=np.concatenate(series), compression="gzip", shuffle=True)
    f.attrs["meaning"] = ("held-out yield pulls, one per row: each bed its own (seed), poured at the pull's mu "
                          "(smoke system I: 8 d x 8 d, 800 grains, K_n = 2e4, D = 2 at depth 4), pulled at "
                          "V = 0.03 and 0.1 for 1.2 d with a 0.6 d transient; drag and drag_err as the engine "
                          "reports them (rho d^3 g); series: -F_x per sample interval after the transient "
                          "(tests/data/make_yield_pulls.sh)")
os.replace(out + ".tmp", out)
print(f"make_yield_pulls: wrote {out}: {len(series)} pulls")
PY
