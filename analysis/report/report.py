"""The report: every figure and each fitted number beside the paper's value.

Verdict for a number with a published value p (the paper gives no error
bars, so only ours count):
  inconclusive       no error bar, an error above INCONCLUSIVE (30 %) of the value,
                     a fit that breaks its model (drag falling with Fr in regime
                     II or III), whose model the data reject (its residuals trend or
                     its χ² is far out: goodness.py; the report then says "model rejected (...)" in
                     place of the number), that ended on a bound of its parameters,
                     or a fit with no degrees of freedom left: such a number could
                     agree with anything; also one whose interval would be Student's t
                     at fewer than 2 dof (untestable at that study)
  within error bars  |fit - p| <= t standard errors, t the two-sided 95 % Student-t
                     quantile at the fit's degrees of freedom (points - parameters;
                     1.96 for a number that has no fit of its own, or whose error is
                     its points' errors unscaled: errors_from_points)
  qualitatively      otherwise, but |fit - p| <= 25 % of |p|
  not reproduced     otherwise (or no fit)
The report counts each verdict apart. Beside every number it says whether its fit
ended on a bound, how many replicate beds it rests on, and whether any of its
runs lacked a plateau (table columns SEED_COLUMN and PLATEAU_COLUMN, when present); where
the scatter between beds in its points' errors came from (replicate beds, pooled from the
study's replicated points, a config's prior, or none: analysis.report.report_notes) is stated once
for every fit when all points share it, else beside each number.
"""
import math
from collections import Counter
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path

import numpy as np

from ..core import paper
from ..core.claims import CLAIMS, claim_of
from ..core.result import N_BOOT, Param, format_pm
from ..core.table import is_yield, reference_params, select, write_text_atomic, yield_rows
from ..figures.figure_list import FIGURES, NAMES, Inputs, draw
from ..figures.figures import not_drawn_reason
from ..fits.fitset import Results, load_results, named_fits, run_fits, save_results
from ..fits.goodness import describe, rejection_text
from .report_notes import (
    PLATEAU_COLUMN,
    SEED_COLUMN,
    basis_notes,
    bed_scatter_sentence,
    shared_caveats,
    uniform_bed_scatter,
)
from .report_render import SYMBOLS, markdown, to_html
from .verdicts import (  # noqa: F401  (re-exported: the report's verdict rules)
    COVERAGE,
    INCONCLUSIVE,
    REL_TOL,
    VERDICTS,
    errors_from_points,
    fit_dof,
    observables_studied,
    sum_dof,
    sum_goodness,
    table_dof,
    table_goodness,
    verdict,
    within_quantile,
)

__all__ = ["PLATEAU_COLUMN", "SEED_COLUMN", "Results", "build_report", "comparisons", "run_fits", "shared_caveats",
           "verdict", "write_report"]


# --- comparisons ---------------------------------------------------------

@dataclass
class Row:
    quantity: str
    fitted: str
    published: str
    verdict: str
    sentence: str
    notes: list = field(default_factory=list)   # bounds, model violations, beds, plateaus
    base: str = ""                              # the sentence without its notes
    rejected: str = ""                          # "model rejected (...)" when the data reject the fit

    def shown(self):
        """The fitted cell of the report's table: the number, or why it is not a finding."""
        return self.rejected or self.fitted


def _row(quantity, p, published, shown=None, fit=None, rows=None, extra="", dof=None, goodness=None,
         bed_scatter=True, observable=False):
    meta = fit.meta if fit is not None else {}
    g = goodness if goodness is not None else meta.get("goodness")
    rejected = rejection_text(g) if g and g.get("rejected") else ""
    v, why = verdict(p, published, meta.get("violations", ()), meta.get("at_bounds", ()),
                     fit_dof(fit) if dof is None else dof, rejected, errors_from_points(fit, g),
                     meta.get("ill_posed", ""))
    shown = shown or f"{published:g}"
    notes = ([rejected] if rejected else []) + ([meta["ill_posed"]] if meta.get("ill_posed") else [])
    notes += list(meta.get("at_bounds", [])) + list(meta.get("violations", []))
    if rows is not None:
        notes += basis_notes(rows, bed_scatter, observable)
    tail = f" [{'; '.join(notes)}]" if notes else ""
    said = f"model rejected, the fitted {p} is not a finding" if rejected else (p if p else "n/a")
    base = f"{quantity}: {said} against {shown} — {v} ({why}){extra}."
    return Row(quantity, str(p) if p else "n/a", shown, v, base + tail, notes, base, rejected)


