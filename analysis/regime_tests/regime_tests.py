"""Claim (a) tested so that a test can say what it cannot see: the drag is about constant below Fr₁ ≈ 1
(regime I), linear from there (II) and quadratic from Fr₂ ≈ 5 (III). For each drag-vs-Fr series of a
table (system I: per D; system II: per depth h; per μ and K_n) and each averaging of the drag, on
1 ≤ Fr ≤ 10 (the paper's data) and 1 ≤ Fr ≤ 15:

  line            a + b Fr, the null every test compares against
  quadratic       a + b Fr + c Fr²: c ± σ_c, Δχ² = -(c/σ_c)²
  paper_fr2_5     the paper's shape (line up to Fr₂, then a' + b' Fr² joined continuously) at Fr₂ = 5
  paper_fr2_free  the same with Fr₂ profiled (its Δχ² ≤ 1 interval)

and on Fr ≤ 3 regime1: a plateau up to Fr₁ continued by a line, Fr₁ profiled, against one line.
Δχ² = χ²(model) - χ²(line): negative when the model fits better. Each test's threshold, p-value,
false-positive rate and power against the paper's size are calibrated on synthetic copies of the
series with its own errors and speeds (analysis.regime_tests.regime_power); the verdict says "shown", "a line
preferred; the paper's size excluded at N σ" or "these data cannot tell; about K× as many beds
would", never "not seen" for what the data cannot tell apart. The fits: analysis.regime_tests.regime_fits.

Errors: the averaging's own error column (drag_err: a point's error with its beds' scatter), as
the issue that asked for these tests weighed them, with the covariance a bed's shift puts between
the speeds pulled through it (analysis.core.bed_shift: every pull of a bed crosses the same grains)
when the table records it (drag_shift_r2; a table made before it: the errors alone); scaled up by
√(χ²/dof) of the quadratic when above 1 (scatter beyond the errors; the quadratic's, so that a
curvature does not pass for noise), `noise_scale` in the table. Yield pulls are left out (their
drag is F_Y, not a drag at speed).

Averagings (AVERAGINGS; `averaging` "both", "steady" or "cumulative", the command's --averaging): the
steady drag (column drag) and the paper's cumulative average from t = 0 over one box length, its pull
(drag_cumulative_box: a curve whose speeds were pulled different lengths is read at one length), each with its
own error column; every test is run under each, and every output says which.

regime_tests.md: the verdicts in words, a section per averaging (summary_markdown).
regime_tests.csv, one row per series × averaging × range × test (COLUMNS): chi2, dof of the test's
model; delta_chi2 against the line; coef (b for the line and regime I, c, b' for the paper's shape)
with coef_value, coef_err; crossover (Fr₂, Fr₁) and its Δχ² ≤ 1 interval crossover_lo, _hi;
statistic (c/σ_c or -Δχ²), its p under the null, the 5 % threshold, power against the paper's size
and against the best fit (power_best_fit), the false_positive_rate measured on fresh lines,
beds_for_80 (the factor of beds for 80 % power: 1 when reached, inf beyond 128), excluded_sigma
(the observation's distance below the paper's size) and excluded_at_limit (no copy reached it: a
lower bound), n_beds; outcome (the verdict's kind, regime_power.outcome); verdict; note.
"""
import math
from pathlib import Path

import numpy as np
import pandas as pd

from ..core.bed_shift import covariance
from ..core.table import is_yield, write_csv, write_text_atomic
from .regime_fits import (
    fit_line,
    fit_paper_shape,
    fit_quadratic,
    profile_paper_shape,
    profile_plateau_line,
    scale,
)
from .regime_power import N_SIM, Calibration, outcome, verdict

# (name, drag column, error column): the steady drag the table has always had, and the paper's
# cumulative average (the whole pull, its start included) when the table has it.
AVERAGINGS = (("steady", "drag", "drag_err"), ("cumulative", "drag_cumulative_box", "drag_cumulative_box_err"))
AVERAGING_NAMES = tuple(a[0] for a in AVERAGINGS)
# What each averaging is, for the summary (regime_tests.md).
AVERAGING_TEXT = {
    "steady": "The steady drag: -F_x averaged after the start's transient is discarded (column drag)",
    "cumulative": "The cumulative average from t = 0 over one box length, the start included (column "
                  "drag_cumulative_box): the averaging of the paper's Fig. 4, which its drags imply, at its "
                  "pull length; a shorter pull's start is spread over a box length (analysis.runs.run_series)"}
