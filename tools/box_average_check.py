"""Whether the paper's cumulative average over one box length can be read from a shorter pull: each
run file at least 2 × L d long (default: the committed box-length pulls of the rung of issue 72) is
read over its first L d only (--length, default 20), its box-length average extrapolated from there
(analysis.runs.run_series.box_cumulative: S + (C - S) L / L_box, the start's excess spread over the
box, the drag assumed to stay steady), and compared with the average the whole box length measured:
the difference, its z against the extrapolation's error, and χ² over the pulls.

    .venv/bin/python tools/box_average_check.py                   # the rung's 40 d pulls
    .venv/bin/python tools/box_average_check.py --length 10 RUN_H5_OR_DIR ...

What it can see: a drag that drifts after L d (a bed still compacting, a wall reached) or a start
that outlasts L d shifts every pull the same way (a mean z away from 0); the noise of the unpulled
part is what the errors stand for. It cannot see a drift smaller than those errors.
"""
import argparse
import math
import sys
from pathlib import Path

import h5py
import numpy as np
from scipy.stats import chi2 as chi2_dist

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from analysis.runs.run_series import box_cumulative, read_series  # noqa: E402
from analysis.runs.series_error import mean_error  # noqa: E402

RUNG = ROOT / "results/reproduction/crossover-k2e6-box40-deep/pieces/pulls"


def run_files(paths):
    out = []
    for p in map(Path, paths or [RUNG]):
        out += sorted(p.rglob("run.h5")) if p.is_dir() else [p]
    return out


def check(path, length):
    """(name, travel, box, measured, extrapolated, its error, z, (first L d's steady drag over the
    rest's minus 1, its error)), or None when the pull is shorter than the box or than 2 × length."""
    with h5py.File(path, "r") as f:
        t, drag_t, skip, speed = read_series(f, path)
        box = float(f["parameters/pour"].attrs["lx"])
    travel = float(t[-1] * speed)
    if travel < box * (1 - 1e-3) or travel < 2 * length:
        return None
    measured = box_cumulative(t, drag_t, skip, speed, box)[0]
    keep = int(np.searchsorted(t * speed, length * (1 + 1e-9), side="right"))
    value, err = box_cumulative(t[:keep], drag_t[:keep], min(skip, keep), speed, box)
    first, rest = mean_error(drag_t[skip:keep]), mean_error(drag_t[keep:])
    halves = ((first.mean - rest.mean) / rest.mean, math.hypot(first.error, rest.error) / rest.mean)
    return "/".join(Path(path).parts[-3:-1]), travel, box, measured, value, err, (value - measured) / err, halves


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("paths", nargs="*", help="run files or directories (default: the rung's pulls)")
    ap.add_argument("--length", type=float, default=20.0, help="the shorter pull's length, d (default 20)")
    args = ap.parse_args(argv)
    if not args.length > 0:
        ap.error(f"--length must be positive, got {args.length}")
    rows = [r for r in (check(p, args.length) for p in run_files(args.paths)) if r is not None]
    if not rows:
        print(f"no pull of a whole box length and at least {2 * args.length:g} d among the paths", file=sys.stderr)
        return 2
    print(f"{'pull':<34} {'box':>4} {'measured':>9} {'from ' + format(args.length, 'g') + ' d':>9} {'err':>6} {'z':>6}")
    for name, _, box, measured, value, err, z, _ in rows:
        print(f"{name:<34} {box:4.0f} {measured:9.1f} {value:9.1f} {err:6.1f} {z:6.2f}")
    z = np.array([r[-2] for r in rows])
    c2 = float(np.sum(z ** 2))
    print(f"{len(z)} pulls: mean z {z.mean():.2f} ± {1 / math.sqrt(len(z)):.2f}, chi2 {c2:.1f} for {len(z)} dof "
          f"(p = {chi2_dist.sf(c2, len(z)):.2g})")
    rel = np.array([r[-1] for r in rows])
    w = 1 / rel[:, 1] ** 2
    mean, err = float(np.sum(w * rel[:, 0]) / np.sum(w)), float(1 / math.sqrt(np.sum(w)))
    plain = (rel[:, 0].mean(), rel[:, 0].std(ddof=1) / math.sqrt(len(rel))) if len(rel) > 1 else (rel[0, 0], math.nan)
    print(f"steady drag over the first {args.length:g} d over that of the rest, minus 1: weighted mean "
          f"{100 * mean:+.2f} ± {100 * err:.2f} %, plain mean {100 * plain[0]:+.2f} ± {100 * plain[1]:.2f} %, "
          f"{int(np.sum(rel[:, 0] > 0))} of {len(rel)} above")
    return 0


if __name__ == "__main__":
    sys.exit(main())
