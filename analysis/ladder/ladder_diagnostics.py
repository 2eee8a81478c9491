"""The ladder's diagnostics: the slope of κ(Fr) against the shell width Z is counted in and κ's
rise taken apart into n and Z, Fr_2 refitted on growing Fr ranges, and Fr_2 refitted with the
start of each pull kept as the paper's cumulative average may have kept it."""
import math

import numpy as np
import pandas as pd

from ..core import paper
from ..core.result import LADDER_N_BOOT
from ..core.table import is_yield, pooled_drag_err, reference_params, select
from ..fits.fits import fit_broken_line, fit_linear
from ..fits.fitset import point_bed_scatter
from ..fits.regimes import fit_regimes, profile_fr2
from ..report.verdicts import OBSERVABLE_MIN_SPEEDS, distinct_speeds

FR_MAX_VALUES = (8.0, 10.0, 12.0, 15.0)


# --- κ in shells ---------------------------------------------------------------

SLOPE_COLUMNS = ["rung", "D", "width", "k0", "k0_err", "k1", "k1_err", "n_points", "n_runs", "errors_from"]


def inside_box(shells):
    """The rows whose shell stays a ball: D/2 + w <= min(lx, ly)/2. Beyond it the minimum-image
    distance clips the shell by the periodic box (it counts the images' neighbourhoods), so its Z
    is not a shell's. Rows without lx, ly (files collected before they were recorded) are kept."""
    if not {"lx", "ly"} <= set(shells.columns):
        return shells
    half = np.minimum(shells.lx.astype(float), shells.ly.astype(float)) / 2
    reach = shells.D.astype(float) / 2 + shells.width.astype(float)
    return shells[~(reach > half)]


def _fig8_shells(shells):
    """The rows of a kappa_shells table (one rung's) that Fig. 8 is about: finite κ, shells that
    stay inside the box, system I, μ = 0.5, the most common K_n (the rows fitset's κ fit uses)."""
    df = inside_box(shells[np.isfinite(shells.kappa.astype(float))])
    df = df[(df.system.astype(str) == "I") & np.isclose(df.mu.astype(float), 0.5)]
    return df[np.isclose(df.kn, df.kn.value_counts().idxmax())] if len(df) else df


def kappa_points(shells):
    """The runs of a kappa_shells table that Fig. 8 is about (_fig8_shells), replicate beds
    (same D, Fr and width, other seed) averaged: columns D, Fr, width, kappa, n_beds, var (their
    variance, NaN for one bed)."""
    df = _fig8_shells(shells)
    if df.empty:
        return pd.DataFrame(columns=["D", "Fr", "width", "kappa", "n_beds", "var"])
    df = df.assign(Fr=df.Fr.astype(float).round(6), width=df.width.astype(float).round(6))
    g = df.groupby(["D", "Fr", "width"]).kappa
    return pd.DataFrame({"kappa": g.mean(), "n_beds": g.size(), "var": g.var(ddof=1)}).reset_index()


def _fit_slope(points):
    """κ = k0 + k1 Fr through bed-averaged points; weights from the pooled between-bed variance
    (see kappa_shell_slopes). Returns (Fit, errors_from)."""
    rep = points[points.n_beds >= 2]
    dof = (rep.n_beds - 1).sum()
    s2 = float(((rep.n_beds - 1) * rep["var"]).sum() / dof) if dof else math.nan
    if np.isfinite(s2) and s2 > 0:
        sigma = np.sqrt(s2 / points.n_beds.to_numpy(float))
        return fit_linear(points.Fr, points.kappa, sigma), f"between-bed spread ({int(dof)} dof)"
    return fit_linear(points.Fr, points.kappa), "residual scatter (no replicate beds)"


