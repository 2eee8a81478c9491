"""The report: every figure and each fitted number beside the paper's value.

Verdict for a number with a published value p (the paper gives no error
bars, so only ours count):
  inconclusive       no error bar, an error above INCONCLUSIVE (30 %) of the value,
                     a fit that breaks its model (drag falling with Fr in regime
                     II or III), whose model the data reject (its residuals trend:
                     goodness.py; the report then says "model rejected (...)" in
                     place of the number), that ended on a bound of its parameters,
                     or a fit with no degrees of freedom left: such a number could
                     agree with anything
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
study's replicated points, a config's prior, or none: analysis.report_notes) is stated once
for every fit when all points share it, else beside each number.
"""
import math
from collections import Counter
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path

import numpy as np
from scipy import stats

from . import paper
from .claims import CLAIMS, claim_of
from .figure_list import FIGURES, NAMES, Inputs, draw
from .figures import not_drawn_reason
from .fits import write_text_atomic
from .fitset import Results, load_results, named_fits, run_fits, save_results
from .goodness import TREND_ALPHA, describe, inherited, rejection_text
from .report_notes import (
    PLATEAU_COLUMN,
    SEED_COLUMN,
    basis_notes,
    bed_scatter_sentence,
    shared_caveats,
    uniform_bed_scatter,
)
from .report_render import SYMBOLS, markdown, to_html
from .result import Param, format_pm
from .table import is_yield, reference_params, select, yield_rows

__all__ = ["PLATEAU_COLUMN", "SEED_COLUMN", "Results", "build_report", "comparisons", "run_fits", "shared_caveats",
           "verdict", "write_report"]

COVERAGE, REL_TOL = 0.95, 0.25   # the within-error interval's coverage; "qualitatively"
INCONCLUSIVE = 0.30        # relative error above which a number cannot confirm anything
VERDICTS = ("reproduced within error bars", "reproduced qualitatively", "not reproduced", "inconclusive")


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


def within_quantile(dof=None):
    """How many standard errors the within-error interval spans: the two-sided COVERAGE
    quantile of Student's t at `dof` degrees of freedom, or of the normal law without one."""
    if dof is None or not math.isfinite(dof):
        return float(stats.norm.ppf(0.5 + COVERAGE / 2))
    return float(stats.t.ppf(0.5 + COVERAGE / 2, dof))


def fit_dof(fit):
    """Points minus free parameters of a fit (None without a fit): its meta n_free when it says
    (a continuous regime fit lists b1 and b2 but derives them from continuity), else every
    parameter it lists."""
    return None if fit is None else fit.n_points - fit.meta.get("n_free", len(fit.params))


def errors_from_points(fit=None, goodness=None):
    """Whether a number's error is its points' errors carried through its fit unscaled (the fit's
    meta errors_from, else, for a fitted table's row, its weighted fit's chi^2/dof <= 1): it then
    rests on those errors' many degrees of freedom, not on the fit's residuals, and its interval
    takes the normal quantile. With the fit's Student-t at a few dof, 95 % intervals held the
    truth 99.8 % of the time (alpha from the yield force, tests/python/test_calibration.py)."""
    src = (fit.meta if fit is not None else {}).get("errors_from")
    if src is not None:
        return src == "points"
    c = (goodness or {}).get("chi2_dof")
    return c is not None and math.isfinite(c) and c <= 1.0


def verdict(p, published, violations=(), at_bounds=(), dof=None, rejected="", from_points=False):
    """Verdict and its reason for Param p against a published number; violations: what
    the fit breaks of its model (regimes.violations), at_bounds: parameters that ended on a
    bound, rejected: "model rejected (...)" when the data reject the model (goodness.py), any
    of which makes it inconclusive; dof: the fit's degrees of freedom, those of its error
    unless from_points (errors_from_points: the normal quantile)."""
    if p is None or not math.isfinite(p.value):
        return "not reproduced", "no fit"
    if violations:
        return "inconclusive", "the fit breaks its model: " + "; ".join(violations)
    if rejected:
        return "inconclusive", "the data reject the model: " + rejected.removeprefix("model rejected (").rstrip(")")
    if at_bounds:
        return "inconclusive", "the fit ended on a bound: " + "; ".join(at_bounds)
    if not (math.isfinite(p.err) and p.err > 0):
        return "inconclusive", "no error bar"
    if dof is not None and dof < 1:
        return "inconclusive", f"the fit has {dof} degrees of freedom: its error means nothing"
    if p.err > INCONCLUSIVE * abs(p.value):
        return "inconclusive", f"error {p.err / abs(p.value):.0%} of the value, above {INCONCLUSIVE:.0%}"
    d = abs(p.value - published)
    q = within_quantile(None if from_points else dof)
    test = (f"Student-t at {dof:g} dof" if dof is not None and math.isfinite(dof) and not from_points
            else "normal")
    if d <= q * p.err:
        return "reproduced within error bars", f"{d / p.err:.1f} standard errors away, within {q:.2f} ({test})"
    if d <= REL_TOL * abs(published):
        return ("reproduced qualitatively",
                f"within {REL_TOL:.0%} but {d / p.err:.1f} standard errors, beyond {q:.2f} ({test})")
    return "not reproduced", f"off by {d / abs(published):.0%}" if published else "off"


