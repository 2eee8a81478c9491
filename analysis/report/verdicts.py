"""The report's verdict on a fitted number against the paper's, and the degrees of freedom its
95 % interval takes (analysis/README.md, "Report verdicts"):
  inconclusive       no error bar, an error above INCONCLUSIVE (30 %) of the value,
                     a fit that breaks its model (drag falling with Fr in regime
                     II or III), whose model the data reject (its residuals trend:
                     goodness.py), that ended on a bound of its parameters,
                     or a fit with no degrees of freedom left: such a number could
                     agree with anything; also a number whose 95 % interval is
                     Student's t at fewer than MIN_DOF (2) degrees of freedom (±12.7
                     standard errors at 1): the comparison can hardly fail, so it is
                     untestable at that study, neither reproduced nor not
  not studied        θ(Fr) and κ(Fr) (Eqs. 7, 8) measured at fewer than
                     OBSERVABLE_MIN_SPEEDS (5) speeds at speed, or from yield pulls
                     only: the report lists no number for them (observables_studied)
  within error bars  |fit - p| <= t standard errors, t the two-sided 95 % Student-t
                     quantile at the number's degrees of freedom (fit_dof, table_dof,
                     sum_dof; the normal 1.96 for a number that has no fit of its own,
                     or whose error is its points' errors unscaled: errors_from_points)
  qualitatively      otherwise, but |fit - p| <= 25 % of |p|
  not reproduced     otherwise (or no fit)
"""
import math

import numpy as np
from scipy import stats

from ..core.table import is_yield
from ..fits.goodness import TREND_ALPHA, inherited

COVERAGE, REL_TOL = 0.95, 0.25   # the within-error interval's coverage; "qualitatively"
INCONCLUSIVE = 0.30        # relative error above which a number cannot confirm anything
MIN_DOF = 2                # Student's t at fewer dof: the interval spans more than ±4.3 errors
OBSERVABLE_MIN_SPEEDS = 5  # θ(Fr), κ(Fr): distinct speeds at speed a study needs to test them
VERDICTS = ("reproduced within error bars", "reproduced qualitatively", "not reproduced", "inconclusive")


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


def verdict(p, published, violations=(), at_bounds=(), dof=None, rejected="", from_points=False, ill_posed=""):
    """Verdict and its reason for Param p against a published number; violations: what
    the fit breaks of its model (regimes.violations), at_bounds: parameters that ended on a
    bound, rejected: "model rejected (...)" when the data reject the model (goodness.py),
    ill_posed: why its errors are not estimable (least_squares.ill_posed), any of which makes it
    inconclusive; dof: the fit's degrees of freedom, those of its error unless from_points
    (errors_from_points: the normal quantile)."""
    if p is None or not math.isfinite(p.value):
        return "not reproduced", "no fit"
    if ill_posed:
        return "inconclusive", ill_posed
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
    if not from_points and dof is not None and math.isfinite(dof) and dof < MIN_DOF:
        return "inconclusive", (f"untestable here: at {dof:.2g} degree{'' if f'{dof:.2g}' == '1' else 's'} of freedom "
                                f"the 95 % interval spans ±{within_quantile(dof):.1f} standard errors (Student-t)")
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


def table_goodness(t):
    """The goodness of a fitted table row (fits.GOODNESS_COLUMNS), as the report reads a fit's;
    {} for tables written before the columns."""
    num = lambda c: float(t[c]) if c in t and math.isfinite(float(t[c])) else None
    if num("rejected") is None:
        return {}
    p = num("trend_p")
    return {"chi2_dof": num("chi2_dof"), "dof": None if num("n") is None else num("n") - 2, "trend_p": p,
            "trend": p is not None and p < TREND_ALPHA, "rejected": bool(num("rejected"))}