def _moving(rows):
    return rows[~is_yield(rows)]


def comparisons(r, df=None):
    """Rows of the report's table; with the pull table df, each says what its fit rests on (the
    bed scatter of its points only when the table's points do not all share one source: the
    report's introduction states it once)."""
    entry = partial(_row, bed_scatter=not uniform_bed_scatter(df))
    ref = None
    if df is not None:
        kn, gn = reference_params(df)
        ref = select(df, kn=kn, gamman=gn)
    sub = (lambda **k: select(ref, **k)) if ref is not None else (lambda **k: None)
    rows = []
    for (label, mu, key), fit in sorted(r.regimes.items(), key=lambda kv: (kv[0][0], -kv[0][1], kv[0][2])):
        where = f"μ = {mu:g}, {label} = {key:.3g}"
        basis = sub(mu=mu, system="I" if label == "D" else "II", **{label: key})
        basis = None if basis is None else _moving(basis)
        rows.append(entry(f"Fr_1 ({where})", fit["Fr1"], paper.CROSSOVER_FR1, "≈ 1", fit, basis))
        rows.append(entry(f"Fr_2 ({where})", fit["Fr2"], paper.CROSSOVER_FR2, "≈ 5", fit, basis))
    h_min = r.options.h_min
    for law in r.laws:
        basis = sub(mu=law.mu)
        if basis is not None:
            basis = _moving(basis[paper.at_least(basis.h, h_min)] if h_min else basis)
        cut = f", h ≥ {h_min:g}" if h_min else ""
        rows.append(entry(f"Fr_1 (Eq. 12 collapse, μ = {law.mu:g}{cut})", law.regimes["Fr1"], 1.0, "≈ 1",
                         law.regimes, basis))
        rows.append(entry(f"Fr_2 (Eq. 12 collapse, μ = {law.mu:g}{cut})", law.regimes["Fr2"], 5.0, "≈ 5",
                         law.regimes, basis))
    obs = sub(mu=0.5, system="I")
    # θ and κ from a few speeds, or from yield pulls only, test nothing: not studied, no row.
    # θ per contact formation, then over the contacts present (time-weighted), each against Eq. 7.
    for col, what, how in (("theta", "θ(Fr)", ""), ("theta_present", "θ_present(Fr)", ", time-weighted")):
        fit = getattr(r, col, None)
        if fit is not None and observables_studied(obs, col, fit):
            for k, name in (("U1", "Υ1"), ("U2", "Υ2"), ("U3", "Υ3")):
                rows.append(entry(f"{what} {name} (Eq. 7{how})", fit[k], paper.THETA[k], fit=fit, rows=obs,
                                 observable=True))
    if r.kappa is not None and observables_studied(obs, "kappa", r.kappa):
        for k in ("k0", "k1"):
            rows.append(entry(f"κ(Fr) {'intercept' if k == 'k0' else 'slope'} (Fig. 8)",
                             r.kappa[k], paper.KAPPA[k], fit=r.kappa, rows=obs,
                             observable=True))
    for D, fit in sorted(r.by("D", 0.0).items()):
        pub = paper.TABLE1.get(int(round(D))) if float(D).is_integer() else None
        if pub and "b0" in fit.params:
            y = fit.meta.get("yield_pull")
            beside = (f"; the yield pull, not in the fit: F_Y = {format_pm(y['drag'], y['drag_err'] or math.nan)}"
                      if y else "")
            basis = sub(mu=0.0, system="I", D=D)
            for k, name, v in zip(("a0", "b0", "c0"), ("a''", "b''", "c''"), pub):
                rows.append(entry(f"Table I {name} (D = {D:g}d)", fit[k], v, fit=fit,
                                 rows=None if basis is None else _moving(basis),
                                 extra=beside if k == "a0" else ""))
    yl = None if ref is None else yield_rows(df)
    for tab, col, pub, name, system in ((r.phi, "phi", paper.PHI_0, "φ_0", "I"),
                                        (r.alpha, "alpha", paper.ALPHA_0, "α_0 (yield force, Fig. 17)", "II")):
        for _, t in (tab[np.isclose(tab.mu, 0.0)].iterrows() if tab is not None else []):
            basis = None if yl is None else select(yl, mu=0.0, kn=t.kn, gamman=t.gamman, system=system)
            rows.append(entry(f"{name} (K_n = {t.kn:.3g})", Param(t[col], t[col + "_err"]), pub,
                             f"≈ {pub:g}", rows=basis, dof=table_dof(t, "n"), goodness=table_goodness(t)))
    ad = r.alpha_drag if r.alpha_drag is not None else []
    for _, t in (ad[np.isclose(ad.mu, 0.0)].iterrows() if len(ad) else []):
        rows.append(entry(f"α_0 (drag, averaged over speeds {t.speeds}; K_n = {t.kn:.3g})",
                         Param(t.alpha, t.alpha_err), paper.ALPHA_0, f"≈ {paper.ALPHA_0:g}",
                         rows=None if df is None else _moving(select(df, mu=0.0, kn=t.kn, gamman=t.gamman,
                                                                      system="II"))))
    for tab, how, alphas, fitted in ((r.sums, "α_μ from the yield force", r.alpha, r.alpha),
                                     (r.sums_drag, "α_μ from the drag, averaged over speeds",
                                      r.alpha_speeds, None)):
        for _, t in (tab.iterrows() if tab is not None else []):
            g = sum_goodness(t, r.phi, alphas)
            rows.append(entry(f"α_μ + φ_μ ({how}; μ = {t.mu:g}, K_n = {t.kn:.3g})",
                             Param(t["sum"], t["sum_err"]), paper.SUM_RULE, "≈ 3",
                             dof=sum_dof(t, r.phi, fitted), goodness=g))
    for D, fit in sorted(r.saturation.items()):
        rows.append(_saturation_row(D, fit))
    return rows


