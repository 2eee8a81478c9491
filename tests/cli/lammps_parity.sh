#!/usr/bin/env bash
# Parity with the paper's own code: the same bed pulled in LAMMPS (gran/hertz/history) and in
# granudrag. The force on the intruder must agree to 1e-6 relative over the first 100 steps, and
# the mean drag over a pull of several grain diameters within the combined error bars (2 sigma).
#   lammps_parity.sh path/to/granudrag
set -euo pipefail
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
if ! command -v lmp >/dev/null; then
  echo "SKIPPED: LAMMPS (lmp) is not installed and could not be: apt-get install lammps"
  exit 0
fi
PY=/usr/bin/python3
mkdir lmp
"$gd" pour --output bed.h5 --lx 10 --ly 10 --grains 1200 --intruder_diameter 2 --depth 4 \
  --kn 2e4 --mu 0.5 --ke_threshold 1e-4 --max_settle_time 40 --quiet >/dev/null
dt=$("$PY" -c "import h5py; print(repr(h5py.File('bed.h5')['/contact'].attrs['dt']))")

# 1. The first 100 steps, every step.
"$gd" export-lammps --bed bed.h5 --output lmp/first --speed 1 --steps 100 >/dev/null
(cd lmp && lmp -in first.in -log none -screen none)
"$gd" pull --bed bed.h5 --output first.h5 --speed 1 --fresh_start --quiet --snapshots 0 \
  --transient 0 --sample_interval "$dt" --distance "$("$PY" -c "print(100.5 * $dt)")" >/dev/null

# 2. A pull of 4 d, forces averaged over 50 steps.
"$gd" export-lammps --bed bed.h5 --output lmp/long --speed 1 --distance 4 --every 50 >/dev/null
(cd lmp && lmp -in long.in -log none -screen none)
"$gd" pull --bed bed.h5 --output long.h5 --speed 1 --fresh_start --quiet --snapshots 0 \
  --distance 4 --sample_interval "$("$PY" -c "print(50 * $dt)")" --transient 1 >/dev/null

# 3. The exported data file imported back is the same bed.
"$gd" import-lammps --data lmp/first.data --output imported.h5 --kn 2e4 --sort false >/dev/null

"$PY" - <<'PYEOF'
import sys
import h5py
import numpy as np

def lammps(path):
    a = np.loadtxt(path, comments="#")
    return a[:, 0].astype(int), a[:, 1:4]

def granudrag(path):
    with h5py.File(path) as f:
        return f["/observables/intruder_force/step"][()], f["/observables/intruder_force/value"][()]

def block_error(x):
    x, best = np.asarray(x, float), 0.0
    while len(x) >= 8:
        best = max(best, x.std(ddof=1) / np.sqrt(len(x)))
        x = 0.5 * (x[: len(x) // 2 * 2 : 2] + x[1 : len(x) // 2 * 2 : 2])
    return best

ok = True
ls, lf = lammps("lmp/first.force.txt")
gs, gf = granudrag("first.h5")
n = min(100, len(ls), len(gs))
assert n == 100, f"expected 100 steps from both codes, got {len(ls)} and {len(gs)}"
assert (ls[1:n + 1] == gs[:n]).all() if len(ls) > n else (ls[-n:] == gs[:n]).all(), "step numbers differ"
lf = lf[-n:] if len(ls) > n else lf[:n]
scale = np.abs(lf).max()
worst = np.abs(gf[:n] - lf).max() / scale
print(f"first {n} steps: max |F_granudrag - F_lammps| / max|F| = {worst:.2e} (bound 1e-6)")
ok &= worst < 1e-6

ls, lf = lammps("lmp/long.force.txt")
gs, gf = granudrag("long.h5")
with h5py.File("long.h5") as f:
    skip = int(f["/observables/drag"].attrs["transient_samples"])
    drag_g, err_g = f["/observables/drag"].attrs["value"], f["/observables/drag"].attrs["error"]
lf = lf[ls > 0]  # LAMMPS also prints the setup step
drag_l = -lf[skip:, 0].mean()
err_l = block_error(-lf[skip:, 0])
bound = 2 * np.hypot(err_g, err_l)
print(f"pull of 4 d: drag granudrag {drag_g:.4f} +- {err_g:.4f}, LAMMPS {drag_l:.4f} +- {err_l:.4f} "
      f"(difference {abs(drag_g - drag_l):.4f}, bound {bound:.4f})")
ok &= abs(drag_g - drag_l) <= bound
with h5py.File("bed.h5") as a, h5py.File("imported.h5") as b:
    for name in ("position", "radius", "species"):
        x, y = a[f"/particles/all/{name}/value"][()], b[f"/particles/all/{name}/value"][()]
        same = x.shape == y.shape and np.allclose(x, y, rtol=0, atol=1e-12)
        print(f"import-lammps round trip, {name}: {'same' if same else 'DIFFERENT'}")
        ok &= same
print("PASS" if ok else "FAIL")
sys.exit(0 if ok else 1)
PYEOF