def _row(quantity, p, published, shown=None, fit=None, rows=None, extra="", dof=None, goodness=None,
         bed_scatter=True, observable=False):
    meta = fit.meta if fit is not None else {}
    g = goodness if goodness is not None else meta.get("goodness")
    rejected = rejection_text(g) if g and g.get("rejected") else ""
    v, why = verdict(p, published, meta.get("violations", ()), meta.get("at_bounds", ()),
                     fit_dof(fit) if dof is None else dof, rejected, errors_from_points(fit, g))
    shown = shown or f"{published:g}"
    notes = [rejected] if rejected else []
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
            basis = _moving(basis[basis.h >= h_min] if h_min else basis)
        cut = f", h ≥ {h_min:g}" if h_min else ""
        rows.append(entry(f"Fr_1 (Eq. 12 collapse, μ = {law.mu:g}{cut})", law.regimes["Fr1"], 1.0, "≈ 1",
                         law.regimes, basis))
        rows.append(entry(f"Fr_2 (Eq. 12 collapse, μ = {law.mu:g}{cut})", law.regimes["Fr2"], 5.0, "≈ 5",
                         law.regimes, basis))
    obs = sub(mu=0.5, system="I")
    if r.theta is not None:
        for k, name in (("U1", "Υ1"), ("U2", "Υ2"), ("U3", "Υ3")):
            rows.append(entry(f"θ(Fr) {name} (Eq. 7)", r.theta[k], paper.THETA[k], fit=r.theta, rows=obs,
                             observable=True))
    if r.kappa is not None:
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
                             f"≈ {pub:g}", rows=basis, dof=_table_dof(t, "n"), goodness=_table_goodness(t)))
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
            g = _sum_goodness(t, r.phi, alphas)
            rows.append(entry(f"α_μ + φ_μ ({how}; μ = {t.mu:g}, K_n = {t.kn:.3g})",
                             Param(t["sum"], t["sum_err"]), paper.SUM_RULE, "≈ 3",
                             dof=_sum_dof(t, r.phi, fitted), goodness=g))
    for D, fit in sorted(r.saturation.items()):
        rows.append(_saturation_row(D, fit))
    return rows


def _table_goodness(t):
    """The goodness of a fitted table row (fits.GOODNESS_COLUMNS), as the report reads a fit's;
    {} for tables written before the columns."""
    num = lambda c: float(t[c]) if c in t and math.isfinite(float(t[c])) else None
    if num("rejected") is None:
        return {}
    p = num("trend_p")
    return {"chi2_dof": num("chi2_dof"), "dof": None if num("n") is None else num("n") - 2, "trend_p": p,
            "trend": p is not None and p < TREND_ALPHA, "rejected": bool(num("rejected"))}


def _sum_goodness(t, phi, alphas):
    """The sum rule's goodness: rejected when the data reject the φ_μ fit or an α_μ fit it adds
    (goodness.inherited; the averaged α_μ: any of its speeds' fits), at the sum's μ, K_n, γ_n."""
    parts = []
    for name, tab in (("φ_μ fit", phi), ("α_μ fit", alphas)):
        hit = [] if tab is None or not len(tab) else tab[np.isclose(tab.mu, t.mu) & np.isclose(tab.kn, t.kn)
                                                        & np.isclose(tab.gamman, t.gamman)]
        for _, h in (hit.iterrows() if len(hit) else []):
            parts.append((f"{name} at V = {h.V:.3g}" if "V" in h else name, _table_goodness(h)))
    return inherited(parts)


