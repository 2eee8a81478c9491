"""Whether a rung's beds shift every speed alike: each bed's mean relative deviation over the
speeds pulled through all beds, a permutation test of it, and the beds' residuals once it is taken
out (analysis/core/bed_shift.py says why the regime tests need it).

    .venv/bin/python tools/bed_shift_check.py                  # the box40-deep rung, as pulled
    .venv/bin/python tools/bed_shift_check.py --travel 20      # every pull over its first 20 d

The statistic: the mean over pairs of speeds of the products of the beds' normalized deviations,
z = (y - ȳ) / e, summed over beds; large when a bed that reads high at one speed reads high at
the others. Its null: the beds' labels permuted within each speed (--permutations copies).
"""
import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tools"))

from equal_length_table import RUNG, equal_length  # noqa: E402

from analysis.core.table import is_yield, mark_yield  # noqa: E402
from analysis.runs.runs import load_runs  # noqa: E402


def pair_statistic(Z):
    """Mean over pairs of rows (speeds) of the rows' dot product (Z: speeds × beds)."""
    G = Z @ Z.T
    n = len(Z)
    return (G.sum() - np.trace(G)) / (n * (n - 1))


def check(runs, column, err_column, permutations, rng):
    P = runs.pivot_table(index="Fr", columns="seed", values=column).dropna()
    E = runs.pivot_table(index="Fr", columns="seed", values=err_column).loc[P.index]
    m = P.mean(axis=1)
    rel, erel = P.div(m, axis=0) - 1, E.div(m, axis=0)
    Z = (rel / erel).to_numpy()
    observed = pair_statistic(Z)
    null = np.array([pair_statistic(np.array([r[rng.permutation(len(r))] for r in Z])) for _ in range(permutations)])
    w = 1 / erel ** 2
    offset = (rel * w).sum() / w.sum()
    resid = rel.sub(offset, axis=1)
    resid = resid.sub(resid.mean(axis=1), axis=0)
    k, n = P.shape[1], P.shape[0]
    print(f"{column}: {n} speeds on all {k} beds (Fr {P.index.min():g}-{P.index.max():g}), "
          f"a pull's median relative error {100 * np.median(erel):.2f} %")
    print("  each bed's mean deviation: " + ", ".join(
        f"seed {s:g} {100 * o:+.2f} %" for s, o in zip(offset.index, offset)))
    print(f"  pair statistic {observed:.3f}, permutation p {(1 + np.sum(null >= observed)) / (permutations + 1):.4f}")
    out = float(((resid / erel) ** 2).to_numpy().sum())
    print(f"  beds' residuals about the points' means: chi2 {float((Z ** 2).sum()):.1f} for {(k - 1) * n} dof; "
          f"with each bed's deviation out: {out:.1f} for {(k - 1) * (n - 1)} dof")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--travel", type=float, default=40.0, help="each pull read over its first L d (default 40)")
    ap.add_argument("--permutations", type=int, default=5000)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args(argv)
    if not args.travel > 0 or args.permutations < 100:
        ap.error("--travel must be positive and --permutations at least 100")
    runs, problems = load_runs(sorted(Path(RUNG).rglob("run.h5")), errors="collect")
    for p in problems:
        print(f"left out: {p}", file=sys.stderr)
    runs, _ = equal_length(mark_yield(runs, 0.1), args.travel)
    runs = runs[~is_yield(runs)]
    rng = np.random.default_rng(args.seed)
    for column, err in (("drag", "drag_err"), ("drag_cumulative_box", "drag_cumulative_box_err")):
        check(runs, column, err, args.permutations, rng)
    return 0


if __name__ == "__main__":
    sys.exit(main())
