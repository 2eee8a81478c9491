"""The paper's alpha_mu averaged over speeds (Sec. III H, Fig. 18a): the depth exponent of the
drag at each of several speeds, fitted per (mu, kn, gamman), and its average over them.
"""
import numpy as np
import pandas as pd

from ..core.table import bed_labels, is_yield, pooled_drag_err, shared_bed_variance
from .beds import slope_weights
from .fits import GOODNESS_COLUMNS, fit_power_law, goodness_columns

__all__ = ["ALPHA_SPEEDS", "SPEED_MATCH", "ALPHA_DRAG_COLUMNS", "ALPHA_SPEED_COLUMNS",
           "fit_alpha_speeds", "average_alpha", "fit_alpha_drag"]

ALPHA_SPEEDS = (0.5, 1.0, 2.0, 4.0, 6.0)   # Sec. III H: the speeds alpha_mu is averaged over
SPEED_MATCH = 0.25                          # a table speed within 25 % of one of them stands for it

ALPHA_DRAG_COLUMNS = ["mu", "kn", "gamman", "alpha", "alpha_err", "spread", "n_speeds", "speeds",
                      "h_min", "h_max"]
ALPHA_SPEED_COLUMNS = (["mu", "kn", "gamman", "V_target", "V", "alpha", "alpha_err", "n", "h_min", "h_max"]
                       + GOODNESS_COLUMNS)   # each speed's fit: its chi^2/dof, trend, rejection


def _speed_covariance(parts):
    """The covariance of the per-speed exponents implied by the points' errors: the speeds are
    pulled in the same beds, so a bed's shift (its shared relative variance) moves every speed's
    drag at its depth the same way, while the within-run noise is each pull's own. parts: per
    speed (slope weights c, relative within-run errors, relative shared bed deviations, bed
    labels)."""
    n = len(parts)
    cov = np.zeros((n, n))
    for i, (ci, wi, bi, li) in enumerate(parts):
        for j, (cj, _, bj, lj) in enumerate(parts):
            same = li[:, None] == lj[None, :]
            cov[i, j] = np.sum((ci * bi)[:, None] * (cj * bj)[None, :] * same)
            if i == j:
                cov[i, j] += np.sum(ci ** 2 * wi ** 2)
    return cov


def fit_alpha_speeds(df, speeds=ALPHA_SPEEDS, system="II", match=SPEED_MATCH, correlations=None):
    """The depth exponent of the drag at each of `speeds` (the paper's V = 0.5, 1, 2, 4, 6):
    F_drag = c h^alpha_V over the depths pulled at that speed, one fit per (mu, kn, gamman)
    and speed. A speed of the table within `match` (relative) of a target stands for it
    (a sweep on a Froude grid has other speeds); each table speed serves one target.
    correlations: a dict, filled with (mu, kn, gamman) -> the covariance matrix of that group's
    per-speed exponents that the points' errors imply (_speed_covariance), in the table's row
    order."""
    rows = df[(df.system == system) & ~is_yield(df)]
    out = []
    for (mu, kn, gn), g in rows.groupby(["mu", "kn", "gamman"]):
        # Weights with the between-bed scatter pooled over the series, as fit_phi's: each
        # point's own 2-dof scatter made the averaged alpha's 1-sigma interval hold the truth
        # 59 % of the time (nominal 68 %; tests/python/test_beds.py).
        err = pooled_drag_err(g)
        bed = np.sqrt(shared_bed_variance(g))     # each point's bed part, relative
        within = g["drag_err_within"] / g.drag if "drag_err_within" in g.columns else err / g.drag
        labels = bed_labels(g)
        have = np.unique(g.V.to_numpy())
        used = set()
        parts = []
        for target in speeds:
            rel = np.abs(have / target - 1.0)
            order = [i for i in np.argsort(rel) if rel[i] <= match and i not in used]
            if not order:
                continue
            V = have[order[0]]
            at = g[np.isclose(g.V, V, rtol=1e-9)]
            if at.h.nunique() < 2:
                continue
            used.add(order[0])
            f = fit_power_law(at.h, at.drag, err[at.index])
            rel = (err[at.index] / at.drag).to_numpy(float)
            parts.append((slope_weights(np.log(at.h.to_numpy(float)), rel), within[at.index].to_numpy(float),
                          bed[at.index].to_numpy(float), labels[at.index].to_numpy()))
            out.append({"mu": mu, "kn": kn, "gamman": gn, "V_target": float(target), "V": float(V),
                        "alpha": f["p"].value, "alpha_err": f["p"].err, "n": f.n_points,
                        "h_min": float(at.h.min()), "h_max": float(at.h.max()), **goodness_columns(f)})
        if correlations is not None and parts:
            correlations[(mu, kn, gn)] = _speed_covariance(parts)
    table = pd.DataFrame(out, columns=ALPHA_SPEED_COLUMNS)
    return table.astype(float) if table.empty else table


def average_alpha(per_speed, correlations=None):
    """The paper's alpha_mu (Sec. III H, Fig. 18a): the depth exponents at the speeds,
    averaged. Its error is that of a mean of correlated numbers, sqrt(1' C 1)/n, C the
    covariance of the per-speed exponents the points' errors imply (correlations[(mu, kn,
    gamman)], from fit_alpha_speeds: the beds' shared scatter and each pull's own), scaled up
    by sqrt(chi^2/dof) of the speeds' fits together when above 1. Without C, the mean of the
    per-speed errors (fully correlated, an upper bound: on tables whose speeds are pulled in
    beds of their own it was twice too wide, RMS of z 0.5; tests/python/test_calibration.py).
    `spread` is the standard deviation of the per-speed exponents."""
    out = []
    for (mu, kn, gn), g in per_speed.groupby(["mu", "kn", "gamman"]):
        a, e = g.alpha.to_numpy(float), g.alpha_err.to_numpy(float)
        C = (correlations or {}).get((mu, kn, gn))
        if C is None or C.shape != (len(e), len(e)):
            err = float(np.mean(e))
        else:
            dof = g.n.to_numpy(float) - 2
            chi2 = float(np.nansum(g.chi2_dof.to_numpy(float) * dof)) / max(1.0, float(np.sum(dof)))
            err = float(np.sqrt(np.sum(C))) / len(e) * max(1.0, np.sqrt(chi2))
        out.append({"mu": mu, "kn": kn, "gamman": gn, "alpha": float(np.mean(a)),
                    "alpha_err": err if np.all(np.isfinite(e)) else np.nan,
                    "spread": float(np.std(a, ddof=1)) if len(a) > 1 else np.nan,
                    "n_speeds": len(a), "speeds": " ".join(f"{v:.3g}" for v in g.V),
                    "h_min": float(g.h_min.min()), "h_max": float(g.h_max.max())})
    table = pd.DataFrame(out, columns=ALPHA_DRAG_COLUMNS)
    return table if len(table) else table.astype({c: float for c in ALPHA_DRAG_COLUMNS if c != "speeds"})


def fit_alpha_drag(df, speeds=ALPHA_SPEEDS, system="II", match=SPEED_MATCH):
    """(averaged alpha_mu table, per-speed table): see fit_alpha_speeds and average_alpha."""
    corr = {}
    per = fit_alpha_speeds(df, speeds, system, match, correlations=corr)
    return average_alpha(per, corr), per