def headline(rows):
    """One line per claim of the paper: its numbers' verdicts, counted by symbol."""
    out = []
    for letter, claim in CLAIMS.items():
        mine = [x for x in rows if claim_of(x.quantity) == letter]
        if not mine:
            out.append(f"({letter}) {claim}: no number of this study tests it.")
            continue
        c = counts(mine)
        tally = ", ".join(f"{SYMBOLS[v]} {c[v]}" for v in VERDICTS if c[v])
        out.append(f"({letter}) {claim}: {tally} of {len(mine)} number{'s' if len(mine) > 1 else ''}.")
    return out


def counts(rows):
    """How many numbers got each verdict (inconclusive counted apart)."""
    c = Counter(x.verdict for x in rows)
    return {v: c.get(v, 0) for v in VERDICTS}


def _saturation_row(D, fit):
    """F_Y saturates if 95 % of its rise (3 mu_c) happens inside the sampled mu."""
    mu_c, mu_max = fit["mu_c"], fit.x_range[1]
    err = mu_c.err if math.isfinite(mu_c.err) else math.inf
    g = fit.meta.get("goodness") or {}
    notes = ([rejection_text(g)] if g.get("rejected") else []) + list(fit.meta.get("at_bounds", []))
    notes += [fit.meta["ill_posed"]] if fit.meta.get("ill_posed") else []
    if notes:
        v = "inconclusive"
    elif 3 * (mu_c.value + within_quantile(fit_dof(fit)) * err) < mu_max:
        v = "reproduced within error bars"
    elif 3 * mu_c.value < mu_max:
        v = "reproduced qualitatively"
    else:
        v = "not reproduced"
    q = f"F_Y saturating in μ (D = {D:g}d)"
    shown = "saturates (Fig. 12)"
    tail = f" [{'; '.join(notes)}]" if notes else ""
    base = (f"{q}: rise scale μ_c = {mu_c} against sampled μ ≤ {mu_max:g} — {v} "
            f"(saturated means 3 μ_c < μ_max).")
    return Row(q, f"μ_c = {mu_c}", shown, v, base + tail, notes, base)


# --- document ------------------------------------------------------------

def _pull_count(df):
    """How many points the table holds, and the pulls behind them: a point pooled over beds (the
    table's n_beds) is that many pulls."""
    beds = df["n_beds"].fillna(1) if "n_beds" in df else None
    if beds is None or (beds <= 1).all():
        return f"{len(df)} pull{'s' if len(df) != 1 else ''}"
    return f"{len(df)} points from {int(beds.sum())} pulls (each point the mean of its beds)"