RANGES = ((1.0, 10.0), (1.0, 15.0))
REGIME1_RANGE = (0.0, 3.0)
GROUP = ["system", "D", "h", "mu", "kn"]   # h: a system II series' depth (NaN for system I)
COLUMNS = GROUP + ["averaging", "fr_low", "fr_high", "test", "n_points", "chi2", "dof", "delta_chi2", "coef",
                   "coef_value", "coef_err", "crossover", "crossover_lo", "crossover_hi", "statistic", "p",
                   "threshold", "power", "power_best_fit", "false_positive_rate", "beds_for_80",
                   "excluded_sigma", "excluded_at_limit", "noise_scale", "n_beds", "outcome", "verdict", "note"]
MIN_SPEEDS = 5   # distinct speeds a range needs: the profiled shapes keep 2 on each side of Fr₂


def _g(v, digits=2):
    return f"{v:.{digits}g}"


def _dchi(d):
    return f"Δχ² = {0.0 if abs(d) < 0.005 else d:.2f}"


def _pm(v, e):
    """v ± e with e to two significant figures and v to the same decimals."""
    d = max(0, 1 - math.floor(math.log10(abs(e)))) if e > 0 and math.isfinite(e) else 2
    return f"{v:.{d}f} ± {e:.{d}f}"


def in_range(fr, F, err, lo, hi):
    """The points with lo ≤ Fr ≤ hi, a finite drag and a positive error, sorted by Fr: (Fr, drag,
    their covariance); err the points' standard errors or their covariance (bed_shift.covariance)."""
    fr, F, err = (np.asarray(v, float) for v in (fr, F, err))
    var = err ** 2 if err.ndim == 1 else np.diag(err)
    m = (fr >= lo - 1e-9) & (fr <= hi + 1e-9) & np.isfinite(F) & np.isfinite(var) & (var > 0)
    idx = np.flatnonzero(m)[np.argsort(fr[m], kind="stable")]
    cov = np.diag(var[idx]) if err.ndim == 1 else err[np.ix_(idx, idx)]
    return fr[idx], F[idx], cov


def noise_scale(x, y, s):
    """√(χ²/dof) of the quadratic when above 1, else 1 (module docstring)."""
    q = fit_quadratic(x, y, s)
    return math.sqrt(q["chi2"] / q["dof"]) if q["dof"] > 0 and q["chi2"] > q["dof"] else 1.0


def _calibrated(row, test, x, y, s, shown, found, alternative, n_sim, seed, beds):
    cal = Calibration(test, x, y, s, n_sim=n_sim, seed=seed)
    n, at_limit = cal.excluded_sigma
    row.update(statistic=cal.observed, p=cal.p, threshold=cal.threshold, power=cal.power,
               power_best_fit=cal.power_best_fit, false_positive_rate=cal.false_positive_rate,
               beds_for_80=cal.beds_for(), excluded_sigma=n, excluded_at_limit=at_limit,
               outcome=outcome(cal, fits_worse=row["delta_chi2"] > 0),
               verdict=verdict(shown, found, cal, alternative, beds, fits_worse=row["delta_chi2"] > 0))
    if at_limit:
        limit = "excluded_sigma a lower bound (no copy reached it)"
        row["note"] = "; ".join(filter(None, [row.get("note", ""), limit]))
    return row


