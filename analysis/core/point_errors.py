"""Errors of a point table's points for a fit across them: each point's within-run error plus
the scatter between beds pooled over replicated points (a point's own two or three beds measure
it at 1-2 dof, and as weights such noisy errors favour the points whose beds happened to agree).
The point table is analysis.core.table.combine_beds'."""
import numpy as np
import pandas as pd


def pooled_drag_err(points, pool=None):
    """Errors of the point table's drags for weighting a fit across points: the within-run
    part of each point plus the between-bed variance pooled over the replicated points of
    `pool` (default: points; pool with points of the same kind: a yield force's beds scatter
    by ~14 %, a drag's at speed by ~5 %), sqrt(drag_err_within^2 + r2 drag^2 / n_beds), r2 the
    mean relative between-bed variance.
    A point's own between-bed variance rests on n_beds - 1 degrees of freedom (1 or 2 in a
    study): right on average, but as weights such noisy errors favour the points whose beds
    happened to agree, and a fit's intervals then cover the truth less often than they say
    (tests/python/test_beds.py): two beds' own 95 % intervals of a yield force cover it, but
    only through Student's t at 1 dof, with a median half-width of the whole force, where the
    pooled ones are 0.3 of it (tests/python/test_yield_errors.py). The point table's drag_err
    if neither it nor `pool` has a replicated point.
    r2 is pooled_bed_r2's: unbiased, where a mean of each point's max(0, ...) counts the beds'
    scatter about twice over when it is small against the within-run noise."""
    pool = points if pool is None else pool
    need = {"n_beds", "drag_err_within", "drag_err_between"}
    if not (need <= set(points.columns) and need <= set(pool.columns)):
        return points["drag_err"]
    k = points["n_beds"].astype(float)
    if not (pool["n_beds"].astype(float) >= 2).any():
        return points["drag_err"]
    r2 = pooled_bed_r2(pool)
    within = points["drag_err_within"].astype(float)
    return np.sqrt(within ** 2 + r2 * points["drag"].astype(float) ** 2 / k)


def pooled_bed_r2(points):
    """The relative between-bed variance of the drag pooled over the point table's replicated
    points: the mean of n_beds drag_var_excess / drag^2 (each point's excess of its beds'
    scatter over its within-run variance, unbiased, negative when they happen to agree), held
    at 0 once pooled; for a table without drag_var_excess, the mean of n_beds
    drag_err_between^2 / drag^2 (each held at 0, biased up: at 1.5 % between beds and 3 % within
    each pull, two beds, 2.8 times the variance). NaN without a replicated point."""
    k = points["n_beds"].astype(float)
    rep = k >= 2
    if not rep.any():
        return np.nan
    y2 = points["drag"].astype(float) ** 2
    if "drag_var_excess" in points.columns:
        return max(0.0, float(np.nanmean((k * points["drag_var_excess"].astype(float) / y2)[rep])))
    return float(np.nanmean((k * points["drag_err_between"].astype(float) ** 2 / y2)[rep]))


def observable_errors(points, column, pool=None):
    """(errors, shared) of θ or κ (`column`) for a fit across the point table's points. A point
    with replicate beds takes its within-run error and the between-bed variance pooled over the
    replicated points of `pool` (default: points; absolute, as one bed's offset of θ or κ does
    not grow with it; the mean excess of the beds' scatter over the within-run variance, held at
    0 only once pooled, as shared_bed_variance's), `shared` being that pooled part's standard
    deviation, which every pull of a bed shares; a point poured once keeps its own error (θ and
    κ take no pooled or prior scatter there) and shares nothing. Without the split columns:
    (the column's errors, zeros). Pooled over a fit's own points alone, which share a handful
    of beds, the variance rested on as many degrees of freedom as beds: κ's intercept's z had an
    RMS of 1.3 (tests/python/test_calibration.py)."""
    err = points[f"{column}_err"].astype(float)
    zero = pd.Series(0.0, index=points.index)
    pool = points if pool is None else pool
    need = {"n_beds", f"{column}_err_within", f"{column}_var_excess"}
    if not (need <= set(points.columns) and need <= set(pool.columns)):
        return err, zero
    k = points["n_beds"].astype(float)
    rep = k >= 2
    kp = pool["n_beds"].astype(float)
    excess = (kp * pool[f"{column}_var_excess"].astype(float))[kp >= 2]
    if not rep.any() or not excess.notna().any():
        return err, zero
    r2 = max(0.0, float(np.nanmean(excess)))
    shared = np.sqrt(r2 / k).where(rep, 0.0)
    within = points[f"{column}_err_within"].astype(float)
    return np.sqrt(within ** 2 + shared ** 2).where(rep, err), shared


def shared_bed_variance(points):
    """Each point's relative between-bed variance, as pooled_drag_err counts it: the part of its
    error a bed shares with every other pull in it (r2 / n_beds for a replicated point, the
    pooled or prior r2 for one poured once), 0 where the table says nothing of its beds (no
    drag_err_within)."""
    if "drag_err_within" not in points.columns:
        return pd.Series(0.0, index=points.index)
    total = pooled_drag_err(points).astype(float) ** 2
    within = points["drag_err_within"].astype(float) ** 2
    return ((total - within).clip(lower=0.0) / points["drag"].astype(float) ** 2).fillna(0.0)