def _error_methods(fits, none):
    """The fits' error methods as they record them (fits.json's `method`), each once, with how
    many fits used it; `none` when there is no fit."""
    how = Counter(f.method.split("errors = ", 1)[-1] for f in fits)
    if not how:
        return none
    return "; ".join(f"{m} ({k} fit{'s' if k > 1 else ''})" for m, k in how.items())


def _regime_errors(r):
    """The regime fits' error methods as their fits record them, each once, with how many fits
    used it."""
    return _error_methods(r.regimes.values(), "no regime fits")


def _law_errors(r):
    """Eq. 12's collapses (the laws' regime fits) have error methods of their own (the beds
    resampled, alpha and phi refitted): the header names them, not only the regime fits' and
    the other fits' least-squares covariance. Empty without a law."""
    if not r.laws:
        return ""
    return f"; Eq. 12 collapses: errors the {_error_methods([law.regimes for law in r.laws], '')}"


def _blocks(df, r, figs, n_boot, seed):
    kn, gn = reference_params(df)
    b = [("h1", "granudrag: drag scaling in dense granular media"),
         ("p", f"{_pull_count(df)}; systems {', '.join(sorted(df.system.unique()))}; "
               f"μ = {', '.join(f'{m:g}' for m in sorted(df.mu.unique()))}; reference contact law "
               f"K_n = {kn:.3g}, γ_n = {gn:.3g}. Regime fits: crossovers fitted by profile least "
               f"squares, errors the {_regime_errors(r)}{_law_errors(r)}; other fits: "
               "least-squares covariance. Errors are one standard error. " + bed_scatter_sentence(df)),
         ("p", _scale_text(df, kn)),
         ("p", f"Verdicts: inconclusive = no error bar, an error above {INCONCLUSIVE:.0%} of the "
               "value, a fit that breaks its model (drag falling with Fr in regime II or III) or "
               "ended on a bound of its parameters, one with no degrees of freedom left, or one whose "
               "interval would be Student's t at fewer than 2 degrees of freedom (untestable here); "
               f"within error bars = the published value inside the {COVERAGE:.0%} interval, "
               "the Student-t quantile at the fit's degrees of freedom (points − parameters) times "
               "its standard error (the normal 1.96 for a number without a fit of its own); "
               f"qualitatively = within {REL_TOL:.0%} of it; else not reproduced. "
               "The paper publishes no error bars. θ(Fr) and κ(Fr) measured at fewer than 5 speeds at speed, "
               "or from yield pulls only, are not studied: no number. Regime fits are made to the pulls at speed; "
               "the yield pull (V = 0.01) is shown beside them, not in them (paper Figs. 5, 10)."
               + (f" Eq. 12 and Fig. 19 use pulls at h ≥ {r.options.h_min:g} d only (h_min)."
                  if r.options.h_min else " Eq. 12 and Fig. 19 use pulls at every depth (h_min = 0)."))]
    rows = comparisons(r, df)
    n = counts(rows)
    caveats, refs = shared_caveats(rows)
    # Lead with the paper's claims, one line each; the intro's method and rules come after.
    b = b[:1] + [("h2", "The paper's claims at a glance"), ("ul", headline(rows)),
                 ("p", "✓ within error bars, ≈ qualitatively, ✗ not reproduced, ? inconclusive "
                       "(the rules below).")] + b[1:]
    b += [("h2", "Fitted numbers beside the paper's"),
          ("p", f"{len(rows)} numbers: " + ", ".join(f"{SYMBOLS[v]} {n[v]} {v}" for v in VERDICTS) + "."),
          ("table", ["quantity", "fitted", "paper", "verdict", "notes"],
           [[x.quantity, x.shown(), x.published, f"{SYMBOLS[x.verdict]} {x.verdict}", refs(x.notes)]
            for x in rows])]
    if caveats:
        b += [("p", "Notes shared by several rows, stated once:"), ("ul", caveats)]
    b += [("h2", "In words"),
          ("ul", [x.base + (f" [{refs(x.notes)}]" if x.notes else "") if x.base else x.sentence
                  for x in rows] or ["No fit could be made."])]
    b += _goodness_blocks(r)
    if len(r.sums) or len(r.phi) or len(r.alpha):
        b += [("h2", "Exponents of the yield force")]
        b += [("table", ["μ", "K_n", "φ_μ", "f(μ)", "α_μ", "g(μ)"], _exponent_rows(r))]
    if r.alpha_drag is not None and len(r.alpha_drag):
        b += [("h2", "α_μ from the drag at speed (Sec. III H, Fig. 18)"),
              ("p", "The paper's α_μ: the depth exponent of the drag at V = "
                    + ", ".join(f"{v:g}" for v in r.options.alpha_speeds)
                    + " (a pulled speed within 25 % stands for each), averaged. Its error is the "
                    "mean of the per-speed errors (the speeds share their beds: fully correlated); "
                    "the spread is the standard deviation over the speeds."),
              ("table", ["μ", "K_n", "α_μ (drag, averaged)", "spread", "speeds", "α_μ (yield force)"],
               _alpha_drag_rows(r))]
    if r.laws:
        b += [("h2", "Scaling law (Eq. 12): λ coefficients"),
              ("p", "F*_drag / (h*^α_μ (D*+1)^φ_μ) = λ^I (Fr < Fr_1); λ_1^II Fr + λ_2^II "
                    "(Fr_1 < Fr < Fr_2); λ_1^III Fr² + λ_2^III (Fr > Fr_2). For μ = 0 regime I is "
                    "λ^I + b0 Fr^c0 (Eq. 10). The paper prints no values for these.")]
        names = list(dict.fromkeys(n for law in r.laws for n in law.lambdas()))
        b += [("table", ["μ", "α_μ", "φ_μ"] + [n.replace("lambda", "λ") for n in names] + ["Fr_1", "Fr_2"],
               [[f"{law.mu:g}", str(law.alpha), str(law.phi)]
                + [str(law.lambdas().get(n, "")) for n in names]
                + [str(law.regimes["Fr1"]), str(law.regimes["Fr2"])] for law in r.laws])]
    b += [("h2", "Figures")]
    for caption, path, note in figs:
        b += [("img", caption, path.name)] if path else [("p", f"{caption}: not drawn — {note}.")]
    if r.notes:
        b += [("h2", "Fits not made"), ("ul", r.notes)]
    return b