def _rows_at(tab, t):
    """The rows of a fitted table (phi, alpha, alpha_speeds; None allowed) at t's mu, K_n, gamma_n."""
    if tab is None or not len(tab):
        return []
    return [h for _, h in tab[np.isclose(tab.mu, t.mu) & np.isclose(tab.kn, t.kn)
                              & np.isclose(tab.gamman, t.gamman)].iterrows()]


def sum_goodness(t, phi, alphas):
    """The sum rule's goodness: rejected when the data reject the φ_μ fit or an α_μ fit it adds
    (goodness.inherited; the averaged α_μ: any of its speeds' fits), at the sum's μ, K_n, γ_n."""
    parts = [(f"{name} at V = {h.V:.3g}" if "V" in h else name, table_goodness(h))
             for name, tab in (("φ_μ fit", phi), ("α_μ fit", alphas)) for h in _rows_at(tab, t)]
    return inherited(parts)


def component_dof(t, tab):
    """The dof of a fitted table row's exponent at t's mu, K_n, gamma_n: infinite when its error is
    its points' errors unscaled (chi^2/dof <= 1: errors_from_points), else its points minus 2;
    infinite without a row (the alpha averaged over speeds takes the normal quantile)."""
    hit = _rows_at(tab, t)
    if not hit:
        return math.inf
    h = hit[0]
    if errors_from_points(goodness=table_goodness(h)):
        return math.inf
    n = table_dof(h, "n")
    return math.inf if n is None else n


def sum_dof(t, phi, alpha):
    """The sum rule's dof: Welch-Satterthwaite's for phi_err^2 + alpha_err^2, each part's dof by
    component_dof (alpha: the fitted table, None for the average over speeds); None (the normal
    quantile) when both rest on their points' errors. Was the fewer points' minus 2, which took
    Student's t at 2-3 dof for a sum whose parts' errors were not from their residuals."""
    a = float(t["phi_err"]) ** 2, float(t["alpha_err"]) ** 2
    nu = component_dof(t, phi), component_dof(t, alpha)
    if not all(math.isfinite(x) for x in a):
        return table_dof(t, "n_min")
    if any(x < 1 for x in nu):
        return min(nu)
    den = sum(v * v / n for v, n in zip(a, nu) if math.isfinite(n))
    return None if den == 0 else sum(a) ** 2 / den


def table_dof(t, column):
    """A fitted table row's dof: its fit's points (`column`) minus the power law's 2 parameters;
    None for tables written before the column."""
    n = t.get(column) if hasattr(t, "get") else None
    return None if n is None or not math.isfinite(float(n)) else float(n) - 2


def observable_speeds(rows, column):
    """How many speeds at speed (yield pulls left out) a series of `rows` measured `column` at
    (theta or kappa): the most distinct Fr (to 6 digits) of one D. Several D pulled at one speed
    give as many Fr, but one speed each."""
    if rows is None or column not in rows.columns:
        return 0
    moving = rows[~is_yield(rows) & rows[column].notna()]
    return distinct_speeds(moving)


def distinct_speeds(rows):
    """The most distinct Fr (to 6 digits) of one D among rows (0 for none)."""
    if not len(rows):
        return 0
    return int(rows.assign(_fr=rows.Fr.astype(float).round(6)).groupby("D")._fr.nunique().max())


def observables_studied(rows, column, fit=None):
    """Whether a study tests θ(Fr) or κ(Fr) (column theta or kappa): its rows (system I at
    μ = 0.5, the reference contact law) hold at least OBSERVABLE_MIN_SPEEDS distinct speeds at
    speed. The paper's claims are curves over Fr 0.1-10; three yield pulls at one speed (a
    yield and depth sweep's) fit a "slope" of κ that is no measurement of Eq. 8's, and fewer
    than five speeds leave Eq. 7's three parameters under two degrees of freedom. Without the
    rows (a report made from the fits alone), the fit's points count."""
    if rows is None:
        return fit is None or fit.n_points >= OBSERVABLE_MIN_SPEEDS
    return observable_speeds(rows, column) >= OBSERVABLE_MIN_SPEEDS
