"""A bed's shift: the part of a pull's drag that every speed pulled through the same bed shares.

Every pull of one bed starts at the same place and crosses the same grains, so the drag's
fluctuation along that path (the packing the intruder meets) is not independent from one speed
to the next: a bed that reads high at one speed reads high at the others. In the box40-deep rung
(3 beds, 13 speeds) the beds' mean relative deviations are +2.5, -2.1 and -1.0 % over 40 d with a
pull's error of 3.4 % (permutation p < 0.001), and once they are taken out the beds' residuals
have χ² 14 for 24 dof: about half of a pull's error is its bed's. The point errors (combine_beds)
are right for each point alone; between points the shift is a covariance. A line, a quadratic and
the paper's shapes each absorb a common relative shift (they are closed under scaling), so fits
whose errors leave it out read curves smoother than their errors (χ²/dof 0.6) and tests of a
curve's shape lose power.

The estimate, per series (the points pulled through the same beds) and drag column, from the drags
alone: for each two points with at least two beds in common, the product of their relative
deviations from their own means over those beds, summed over the beds and divided by (k - 1), is
unbiased for σ_β², the variance of a bed's relative shift; σ_β² is their mean over pairs, held at
0 once averaged. Nothing in it comes from a pull's error: an estimate that took a point's whole
variance from its pulls' errors and set apart the two-way residual (24 dof here) read σ_β = 6 %
at crossover-k2e6-box40-full, whose pull errors are mostly unconverged bounds (the beds' residuals
χ² 26 for 34 dof) and whose beds shift nothing measurable (p = 0.13), and turned its line into a
"shown" quadratic. Like anything the beds share, σ_β² rests on k - 1 dof (2 with three beds):
the regime tests quote it, and the covariance keeps each point's pooled variance on its diagonal,
so the shift moves weight between points but never shrinks a point's error.
"""
import numpy as np

from .bed_spread import _moments
from .point_errors import pooled_drag_err

# (drag column, its error column, the point table's column of its series' σ_β²)
SHIFT_COLUMNS = (("drag", "drag_err", "drag_shift_r2"),
                 ("drag_cumulative_box", "drag_cumulative_box_err", "drag_cumulative_box_shift_r2"))
SHARED_CAP = 0.9   # the shared part of a point's variance at most this much of its error²


def shift_r2(values):
    """σ_β² of one series from values (points, beds): a point's drag through each bed, NaN where
    that point was not pulled through it; NaN when no two points share two beds."""
    Y = np.asarray(values, float)
    have = np.isfinite(Y)
    total, pairs = 0.0, 0
    for a in range(len(Y)):
        for b in range(a + 1, len(Y)):
            common = have[a] & have[b]
            k = int(common.sum())
            if k < 2:
                continue
            ra = Y[a, common] / Y[a, common].mean() - 1
            rb = Y[b, common] / Y[b, common].mean() - 1
            total += float(np.sum(ra * rb)) / (k - 1)
            pairs += 1
    return max(0.0, total / pairs) if pairs else np.nan


def bed_shift(out, runs, codes):
    """combine_beds's columns of each point's series' σ_β² (SHIFT_COLUMNS; runs with its _series
    and a seed per bed, codes each run's point in out), and the split of a point's error into its
    pulls' and the beds' excess (_err_within, _err_between, _var_excess, as the drag's) for the
    columns that lack it."""
    if "seed" not in runs:
        return
    series = runs.groupby(codes)["_series"].first().to_numpy()
    k = np.bincount(codes)
    for col, err, name in SHIFT_COLUMNS:
        if col not in runs or err not in runs:
            continue
        if f"{col}_err_within" not in out:
            _, s2, W = _moments(codes, k, runs[col].to_numpy(float), runs[err].to_numpy(float))
            out[f"{col}_err_within"] = np.sqrt(W / k)
            out[f"{col}_err_between"] = np.sqrt(np.maximum(0.0, np.nan_to_num(s2) - W) / k)
            out[f"{col}_var_excess"] = np.where(k >= 2, (s2 - W) / k, np.nan)
        out[name] = np.nan
        Y = runs.assign(_code=codes).pivot_table(index="_code", columns="seed", values=col, aggfunc="mean")
        for s in np.unique(series):
            mine = np.flatnonzero(series == s)
            out.loc[mine, name] = shift_r2(Y.reindex(mine).to_numpy(float))