def _goodness_blocks(r):
    """The goodness of every fit (goodness.py): χ²/dof and the runs test of its residuals."""
    fits = [(name, f.meta.get("goodness")) for name, f in named_fits(r).items()]
    for tab, what in ((r.phi, "phi"), (r.alpha, "alpha")):
        for _, t in (tab.iterrows() if tab is not None else []):
            fits.append((f"{what}_mu{t.mu:g}_kn{t.kn:.3g}", table_goodness(t)))
    rows = [[name, "rejected" if g and g.get("rejected") else "not rejected" if g else "-",
             describe(g) if g else "not recorded"] for name, g in fits]
    return [("h2", "Goodness of the fits"),
            ("p", "Each fit's χ²/dof against the errors it was weighted by, and a runs test of its "
                  "residuals' signs in the order of x (within each series): too few runs means the "
                  "residuals trend, the curve has the wrong shape (a line through a U). The data "
                  "reject a model whose residuals trend at the 1 % level, or whose χ² is far out "
                  "(P(χ² ≥ observed) < 10⁻⁶, more than errors understated by a third explain); its numbers "
                  "above then read \"model rejected\" and are inconclusive. A χ²/dof above 1 short of that, "
                  "without a trend, is scatter beyond the errors, which the fits' errors already include "
                  "(scaled by it, or bootstrapped from the residuals)."),
            ("table", ["fit", "model", "goodness"], rows)] if rows else []


def _span(values, unit="", fmt="{:.3g}"):
    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    if not len(v):
        return "?"
    lo, hi = fmt.format(v.min()), fmt.format(v.max())
    return (lo if lo == hi else f"{lo}–{hi}") + unit


