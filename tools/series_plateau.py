"""Whether each pull's drag error converged (analysis.runs.series_error's `plateau`), and why not where it
did not: the steady series of every run file under the given paths (default: the committed pulls of
the rung of issue 72), with its first lobe (z1, z2: the autocorrelation's first negative lag and
the first lag after it where it is not negative, sought up to N/6), the window M, the error, its
dof and the flag, then the count.

    .venv/bin/python tools/series_plateau.py                      # the rung's pulls, one a line
    .venv/bin/python tools/series_plateau.py --windows 10 20 30   # and windows of the long pulls
    .venv/bin/python tools/series_plateau.py DIR_OR_RUN_H5 ...

--windows L...: for every pull whose steady series (after the transient, about 4 d on the rung)
spans at least L d, the fraction of its windows of L d of steady travel (starting every --step d,
overlapping) whose error converged: how long a pull of that kind must be for its error to
converge (the rung's 40 d pulls against its 20 d ones).
Why a pull did not converge (`why`): "lobe > N/6" (the lobe's end was not found within N/6
lags: the series holds fewer than six of its lobes), "sum <= 0" (the lobe was found, but the
window's sum was not positive: the lobe's noise is larger than the sum), "no lobe".
"""
import argparse
import math
import sys
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from analysis.core.path_scheme import name_of  # noqa: E402
from analysis.runs.run_series import read_series  # noqa: E402
from analysis.runs.series_error import (  # noqa: E402
    LOBE_SEARCH,
    autocovariance,
    corrected_autocorrelation,
    first_lobe,
    mean_error,
)

RUNG = ROOT / "results/reproduction/crossover-k2e6-box40-deep/pieces/pulls"


def run_files(paths):
    for p in map(Path, paths):
        yield from (sorted(p.rglob("run.h5")) if p.is_dir() else [p])


def label(path):
    """seed~S/Fr~F (or the path) of a run file."""
    parts = [q for q in path.parts if name_of(q) in ("seed", "Fr")]
    return "/".join(parts) if parts else str(path)


def diagnose(x):
    """(MeanError, z1, z2, why) of a steady series."""
    r = mean_error(x)
    n = len(x)
    search = int(n * LOBE_SEARCH)
    z1 = z2 = None
    if n >= 8 and np.all(np.isfinite(x)) and np.var(x) > 0:
        z1, z2 = first_lobe(corrected_autocorrelation(autocovariance(x), n, search + 1), search)
    why = "" if r.plateau else ("no lobe" if z1 is None else "lobe > N/6" if z2 is None else "sum <= 0")
    return r, z1, z2, why


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("paths", nargs="*", default=[str(RUNG)], help="run files or directories (default: the rung)")
    ap.add_argument("--windows", nargs="*", type=float, default=[], metavar="L", help="window lengths, d of travel")
    ap.add_argument("--step", type=float, default=2.5, help="the windows' starts, d apart (default 2.5)")
    a = ap.parse_args(argv)
    pulls = []
    for path in run_files(a.paths):
        with h5py.File(path) as f:
            t, drag, skip, speed = read_series(f, path)
        pulls.append((label(path), drag[skip:], t[skip:] * speed))
    if not pulls:
        sys.exit(f"series_plateau: no run.h5 under {' '.join(a.paths)}")
    print(f"{'pull':16s} {'N':>5s} {'travel d':>8s} {'z1':>3s} {'z2':>3s} {'M':>4s} {'drag':>9s} {'error':>8s} "
          f"{'dof':>6s}  plateau")
    converged = 0
    for name, x, travel in pulls:
        r, z1, z2, why = diagnose(x)
        converged += r.plateau
        print(f"{name:16s} {len(x):5d} {travel[-1] - travel[0]:8.1f} {z1 or '-':>3} {z2 or '-':>3} {r.window:4d} "
              f"{r.mean:9.1f} {r.error:8.2f} {r.dof:6.1f}  {'yes' if r.plateau else 'no (' + why + ')'}")
    print(f"plateau on {converged} of {len(pulls)} pulls ({converged / len(pulls):.2f})")
    for L in a.windows:
        rows = []
        for name, x, travel in pulls:
            if travel[-1] - travel[0] < L * (1 - 1e-9):
                continue
            starts = np.arange(travel[0], travel[-1] - L * (1 - 1e-9), a.step)
            flags = []
            for s in starts:
                keep = (travel > s) & (travel <= s + L * (1 + 1e-9))
                flags.append(mean_error(x[keep]).plateau)
            rows.append((name, int(np.sum(flags)), len(flags)))
        if rows:
            done, total = sum(c for _, c, _ in rows), sum(w for _, _, w in rows)
            each = ", ".join(f"{n} {c}/{w}" for n, c, w in rows)
            print(f"windows of {L:g} d of steady travel (every {a.step:g} d): converged {done} of {total} "
                  f"({done / total if total else math.nan:.2f}): {each}")
        else:
            print(f"windows of {L:g} d: no pull that long")


if __name__ == "__main__":
    main()