def regime3_rows(fr, F, err, lo, hi, *, n_sim=N_SIM, seed=0, beds=None):
    """The rows of the line, the quadratic and the paper's shape (Fr₂ = 5 and profiled) on lo ≤ Fr ≤ hi."""
    x, y, s = in_range(fr, F, err, lo, hi)
    base = {"fr_low": lo, "fr_high": hi, "n_points": len(x), "n_beds": beds}
    if len(np.unique(x)) < MIN_SPEEDS:
        return [{**base, "test": t, "note": f"{len(np.unique(x))} speeds in {lo:g}-{hi:g}: needs {MIN_SPEEDS}"}
                for t in ("line", "quadratic", "paper_fr2_5", "paper_fr2_free")]
    factor = noise_scale(x, y, s)
    s = scale(s, factor)
    base["noise_scale"] = factor
    line, quad = fit_line(x, y, s), fit_quadratic(x, y, s)
    fixed, free = fit_paper_shape(x, y, s), profile_paper_shape(x, y, s)
    rows = [{**base, "test": "line", "chi2": line["chi2"], "dof": line["dof"], "coef": "b", "coef_value": line["b"],
             "coef_err": line["b_err"]}]
    alternative = "a paper-sized quadratic from Fr₂ = 5"   # regime_power.paper_sized: tangent to the line
    dq = quad["chi2"] - line["chi2"]
    row = {**base, "test": "quadratic", "chi2": quad["chi2"], "dof": quad["dof"], "delta_chi2": dq, "coef": "c",
           "coef_value": quad["c"], "coef_err": quad["c_err"]}
    rows.append(_calibrated(row, "quadratic", x, y, s, "a quadratic rise",
                            f"c = {_pm(quad['c'], quad['c_err'])}, {_dchi(dq)}", alternative,
                            n_sim, seed, beds))
    for test, fit in (("paper_fr2_5", fixed), ("paper_fr2_free", free)):
        d = fit["chi2"] - line["chi2"]
        row = {**base, "test": test, "chi2": fit["chi2"], "dof": fit["dof"], "delta_chi2": d, "coef": "b2",
               "coef_value": fit["b2"], "coef_err": fit["b2_err"], "crossover": fit["Fr2"],
               "note": _paper_note(fit, hi)}
        where = "Fr ≈ 5"
        if test == "paper_fr2_free":
            row.update(crossover_lo=fit["Fr2_lo"], crossover_hi=fit["Fr2_hi"])
            where = f"Fr₂ = {_g(fit['Fr2'])} ({_g(fit['Fr2_lo'])}-{_g(fit['Fr2_hi'])})"
        shown = f"a quadratic from {where}"
        if _slope_drops(fit):
            past = 2 * fit["b2"] * fit["Fr2"]
            shown += f", its slope dropping there from {fit['b']:.3g} to {past:.3g} before it rises,"
        rows.append(_calibrated(row, test, x, y, s, shown, _dchi(d), alternative, n_sim, seed, beds))
    return rows


def _slope_drops(fit):
    """Whether the shape's slope just past Fr₂, 2b' Fr₂, is below the line's b before it: the paper's
    regime III steepens there; a drop is a kink down that the quadratic then makes up."""
    return 2 * fit["b2"] * fit["Fr2"] < fit["b"]


def _paper_note(fit, end):
    notes = []
    if _slope_drops(fit) and not fit["held"]:
        notes.append(f"the slope drops at Fr₂, from b = {fit['b']:.3g} to 2b' Fr₂ = {2 * fit['b2'] * fit['Fr2']:.3g}, "
                     "and rises again past it: a kink down, then a quadratic, not a steepening at Fr₂")
    if fit["held"]:
        notes.append(f"b' held at its least, b / (Fr₂ + {end:g}): the free fit's drag flattened past Fr₂")
    if fit.get("at_edge"):
        notes.append("the Fr₂ interval reaches the profiled grid's end (open)")
    return "; ".join(notes)


def regime1_row(fr, F, err, lo, hi, *, n_sim=N_SIM, seed=0, beds=None):
    """The row of regime I's plateau-then-line against one line on lo ≤ Fr ≤ hi."""
    x, y, s = in_range(fr, F, err, lo, hi)
    base = {"fr_low": lo, "fr_high": hi, "test": "regime1", "n_points": len(x), "n_beds": beds}
    if len(np.unique(x)) < 4:
        return {**base, "note": f"{len(np.unique(x))} speeds in {lo:g}-{hi:g}: needs 4"}
    factor = noise_scale(x, y, s)
    s = scale(s, factor)
    line, fit = fit_line(x, y, s), profile_plateau_line(x, y, s)
    d = fit["chi2"] - line["chi2"]
    row = {**base, "noise_scale": factor, "chi2": fit["chi2"], "dof": fit["dof"], "delta_chi2": d, "coef": "b",
           "coef_value": fit["b"], "crossover": fit["Fr1"], "crossover_lo": fit["Fr1_lo"],
           "crossover_hi": fit["Fr1_hi"],
           "note": ("the Fr₁ interval reaches the profiled grid's end (open; at the slowest speed the plateau is "
                    "empty: one line)") if fit["at_edge"] else ""}
    shown = f"a plateau up to Fr₁ = {_g(fit['Fr1'])} ({_g(fit['Fr1_lo'])}-{_g(fit['Fr1_hi'])})"
    return _calibrated(row, "regime1", x, y, s, shown, _dchi(d),
                       "a paper-sized plateau (up to Fr₁ = 1)", n_sim, seed, beds)


def series(table):
    """(keys, rows) of each drag-vs-Fr series of the table: pulls at speed, grouped by GROUP."""
    df = table[~is_yield(table)]
    h = np.where(df.system.astype(str) == "II", df.h.astype(float).round(6), np.nan)
    df = df.assign(h=h)
    for keys, g in df.groupby(GROUP, dropna=False, sort=True):
        yield dict(zip(GROUP, keys)), g.sort_values("Fr")


