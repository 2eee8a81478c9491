"""The point table's columns beside its drag (analysis.core.table.combine_beds): the cumulative drag
from t = 0 with its error, the engine's errors, and the beds' spread against one pull's error.

Pull noise alone makes the standard deviation of a point's per-bed drags about one pull's error:
its ratio to the mean error (drag_bed_sd_ratio) says whether the errors are as wide as the scatter.
With k beds the ratio of a sample standard deviation to the true one scatters widely (k = 3: its
median is 0.83, chi with 2 dof), so read it as a median over points, and with bed-to-bed
differences on top it exceeds 1.
"""
import numpy as np


def _moments(codes, k, y, e):
    """Per point: mean of y, var of y (ddof 1, NaN for one bed), mean(e^2) (table._moments)."""
    m = np.bincount(codes, y) / k
    with np.errstate(invalid="ignore", divide="ignore"):
        s2 = np.bincount(codes, (y - m[codes]) ** 2) / (k - 1)
    return m, np.where(k >= 2, s2, np.nan), np.bincount(codes, e ** 2) / k


def bed_spread(out, runs, codes, k, r2):
    """combine_beds's columns of the cumulative drags (over the pull, over a box length), the engine's
    errors and the beds' spread."""
    def by_rule(y, e):    # drag_err's rule: sqrt((sigma_B^2 + W)/k), one bed sigma_B^2 = r2 y^2
        m, s2, W = _moments(codes, k, y, e)
        return m, np.sqrt((np.nan_to_num(np.where(k >= 2, np.maximum(0.0, s2 - W), r2 * m ** 2)) + W) / k)
    y = runs.drag.to_numpy(float)
    for c in ("drag_cumulative", "drag_cumulative_box"):
        if {c, c + "_err"} <= set(runs.columns):
            out[c], out[c + "_err"] = by_rule(runs[c].to_numpy(float), runs[c + "_err"].to_numpy(float))
    sd = np.sqrt(_moments(codes, k, y, y)[1])
    out["drag_bed_sd"] = sd
    for c, suffix in (("drag_err", ""), ("drag_err_engine", "_engine")):
        if c in runs:
            e = runs[c].to_numpy(float)
            if suffix:
                out[c] = by_rule(y, e)[1]
            with np.errstate(invalid="ignore", divide="ignore"):
                out["drag_bed_sd_ratio" + suffix] = sd / (np.bincount(codes, e) / k)