def _component_dof(t, tab, col):
    """The dof of a fitted table row's exponent at t's mu, K_n, gamma_n: infinite when its error is
    its points' errors unscaled (chi^2/dof <= 1: errors_from_points), else its points minus 2;
    infinite without a row (the alpha averaged over speeds takes the normal quantile)."""
    hit = [] if tab is None or not len(tab) else tab[np.isclose(tab.mu, t.mu) & np.isclose(tab.kn, t.kn)
                                                    & np.isclose(tab.gamman, t.gamman)]
    if not len(hit):
        return math.inf
    h = hit.iloc[0]
    if errors_from_points(goodness=_table_goodness(h)):
        return math.inf
    n = _table_dof(h, "n")
    return math.inf if n is None else n


def _sum_dof(t, phi, alpha):
    """The sum rule's dof: Welch-Satterthwaite's for phi_err^2 + alpha_err^2, each part's dof by
    _component_dof (alpha: the fitted table, None for the average over speeds); None (the normal
    quantile) when both rest on their points' errors. Was the fewer points' minus 2, which took
    Student's t at 2-3 dof for a sum whose parts' errors were not from their residuals."""
    a = float(t["phi_err"]) ** 2, float(t["alpha_err"]) ** 2
    nu = _component_dof(t, phi, "phi"), _component_dof(t, alpha, "alpha")
    if not all(math.isfinite(x) for x in a):
        return _table_dof(t, "n_min")
    if any(x < 1 for x in nu):
        return min(nu)
    den = sum(v * v / n for v, n in zip(a, nu) if math.isfinite(n))
    return None if den == 0 else sum(a) ** 2 / den


def _table_dof(t, column):
    """A fitted table row's dof: its fit's points (`column`) minus the power law's 2 parameters;
    None for tables written before the column."""
    n = t.get(column) if hasattr(t, "get") else None
    return None if n is None or not math.isfinite(float(n)) else float(n) - 2


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

def _blocks(df, r, figs, n_boot, seed):
    kn, gn = reference_params(df)
    b = [("h1", "granudrag: drag scaling in dense granular media"),
         ("p", f"{len(df)} pulls; systems {', '.join(sorted(df.system.unique()))}; "
               f"μ = {', '.join(f'{m:g}' for m in sorted(df.mu.unique()))}; reference contact law "
               f"K_n = {kn:.3g}, γ_n = {gn:.3g}. Regime fits: crossovers fitted by profile least "
               f"squares, errors from {n_boot} wild-bootstrap refits (seed {seed}); other fits: "
               "least-squares covariance. Errors are one standard error. " + bed_scatter_sentence(df)),
         ("p", _scale_text(df, kn)),
         ("p", f"Verdicts: inconclusive = no error bar, an error above {INCONCLUSIVE:.0%} of the "
               "value, a fit that breaks its model (drag falling with Fr in regime II or III) or "
               "ended on a bound of its parameters, or one with no degrees of freedom left; "
               f"within error bars = the published value inside the {COVERAGE:.0%} interval, "
               "the Student-t quantile at the fit's degrees of freedom (points − parameters) times "
               "its standard error (the normal 1.96 for a number without a fit of its own); "
               f"qualitatively = within {REL_TOL:.0%} of it; else not reproduced. "
               "The paper publishes no error bars. Regime fits are made to the pulls at speed; "
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
            fits.append((f"{what}_mu{t.mu:g}_kn{t.kn:.3g}", _table_goodness(t)))
    rows = [[name, "rejected" if g and g.get("rejected") else "not rejected" if g else "-",
             describe(g) if g else "not recorded"] for name, g in fits]
    return [("h2", "Goodness of the fits"),
            ("p", "Each fit's χ²/dof against the errors it was weighted by, and a runs test of its "
                  "residuals' signs in the order of x (within each series): too few runs means the "
                  "residuals trend, the curve has the wrong shape (a line through a U). The data "
                  "reject a model whose residuals trend at the 1 % level; its numbers above then read "
                  "\"model rejected\" and are inconclusive. A χ²/dof above 1 without a trend is scatter "
                  "beyond the errors, which the fits' errors already include (scaled by it, or "
                  "bootstrapped from the residuals)."),
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


def build_report(df, outdir, n_boot=200, seed=0, restitution=None, trace=None, coordination=None, flow=None,
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
