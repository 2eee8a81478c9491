"""The energy checks and the largest overlaps of a study's pulls, per system and K_n: what a
validation of the time step compares besides the observables (issue 74). From each run.h5's
/sanity report (docs/files.md): the energy balance's residual, the grains' energy change minus the
intruder's work plus the energy dissipated, over that work (0 for an exact integration of a
closed system), and the largest overlap any contact reached.

    .venv/bin/python tools/energy_overlap.py results/validate/time_step_mu0

Prints per K_n and system the pulls, the largest |residual|, and the median and largest of the
largest overlaps; per K_n and system other than the first, the median over pulls of its largest
overlap over the same bed's and speed's in the reference system (--reference, default T64: the
time-step studies' reference).
"""
import argparse
import re
import statistics as st
import sys
from collections import defaultdict
from pathlib import Path

import h5py

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from analysis.core.path_scheme import named, part  # noqa: E402

REPORT = re.compile(r"energy of the grains (\S+) -> (\S+), work by the intruder (\S+), dissipated (\S+)")


def read(run):
    """(residual, largest overlap) of one run.h5."""
    with h5py.File(run, "r") as f:
        s = f["sanity"].attrs
        report = s["report"].decode() if isinstance(s["report"], bytes) else str(s["report"])
        overlap = float(s["max_overlap"])
    m = REPORT.search(report)
    if not m:
        raise SystemExit(f"energy_overlap.py: {run}: no energy line in /sanity's report")
    e0, e1, work, dissipated = map(float, m.groups())
    return (e1 - e0 - work + dissipated) / work, overlap


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", type=Path, help="a study's results directory (its pulls/ below it)")
    ap.add_argument("--reference", default="T64", help="the system the others are compared with (default T64)")
    a = ap.parse_args()
    runs = sorted((a.results / "pulls").rglob("run.h5"))
    if not runs:
        raise SystemExit(f"energy_overlap.py: no run.h5 under {a.results / 'pulls'}")
    rows = defaultdict(dict)   # (kn, system) -> {(the bed's other keys, speed): (residual, overlap)}
    for run in runs:
        names = named(run.relative_to(a.results / "pulls"))
        kn, system = part("kn", names.pop("kn")), part("system", names.pop("system"))
        rows[(kn, system)][tuple(sorted(names.items()))] = read(run)
    first = part("system", a.reference)
    if first not in {s for _, s in rows}:
        raise SystemExit(f"energy_overlap.py: no system {a.reference} under {a.results / 'pulls'} (--reference)")
    for kn, system in sorted(rows):
        r = rows[(kn, system)]
        worst = max(abs(v[0]) for v in r.values())
        ov = [v[1] for v in r.values()]
        line = (f"{kn} {system}: {len(r)} pulls, |residual| at most {worst:.2e}, largest overlap median "
                f"{st.median(ov):.4f} d, greatest {max(ov):.4f} d")
        ref = rows.get((kn, first), {})
        if system != first and ref:
            q = [v[1] / ref[k][1] for k, v in r.items() if k in ref]
            line += f"; over {first}'s: median {st.median(q):.3f} ({min(q):.3f}-{max(q):.3f}, {len(q)} pairs)"
        print(line)


if __name__ == "__main__":
    main()