def kappa_shell_slopes(shells):
    """k0, k1 of κ = k0 + k1 Fr at each shell width, all D pooled (D = "all") and per D, per
    rung (column `rung`, when the table has one).

    Errors: the replicate beds of a point (same D and Fr, other seed) are averaged first; the
    between-bed variance, pooled over every replicated point of the fit (a point's own rests on
    1 dof with 2 beds and would weigh the points by luck; analysis.core.table.pooled_drag_err), over
    the beds of each point weighs it. The line's covariance is the one these errors give,
    scaled up by the reduced χ² when it exceeds 1 (the points scatter about the line more than
    the beds do: κ is not linear in Fr, or the beds' spread is underestimated), as fits.fit_linear
    does. Without replicate beds: unweighted, the residual-variance-scaled covariance. A fit
    needs 3 points, and a rung whose series have fewer than OBSERVABLE_MIN_SPEEDS speeds (a
    yield and depth sweep's three yield pulls, one speed per D) is not studied: no rows, as the
    report has no κ number for it (analysis.report.verdicts.observables_studied)."""
    shells = shells if "rung" in shells.columns else shells.assign(rung="")
    rows = []
    for rung, s in shells.groupby("rung", sort=False):
        if distinct_speeds(_fig8_shells(s)) < OBSERVABLE_MIN_SPEEDS:
            continue        # κ at a few speeds (a yield sweep's one speed per D): not studied
        pts = kappa_points(s)
        groups = [("all", pts)] + [(f"{D:g}", g) for D, g in pts.groupby("D")]
        for D, g in groups:
            for w, p in g.groupby("width"):
                if len(p) < 3:
                    continue
                fit, how = _fit_slope(p)
                rows.append({"rung": rung, "D": D, "width": float(w), "k0": fit["k0"].value,
                             "k0_err": fit["k0"].err, "k1": fit["k1"].value, "k1_err": fit["k1"].err,
                             "n_points": len(p), "n_runs": int(p.n_beds.sum()), "errors_from": how})
    return pd.DataFrame(rows, columns=SLOPE_COLUMNS)


DECOMPOSITION_COLUMNS = ["rung", "D", "width", "Fr_low", "Fr_high", "n_low", "n_high", "Z_low", "Z_high",
                         "n_ratio", "Z_ratio", "kappa_ratio"]
# The Froude numbers the decomposition compares: the paper's Fig. 8 runs from about Fr = 1 to 10.
DECOMPOSITION_FR = (1.0, 10.0)
DECOMPOSITION_WIDTHS = (2.0, 4.0, 6.0)


def kappa_decomposition(shells, fr=DECOMPOSITION_FR, widths=DECOMPOSITION_WIDTHS):
    """Why κ = (Z/n)(D+d)²/(2√3 d²) rises or not: n and Z at the pulled Froude numbers nearest
    fr (low, high) for each D and shell width, bed-averaged, and their ratios high/low. κ rises
    by n_ratio⁻¹ Z_ratio; the paper's line rises by (0.887 + 0.185·10)/(0.887 + 0.185) = 2.55
    from Fr 1 to 10, and says "n … decreases faster than Z" (Sec. III B)."""
    shells = shells if "rung" in shells.columns else shells.assign(rung="")
    df = pd.concat([_fig8_shells(s) for _, s in shells.groupby("rung", sort=False)]) if len(shells) else shells
    rows = []
    for (rung, D), g in df.groupby(["rung", "D"], sort=False):
        frs = np.unique(g.Fr.astype(float))
        lo, hi = (float(frs[np.argmin(np.abs(frs - f))]) for f in fr)
        if lo == hi:
            continue
        for w in widths:
            at = g[np.isclose(g.width.astype(float), w)]
            if at.empty:
                continue
            a, b = at[np.isclose(at.Fr, lo)], at[np.isclose(at.Fr, hi)]
            n_lo, n_hi = a.n_contacts.mean(), b.n_contacts.mean()
            z_lo, z_hi = a.Z.mean(), b.Z.mean()
            rows.append({"rung": rung, "D": float(D), "width": w, "Fr_low": lo, "Fr_high": hi, "n_low": n_lo,
                         "n_high": n_hi, "Z_low": z_lo, "Z_high": z_hi, "n_ratio": n_hi / n_lo,
                         "Z_ratio": z_hi / z_lo, "kappa_ratio": (z_hi / n_hi) / (z_lo / n_lo)})
    return pd.DataFrame(rows, columns=DECOMPOSITION_COLUMNS)


# --- the start of a pull, kept as the paper may have kept it ----------------------

STARTUP_FIT_COLUMNS = ["rung", "D", "pull", "fr_max", "continuous", "Fr1", "Fr1_err", "Fr2", "Fr2_err",
                       "delta_at_5", "note"]
PAPER_PULL = paper.SYSTEMS["I"][0]  # d: system I's box length, the paper's pull


def _drag_series(table):
    """The μ = 0.5 drag-vs-Fr series that fitset.run_fits fits (system I, the reference contact
    law, yield pulls out) and the table's bed scatter."""
    kn, gn = reference_params(table)
    series = select(select(table, kn=kn, gamman=gn), mu=0.5, system="I")
    return series[~is_yield(series)], point_bed_scatter(table[~is_yield(table)]), kn