def averagings(table, which="both"):
    """The averagings the table has, (name, drag column, error column); which: "both" (every one it
    has), "steady" or "cumulative" (that one: ValueError, naming its columns, when the table lacks it)."""
    have = [a for a in AVERAGINGS if {a[1], a[2]} <= set(table.columns)]
    if which == "both":
        return have
    if which not in AVERAGING_NAMES:
        raise ValueError(f"averaging {which!r}: one of {', '.join(AVERAGING_NAMES)} or both")
    found = [a for a in have if a[0] == which]
    if not found:
        a = next(a for a in AVERAGINGS if a[0] == which)
        raise ValueError(f"the {which} averaging needs columns {a[1]} and {a[2]}, which the table lacks "
                         f"(a table made before them: rebuild it from its runs, analysis.ladder_refit)")
    return found


def series_beds(g):
    """A series' beds for the verdict's "N instead of n": its typical point's (a curve whose slowest
    point has one bed so far is not a one-bed curve; the factor of beds does not depend on it);
    None when the table does not count them."""
    return int(round(g.n_beds.median())) if "n_beds" in g.columns and g.n_beds.notna().all() else None


def regime_tests(table, *, ranges=RANGES, regime1_range=REGIME1_RANGE, n_sim=N_SIM, seed=0, averaging="both"):
    """Every test of every series and averaging of the table (DataFrame, COLUMNS); averaging as
    averagings' `which`."""
    rows = []
    chosen = averagings(table, averaging)
    for keys, g in series(table):
        beds = series_beds(g)
        for name, col, err in chosen:
            cols = (g.Fr, g[col], covariance(g, col, err))
            out = [r for lo, hi in ranges for r in regime3_rows(*cols, lo, hi, n_sim=n_sim, seed=seed, beds=beds)]
            out.append(regime1_row(*cols, *regime1_range, n_sim=n_sim, seed=seed, beds=beds))
            rows += [{**keys, "averaging": name, **r} for r in out]
    return pd.DataFrame(rows, columns=COLUMNS)


def write_tests(table, outdir, **kw):
    """regime_tests.csv and its summary regime_tests.md (summary_markdown) in outdir, written
    atomically; returns (the tests, the csv's path). The figures: analysis.regime_tests.regime_figure.draw."""
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    tests = regime_tests(table, **kw)
    write_csv(tests, outdir / "regime_tests.csv")
    write_text_atomic(outdir / "regime_tests.md", summary_markdown(tests))
    return tests, outdir / "regime_tests.csv"


def _series_title(r):
    where = f"h = {r.h:g}" if np.isfinite(float(r.h)) else f"D = {r.D:g}"
    return f"system {r.system}, {where}, μ = {r.mu:g}, K_n = {r.kn:g}"


def summary_markdown(tests):
    """The tests' verdicts in words, a section per averaging (what it is, AVERAGING_TEXT), a table per
    series: range, test, Δχ² against the line, the coefficient, p, power, verdict."""
    lines = ["# Claim (a): regime tests", "",
             "Each test under each averaging of the drag; Δχ² against one line (negative: the model fits "
             "better), p and power calibrated on synthetic copies of the series "
             "(analysis/regime_tests/regime_tests.py).", ""]
    for name in [a for a in AVERAGING_NAMES if a in set(tests.averaging)]:
        lines += [f"## {name} averaging", "", AVERAGING_TEXT[name] + ".", ""]
        part = tests[tests.averaging == name]
        for _, g in part.groupby(GROUP, dropna=False, sort=False):
            lines += [f"### {_series_title(g.iloc[0])} ({name})", "",
                      "| Fr | test | Δχ² | coefficient | p | power | verdict |", "|---|---|---|---|---|---|---|"]
            for r in g.itertuples():
                coef = (f"{r.coef} = {_pm(r.coef_value, r.coef_err)}" if isinstance(r.coef, str)
                        and np.isfinite(r.coef_err) else f"{r.coef} = {r.coef_value:.4g}" if isinstance(r.coef, str)
                        else "")
                cells = [f"{r.fr_low:g}-{r.fr_high:g}", r.test, "" if pd.isna(r.delta_chi2) else f"{r.delta_chi2:.2f}",
                         coef, "" if pd.isna(r.p) else f"{r.p:.2g}", "" if pd.isna(r.power) else f"{r.power:.2f}",
                         r.verdict if isinstance(r.verdict, str) else (r.note if isinstance(r.note, str) else "")]
                lines.append("| " + " | ".join(str(c).replace("|", "/") for c in cells) + " |")
            lines.append("")
    return "\n".join(lines)
