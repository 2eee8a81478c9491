"""Two forms of the drag's dependence on depth h and speed V, fitted to the same points with the
same number of parameters and the same covariance, so their chi^2 compare directly:

    product   F = G_k h^alpha          the paper's (Eq. 12 at one D, Fig. 19): one G per speed k,
                                       the yield pulls one more k, one alpha
    sum       F = g h^a + c_k          a depth law common to every speed plus a depth-independent
                                       excess per speed (c = 0 for the yield pulls)

Both have (speeds + 2) parameters. On the points' covariance of analysis.deep_law (each point's
within-run and between-bed variance, the beds' part shared by the speeds pulled through them),
carried to linear space (C_ij F_i F_j). With errors that are upper bounds (unconverged pulls), both
chi^2 read low; their difference at equal parameters still ranks the forms, and understates it.
A reading beside `granudrag-analysis deep-law`, not a test the report makes:

    .venv/bin/python tools/depth_law_forms.py results/reproduction/scaling-k2e4-deep/table.csv
"""
import argparse
import sys
from pathlib import Path

import numpy as np
from scipy import stats
from scipy.optimize import least_squares

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from analysis.core.paper import at_least  # noqa: E402
from analysis.core.table import is_yield, load_csv  # noqa: E402
from analysis.deep_law.deep_law import log_covariance, speed_groups  # noqa: E402
from analysis.fits.alpha_drag import ALPHA_SPEEDS  # noqa: E402


def compare_forms(df, h_min=0.0, speeds=ALPHA_SPEEDS):
    """{form: (chi2, dof, p, parameters)} of the two forms on df's system II rows at h >= h_min
    (errors pooled over every depth), and n, the points."""
    rows = df[df.system == "II"]
    t = rows[at_least(rows.h, h_min)]
    group = np.where(np.asarray(is_yield(t)), 0.0, speed_groups(t, speeds))
    keep = np.isfinite(group)
    t, group = t[keep], group[keep]
    _, C, _, _ = log_covariance(t, rows)
    F, h = t.drag.to_numpy(float), t.h.to_numpy(float)
    W = np.linalg.inv(np.linalg.cholesky(C * np.outer(F, F)))
    keys = sorted(set(group.tolist()))
    k = np.array([keys.index(g) for g in group])
    yield_key = 0.0 in keys

    def product(p):
        return np.exp(p[k]) * h ** p[-1]

    def total(p):
        c = np.concatenate([[0.0], p[2:]]) if yield_key else p[2:]
        return p[0] * h ** p[1] + c[k]

    n_c = len(keys) - 1 if yield_key else len(keys)
    start_g = float(np.median(F / h))
    fits = {"product": least_squares(lambda p: W @ (F - product(p)), np.r_[np.log(np.full(len(keys), start_g)), 1.0]),
            "sum": least_squares(lambda p: W @ (F - total(p)), np.r_[start_g, 1.0, np.full(n_c, 0.1 * F.mean())])}
    out = {}
    for name, fit in fits.items():
        chi2, dof = 2.0 * fit.cost, len(F) - len(fit.x)
        out[name] = (chi2, dof, float(stats.chi2.sf(chi2, dof)) if dof > 0 else float("nan"), fit.x)
    return out, len(F)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("table", help="a rung's table.csv with system II pulls at several depths")
    ap.add_argument("--h-min", type=float, action="append", help="depths read (default: 0, 20 and 45 d)")
    args = ap.parse_args(argv)
    df = load_csv(args.table)
    for h_min in args.h_min or [0.0, 20.0, 45.0]:
        forms, n = compare_forms(df, h_min)
        (c1, d1, p1, x1), (c2, d2, p2, x2) = forms["product"], forms["sum"]
        print(f"h >= {h_min:g} d, {n} points: product G_k h^alpha chi2 {c1:.1f} for {d1} dof (p {p1:.2g}), "
              f"alpha {x1[-1]:.3f}; sum g h^a + c_k chi2 {c2:.1f} for {d2} dof (p {p2:.2g}), a {x2[1]:.3f}, "
              f"c_k {', '.join(f'{c:.0f}' for c in x2[2:])}; chi2 product - sum {c1 - c2:+.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