def _scale_text(df, kn):
    """At what scale these numbers were obtained, beside the paper's."""
    parts = []
    for system, g in df.groupby("system", sort=True):
        box = (f"{_span(g.lx, fmt='{:g}')} × {_span(g.ly, fmt='{:g}')} d, {_span(g.grains, fmt='{:.0f}')} grains"
               if {"lx", "ly", "grains"} <= set(g.columns) else "box not recorded")
        pulled = _span(g.distance, " d") if "distance" in g.columns else "?"
        text = (f"system {system}: {box}, D = {_span(g.D, ' d', '{:g}')}, h = {_span(g.h, ' d')}, "
                f"pulls of {pulled}")
        if system in paper.SYSTEMS:
            lx, ly, n = paper.SYSTEMS[system]
            text += f" (paper: {lx:g} × {ly:g} d, {n:,} grains, pulls of one box length)"
        parts.append(text)
    return (f"Scale of these numbers: {'; '.join(parts)}; K_n = {kn:.3g} (paper {paper.KN:.0e}). "
            "A verdict holds at this scale: a number not reproduced here may still be reproduced "
            "at the paper's.")


def _exponent_rows(r):
    m = r.phi.merge(r.alpha, on=["mu", "kn", "gamman"], how="outer").sort_values(["kn", "mu"])
    fmt = lambda row, c: format_pm(row[c], row[c + "_err"]) if c in row and np.isfinite(row[c]) else "-"
    return [[f"{row.mu:g}", f"{row.kn:.3g}", fmt(row, "phi"), fmt(row, "f"), fmt(row, "alpha"), fmt(row, "g")]
            for _, row in m.iterrows()]


def _alpha_drag_rows(r):
    out = []
    for _, t in r.alpha_drag.sort_values(["kn", "mu"]).iterrows():
        a = r.alpha[np.isclose(r.alpha.mu, t.mu) & np.isclose(r.alpha.kn, t.kn) & np.isclose(r.alpha.gamman, t.gamman)]
        out.append([f"{t.mu:g}", f"{t.kn:.3g}", format_pm(t.alpha, t.alpha_err),
                    f"{t.spread:.2g}" if np.isfinite(t.spread) else "-", t.speeds,
                    format_pm(a.alpha.iloc[0], a.alpha_err.iloc[0]) if len(a) else "-"])
    return out


FIG1_CAPTION = ("Fig. 1: (a) a system I and (c) a system II bed with the intruder (red; frozen base "
                "grey), the half in front of the intruder's plane cut away; (b) the slice of the "
                "system I bed through the intruder's plane, grains as circles of their cut radius.")


def figure_entries(outdir):
    """[(caption, png path or None, why not drawn)] of every figure in outdir, paper order."""
    out = []
    fig1 = Path(outdir) / "fig01_beds.png"  # drawn by workflow/rules/fig1.smk, if it ran
    if fig1.is_file():
        note = fig1.with_suffix(".txt")
        out.append((FIG1_CAPTION + (" " + note.read_text().strip() if note.is_file() else ""), fig1, ""))
    for fig in FIGURES:
        png = Path(outdir) / f"{fig.name}.png"
        why = not_drawn_reason(png) if png.is_file() else "no figure file"
        out.append((fig.caption, None if why else png, why or ""))
    return out


def write_report(df, r, outdir, n_boot, seed):
    """report.md and report.html in outdir, from the table, the fits (Results, as read from
    fits.json) and the figure files already in outdir. Returns the path of report.md."""
    outdir = Path(outdir)
    blocks = _blocks(df, r, figure_entries(outdir), n_boot, seed)
    write_text_atomic(outdir / "report.md", markdown(blocks))
    write_text_atomic(outdir / "report.html", to_html(blocks))
    return outdir / "report.md"


def build_report(df, outdir, n_boot=N_BOOT, seed=0, restitution=None, trace=None, coordination=None, flow=None,
                 options=None):
    """Fit, draw and write fits.json, every figure, report.md and report.html into outdir (what
    the workflow's fits, figure and report rules do one step at a time).

    restitution: optional (v_n, e, theory_v, theory_e[, label of e]) for Fig. 2;
    trace: optional (t, force[, transient]) for Fig. 4.
    coordination: optional long table of P(Z) per run for Fig. 7 (see figures.fig07_coordination);
    flow: optional [(D, V, snapshot DataFrame)] for the panels of Fig. 9.
    Returns the path of report.md.
    """
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    save_results(outdir / "fits.json", run_fits(df, n_boot=n_boot, seed=seed, options=options))
    r = load_results(outdir / "fits.json")
    inputs = Inputs(table=df, restitution=restitution, trace=trace, coordination=coordination, flow=flow)
    for name in NAMES:
        draw(name, inputs, r, outdir)
    return write_report(df, r, outdir, n_boot, seed)