def _crossover_fit(fr, drag, err, continuous, *, bed_scatter, beds, n_boot, seed):
    """Fr1, Fr2 (with errors), the χ² profile at the paper's Fr2 (delta_at_5) and the fit's
    notes, as a row's fields; NaN and the reason when the fit cannot be made."""
    try:
        fit = fit_regimes(fr, drag, err, regime1="constant", continuous=continuous, n_boot=n_boot, seed=seed,
                          bed_scatter=bed_scatter, beds=beds)
    except ValueError as exc:
        return {**dict.fromkeys(("Fr1", "Fr1_err", "Fr2", "Fr2_err", "delta_at_5"), math.nan), "note": str(exc)}
    delta = profile_fr2(fr, drag, err, [paper.CROSSOVER_FR2], continuous=continuous)[0][2]
    return {"Fr1": fit["Fr1"].value, "Fr1_err": fit["Fr1"].err, "Fr2": fit["Fr2"].value,
            "Fr2_err": fit["Fr2"].err, "delta_at_5": delta,
            "note": "; ".join(fit.meta.get("at_bounds", []) + fit.meta.get("violations", []))}


def kept_drag(drag, whole_mean, travel, pull=PAPER_PULL):
    """The mean force over a pull of `pull` d whose start is the one pulled here (over `travel`
    d, mean whole_mean) and whose rest runs at the steady drag: the start's excess work
    (whole_mean - drag) travel spread over `pull`."""
    return drag + (whole_mean - drag) * travel / pull


def startup_refit(startup, table, fr_max_values=(10.0, 15.0), *, n_boot=LADDER_N_BOOT, seed=0, rung=""):
    """Fr_2 of the mu = 0.5 series per D fitted to the drag with the start of each pull kept and
    diluted over the paper's 40 d pull (kept_drag), beside the same fit of the steady drag
    (pull = "steady"): the start of a fast pull is an impact (the intruder starts at V), whose
    excess force grows about as V^2, so kept in a cumulative average it could add a quadratic
    rise by itself. Both fits take the point table's series, weights (pooled_drag_err) and bed
    scatter exactly as fr2_vs_range does; the kept drag shifts each point by the bed-averaged
    start excess of its runs in `startup`."""
    rows = []
    series, bed_scatter, kn = _drag_series(table)
    st = startup[np.isclose(startup.mu.astype(float), 0.5) & (startup.system.astype(str) == "I")]
    st = st[np.isclose(st.kn.astype(float), kn)]
    if series.empty or st.empty:
        return pd.DataFrame(rows, columns=STARTUP_FIT_COLUMNS)
    excess = (kept_drag(st.drag, st.whole_mean, st.travel) - st.drag).groupby(
        [st.D.astype(float).round(6), st.Fr.astype(float).round(6)]).mean()
    for D, g in series.groupby("D"):
        g = g.sort_values("Fr")
        shift = np.array([excess.get((round(float(D), 6), round(float(fr), 6)), np.nan) for fr in g.Fr])
        err, fr = np.asarray(pooled_drag_err(g), float), g.Fr.to_numpy(float)
        beds = int(g["n_beds"].min()) if "n_beds" in g.columns else 1
        for label, y in (("steady", g.drag.to_numpy(float)),
                         (f"start kept, {PAPER_PULL:g} d", g.drag.to_numpy(float) + shift)):
            for fr_max in fr_max_values:
                m = (fr <= fr_max + 1e-9) & np.isfinite(y)
                for continuous in (True, False):
                    rows.append({"rung": rung, "D": float(D), "pull": label, "fr_max": float(fr_max),
                                 "continuous": continuous,
                                 **_crossover_fit(fr[m], y[m], err[m], continuous, bed_scatter=bed_scatter,
                                                  beds=beds, n_boot=n_boot, seed=seed)})
    return pd.DataFrame(rows, columns=STARTUP_FIT_COLUMNS)


# --- Fr_2 against the fitted range ----------------------------------------------

FR2_COLUMNS = ["rung", "D", "fr_max", "continuous", "Fr1", "Fr1_err", "Fr2", "Fr2_err", "delta_at_5",
               "n_points", "fr_used_max", "note"]