def bed_sets(points):
    """Each point's beds (the table's `seeds`, ';'-joined) as sets; one unnamed bed per row
    without them."""
    if "seeds" not in points.columns:
        return [{f"row {i}"} for i in range(len(points))]
    return [set(filter(None, str(s).split(";"))) or {f"row {i}"} for i, s in enumerate(points["seeds"])]


def pooled_variance(points, column, err_column):
    """Each point's variance with its pulls' errors and the beds' excess over them pooled across
    the points (point_errors.pooled_drag_err on this column): the diagonal a covariance needs. A
    point's own max(s², W) / k is right on average but, with 3 beds, 1.37 times its variance, and
    that inflation falls wholly on the independent part once the shared part is set apart."""
    split = [f"{column}_err_within", f"{column}_err_between", f"{column}_var_excess"]
    if not set(split + ["n_beds"]) <= set(points.columns):
        return points[err_column].to_numpy(float) ** 2
    as_drag = points[[column, err_column, "n_beds"] + split].set_axis(
        ["drag", "drag_err", "n_beds", "drag_err_within", "drag_err_between", "drag_var_excess"], axis=1)
    return np.asarray(pooled_drag_err(as_drag), float) ** 2


def _shift_column(points, column):
    """The points' column of σ_β² for `column` (SHIFT_COLUMNS) when it holds a value, else None."""
    name = next((n for c, ec, n in SHIFT_COLUMNS if c == column), None)
    if name is None or name not in points.columns or not np.isfinite(points[name].to_numpy(float)).any():
        return None
    return name


def curve_errors(points, column="drag", err_column="drag_err"):
    """What a fit of a curve through the points weighs them by: their covariance when the table
    knows their series' σ_β², else each point's pooled error (pooled_variance), as the fits weighed
    them before the shift was measured (a table made before it reads as it did)."""
    if _shift_column(points, column) is None:
        return np.sqrt(pooled_variance(points, column, err_column))
    return covariance(points, column, err_column)


def covariance(points, column, err_column):
    """The covariance of the points' `column` (in their order): each point's pooled_variance on the
    diagonal and, between two points, σ_β² y_i y_j n_ij / (k_i k_j) (n_ij the beds they share, k
    their beds), σ_β² their series' (SHIFT_COLUMNS; held so that no point's shared part passes
    SHARED_CAP of its variance). Each point's error² alone when the table has no σ_β² (made before
    it, one bed a point, no pair)."""
    y = points[column].to_numpy(float)
    name = _shift_column(points, column)
    if name is None:
        return np.diag(points[err_column].to_numpy(float) ** 2)
    v = pooled_variance(points, column, err_column)
    e = np.sqrt(v)
    C = np.diag(v)
    r2 = points[name].to_numpy(float)
    beds = bed_sets(points)
    k = np.array([len(b) for b in beds], float)
    ok = np.isfinite(r2) & np.isfinite(y) & np.isfinite(e) & (e > 0)
    if not ok.any() or not np.nanmax(np.where(ok, r2, np.nan)) > 0:
        return C
    r2 = float(np.nanmedian(r2[ok]))   # one value per series: the points of one series carry it alike
    r2 = min(r2, SHARED_CAP * float(np.min((k * e ** 2 / y ** 2)[ok])))
    n = np.array([[len(a & b) for b in beds] for a in beds], float)
    S = r2 * np.outer(y / k, y / k) * n
    S[~ok, :] = 0.0
    S[:, ~ok] = 0.0
    np.fill_diagonal(S, 0.0)
    return C + S
