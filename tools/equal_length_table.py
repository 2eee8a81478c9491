"""A rung's point table with every pull read over the same travel: the first L d of each pull
(--travel, default 20), both averagings (the steady drag after the engine's transient; the paper's
cumulative average over one box length, extrapolated from those L d as analysis.runs.run_series
.box_cumulative does), the beds then combined as the workflow's table rule combines them. For a
drag curve whose speeds were pulled different lengths (the box40-deep rung: 20 d to Fr 7, 40 d
from Fr 8): the drag relaxes along a pull, so lengths that change with the speed would put a step
in the curve where the length changes.

    .venv/bin/python tools/equal_length_table.py --out table20.csv            # the rung's pulls
    .venv/bin/granudrag-analysis regime-tests table20.csv --out regime20
    .venv/bin/python tools/equal_length_table.py --travel 20 --out T.csv RUN_H5_OR_DIR ...

A pull shorter than L is read whole (and said so on stderr). Yield pulls are marked as the rung's
config marks them (--yield-speed, default 0.1).
"""
import argparse
import sys
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from analysis.core.table import combine_beds, mark_yield, save_csv  # noqa: E402
from analysis.runs.run_series import box_cumulative, first_travel, read_series  # noqa: E402
from analysis.runs.runs import load_runs  # noqa: E402

RUNG = ROOT / "results/reproduction/crossover-k2e6-box40-deep/pieces"


def equal_length(runs, travel):
    """runs (load_runs's rows) with drag, drag_err and drag_cumulative_box(_err) read over each
    pull's first `travel` d; returns (runs, the names of the pulls shorter than that)."""
    runs, short = runs.copy(), []
    for i, r in runs.iterrows():
        with h5py.File(r.path, "r") as f:
            t, drag_t, skip, speed = read_series(f, r.path)
        if t[-1] * speed < travel * (1 - 1e-3):
            short.append(r.run)
        if t[-1] * speed <= travel * (1 + 1e-3):   # read whole, as the table reads it
            continue
        w = first_travel(t, drag_t, skip, speed, travel)
        keep = int(np.searchsorted(t * speed, travel * (1 + 1e-9), side="right"))
        box = box_cumulative(t[:keep], drag_t[:keep], min(skip, keep), speed, r.lx)
        runs.loc[i, ["drag", "drag_err", "drag_cumulative_box", "drag_cumulative_box_err"]] = \
            [w["drag_series"], w["drag_err"], *box]
    return runs, short


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("paths", nargs="*", help="run files or directories (default: the box40-deep rung's pulls)")
    ap.add_argument("--travel", type=float, default=20.0, help="the travel every pull is read over, d")
    ap.add_argument("--yield-speed", type=float, default=0.1, help="the speed of the yield pulls (report.yield_speed)")
    ap.add_argument("--out", required=True, help="the point table to write (CSV)")
    args = ap.parse_args(argv)
    if not args.travel > 0:
        ap.error(f"--travel must be positive, got {args.travel}")
    files = []
    for p in map(Path, args.paths or [RUNG]):
        files += sorted(p.rglob("run.h5")) if p.is_dir() else [p]
    if not files:
        ap.error("no run.h5 among the paths")
    runs, problems = load_runs(files, errors="collect")
    for p in problems:
        print(f"left out: {p}", file=sys.stderr)
    runs, short = equal_length(mark_yield(runs, args.yield_speed), args.travel)
    for name in short:
        print(f"shorter than {args.travel:g} d, read whole: {name}", file=sys.stderr)
    save_csv(combine_beds(runs, prior=None), args.out)
    print(f"{args.out}: {len(runs)} pulls over their first {args.travel:g} d")
    return 0


if __name__ == "__main__":
    sys.exit(main())