def fr2_vs_range(table_df, fr_max_values=FR_MAX_VALUES, *, n_boot=LADDER_N_BOOT, seed=0, rung=""):
    """The crossovers of the μ = 0.5 drag-vs-Fr series of each D (system I, the reference
    contact law, yield pulls out: as fitset.run_fits fits them, with pooled_drag_err weights
    and the table's bed scatter) refitted on the points with Fr <= fr_max, continuous and not.
    Does Fr_2 settle as the range grows, or follow it? delta_at_5: the fit's chi-square profile
    at Fr_2 = 5, the paper's (regimes.profile_fr2; above 3.84 the data exclude 5 at 95 %
    whatever the bootstrap says). A fit that cannot be made (too few points) is a row with NaN
    and the reason in `note`. Fixed seed: deterministic."""
    series, bed_scatter, _ = _drag_series(table_df)
    rows = []
    for D, g in series.groupby("D"):
        moving = g.sort_values("Fr")
        for fr_max in fr_max_values:
            used = moving[moving.Fr <= fr_max + 1e-9]
            beds = int(used["n_beds"].min()) if "n_beds" in used.columns and len(used) else 1
            for continuous in (True, False):
                rows.append({"rung": rung, "D": float(D), "fr_max": float(fr_max), "continuous": continuous,
                             "n_points": len(used), "fr_used_max": float(used.Fr.max()) if len(used) else math.nan,
                             **_crossover_fit(used.Fr, used.drag, pooled_drag_err(used), continuous,
                                              bed_scatter=bed_scatter, beds=beds, n_boot=n_boot, seed=seed)})
    return pd.DataFrame(rows, columns=FR2_COLUMNS)


# --- the drag's slope above Fr 5 against below -----------------------------------

KNEE_COLUMNS = ["rung", "D", "knee", "fr_low", "fr_high", "level", "level_err", "slope_below", "slope_below_err",
                "slope_above", "slope_above_err", "ratio", "ratio_err", "steepening", "steepening_err", "z",
                "chi2_red", "n_points", "note"]
KNEE_FR = paper.CROSSOVER_FR2   # the paper's Fr_2
KNEE_RANGE = (1.0, 10.0)  # its regime II starts at Fr_1 ≈ 1; its data end at Fr = 10


def knee_at_five(table_df, *, knee=KNEE_FR, fr_range=KNEE_RANGE, rung=""):
    """Does the drag steepen past Fr = 5, as the paper's regime III (linear up to Fr_2 ≈ 5,
    quadratic beyond) says it must? A test that needs no fitted crossover: the μ = 0.5 series of
    each D (the point table's, weighted as fr2_vs_range weighs it: pooled_drag_err) on
    fr_range, fitted by a line broken at `knee` (fits.fit_broken_line). slope_above / slope_below is 1 for
    one straight line, above 1 for a quadratic rise beyond the knee (a regime III a2 + b2 Fr²
    joined smoothly to a regime II line at 5, i.e. with its slope 10 b2 there, has a secant slope
    15 b2 over 5-10: 1.5), near 0 for a plateau. steepening = slope_above - slope_below and z its ratio to
    its error: z > 2 says the drag steepens past 5, z < -2 that it flattens. Needs 2 points on
    each side of the knee."""
    series, _, _ = _drag_series(table_df)
    rows = []
    for D, g in series.groupby("D"):
        g = g[(g.Fr >= fr_range[0] - 1e-9) & (g.Fr <= fr_range[1] + 1e-9)].sort_values("Fr")
        # Points with a drag and an error only: the fit would drop a missing drag, and one missing
        # error would make it unweighted.
        err = np.asarray(pooled_drag_err(g), float)
        usable = np.isfinite(g.drag.to_numpy(float)) & np.isfinite(err) & (err > 0)
        g, err = g[usable], err[usable]
        fr = g.Fr.to_numpy(float)
        base = {"rung": rung, "D": float(D), "knee": knee, "fr_low": fr_range[0], "fr_high": fr_range[1],
                "n_points": len(g)}
        if (fr < knee).sum() < 2 or (fr > knee).sum() < 2:
            rows.append({**base, "note": f"needs 2 points on each side of Fr = {knee:g} in "
                                         f"{fr_range[0]:g}-{fr_range[1]:g}"})
            continue
        fit = fit_broken_line(fr, g.drag.to_numpy(float), err, knee)
        p, cov, e = np.array(list(fit.values().values())), fit.covariance, [q.err for q in fit.params.values()]
        ratio = p[2] / p[1]
        # First order in both slopes, with their covariance.
        grad = np.array([0.0, -p[2] / p[1] ** 2, 1.0 / p[1]])
        diff_err = math.sqrt(cov[1, 1] + cov[2, 2] - 2 * cov[1, 2])
        rows.append({**base, "level": p[0], "level_err": e[0], "slope_below": p[1], "slope_below_err": e[1],
                     "slope_above": p[2], "slope_above_err": e[2], "ratio": ratio,
                     "ratio_err": math.sqrt(grad @ cov @ grad), "steepening": p[2] - p[1],
                     "steepening_err": diff_err, "z": (p[2] - p[1]) / diff_err,
                     "chi2_red": fit.meta["goodness"]["chi2_dof"],
                     "note": "slope below the knee not positive: the ratio means nothing" if p[1] <= 0 else ""})
    return pd.DataFrame(rows, columns=KNEE_COLUMNS)
