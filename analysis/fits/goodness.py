"""How well a fitted model describes its data: χ²/dof, and whether the residuals trend.

Every least-squares fit of the analysis (fits._covariance_fit, the regime fits, the exponent
tables) records `goodness(...)` in its meta, and fits.json carries it beside the parameters:

    chi2, dof, chi2_dof   Σ ((y - model)/σ)², points − parameters, their ratio (σ the per-point
                          errors the fit was weighted by; null when it had none)
    chi2_p                P(χ²_dof ≥ chi2): small when the scatter about the model exceeds the
                          errors (the model misses, or the errors are too small)
    runs, runs_expected   the runs test: the residuals' signs in the order of x, counted in runs
                          (++−−−++ is 3 runs), within each series when the fit spans several
    trend_p               P(runs ≤ observed) for signs in random order, exact (the distribution
                          of the number of runs, Wald & Wolfowitz 1940); null when even the
                          fewest runs the signs allow would not reach TREND_ALPHA
    trend                 trend_p < TREND_ALPHA (1 %): the residuals trend with x
    rejected              the data reject the model: its residuals trend, or its χ² is far out
                          (chi2_p < CHI2_ALPHA, 10⁻⁶)

Why the runs test: it asks the one thing a curve of the wrong shape cannot hide (a line through
a U leaves + at both ends and − in the middle: 3 runs where ~n/2 are expected), it needs no
second model and works alike for every model here, weighted or not. It uses the signs only,
so it holds whether or not the errors are right, where χ² does not: a line through a U whose
error bars are wide has χ²/dof below 1 and still trending residuals. Two series measured at
the same x (κ at D = 2 and 3) are counted apart, so that their offset does not pass for
alternating signs. It has little power on a short series: with fewer than 10 points no order of
the signs reaches 1 %, and the fit says "too few points for a trend test" rather than passing.

Why χ² only when far out: a χ²/dof above 1 without a trend says the points scatter more than
their errors, which a wrong model and too small errors both explain; the fits' errors absorb a
moderate excess (the least-squares covariance is scaled by χ²/dof when above 1, the regime fits'
errors are bootstrapped from the residuals). A wrong shape they do not absorb: it biases the
parameters, however large their errors. So a χ² rejects the model only where errors understated
by a plausible factor cannot explain it: P(χ²_dof ≥ chi2) < CHI2_ALPHA = 10⁻⁶, which needs
χ²/dof above 3.9 at 14 dof (2.3 at 45, 6.4 at 6) and, at 14 dof, errors understated by more than
1.37× for the data still to reject the model at 1 %. θ's Eq. 7 fit in the 40 d box (χ²/dof 5.2 at
14 dof, p = 5×10⁻¹⁰, its runs test p = 0.02) is such a fit: the curve misses the points by
2.3 errors (rms), which no error estimate here is wrong by. Below that level χ²/dof is
reported beside the runs test, for the reader to judge.

The parameters of a rejected model are not measurements of the model's, and the report says
"model rejected (...)" instead of quoting them (analysis.report.report). The false-alarm rate on
straight lines with noise, and the U that must be caught, are measured in
tests/python/test_goodness.py.
"""
from math import comb

import numpy as np
import pandas as pd
from scipy import stats

TREND_ALPHA = 0.01   # runs test: one-sided level for "the residuals trend", which rejects the model
CHI2_ALPHA = 1e-6    # P(χ² ≥ observed) below which the scatter about the model rejects it (docstring)


def runs_distribution(n1, n2):
    """P(R = r) for r = 0 .. n1 + n2: the number of runs in a random order of n1 pluses and
    n2 minuses (Wald & Wolfowitz 1940)."""
    n = n1 + n2
    p = np.zeros(n + 1)
    if n1 == 0 or n2 == 0:
        p[min(1, n)] = 1.0
        return p
    total = comb(n, n1)
    for r in range(2, n + 1):
        k, odd = divmod(r, 2)
        if odd:
            ways = comb(n1 - 1, k - 1) * comb(n2 - 1, k) + comb(n1 - 1, k) * comb(n2 - 1, k - 1)
        else:
            ways = 2 * comb(n1 - 1, k - 1) * comb(n2 - 1, k - 1)
        p[r] = ways / total
    return p


def runs_test(x, residuals, groups=None):
    """(runs, expected runs, p, smallest p possible) of the residuals' signs ordered by x within
    each series (groups: a label per point, None: one series; ties in x kept in input order; zero
    residuals left out). Several series: their runs add up, and p = P(total <= observed) under
    the convolution of their distributions, so the offset between two series measured at the
    same x does not pass for alternating signs. p is 1 when there is nothing to test."""
    x, r = np.asarray(x, float), np.asarray(residuals, float)
    labels = np.zeros(len(x)) if groups is None else pd.factorize(np.asarray(groups))[0]
    pmf, runs, expected = np.array([1.0]), 0, 0.0
    for g in np.unique(labels):
        idx = np.flatnonzero(labels == g)
        s = np.sign(r[idx][np.argsort(x[idx], kind="stable")])
        s = s[s != 0]
        n1, n2 = int(np.sum(s > 0)), int(np.sum(s < 0))
        if len(s) == 0:
            continue
        runs += 1 + int(np.sum(s[1:] != s[:-1]))
        expected += 1.0 + 2.0 * n1 * n2 / (n1 + n2)
        pmf = np.convolve(pmf, runs_distribution(n1, n2))
    support = np.flatnonzero(pmf > 0)
    smallest = float(pmf[support[0]]) if len(support) else 1.0
    return runs, expected, float(min(1.0, np.sum(pmf[:runs + 1]))), smallest


def goodness(x, y, model, n_params, sigma=None, groups=None):
    """The goodness of a fit (module docstring) as a dict for a Fit's meta: x, y the fitted
    points, model the fitted curve at x, n_params the fitted parameters, sigma the per-point
    errors it was weighted by (None: unweighted) or their covariance (n, n: χ² = rᵀ C⁻¹ r),
    groups the series each point belongs to (runs are counted within a series; None: one
    series)."""
    x, y, model = (np.asarray(v, float) for v in (x, y, model))
    resid = y - model
    dof = len(x) - int(n_params)
    out = {"n_points": int(len(x)), "dof": int(dof), "chi2": None, "chi2_dof": None, "chi2_p": None}
    if sigma is not None and dof > 0:
        s = np.asarray(sigma, float)
        chi2 = float(resid @ np.linalg.solve(s, resid) if s.ndim == 2 else np.sum((resid / s) ** 2))
        out.update(chi2=chi2, chi2_dof=chi2 / dof, chi2_p=float(stats.chi2.sf(chi2, dof)))
    runs, expected, p, smallest = runs_test(x, resid, groups)
    # Testable when the fewest runs these signs allow would be significant.
    testable = dof > 0 and smallest < TREND_ALPHA
    out.update(runs=int(runs), runs_expected=float(expected), trend_p=float(p) if testable else None,
               trend=bool(testable and p < TREND_ALPHA))
    out["rejected"] = is_rejected(out)
    return out


def is_rejected(g):
    """Whether a goodness dict (as goodness returns, or read back from fits.json or a fitted
    table's row) says the data reject the model: its residuals trend, or its χ² is far out
    (chi2_far_out; module docstring)."""
    return bool(g and (g.get("trend") or chi2_far_out(g)))


def chi2_p(g):
    """P(χ²_dof ≥ chi2) of a goodness dict: its chi2_p, else from chi2_dof and dof (a fitted
    table's row records those two); None when it has no χ²."""
    if g.get("chi2_p") is not None:
        return float(g["chi2_p"])
    c, dof = g.get("chi2_dof"), g.get("dof")
    if c is None or dof is None or not np.isfinite(c) or not dof or dof < 1:
        return None
    return float(stats.chi2.sf(c * dof, dof))


def chi2_far_out(g):
    """Whether the points scatter about the model far beyond their errors: chi2_p < CHI2_ALPHA."""
    p = chi2_p(g) if g else None
    return p is not None and p < CHI2_ALPHA


def describe(g):
    """'χ²/dof = 2.31 (24 dof), residuals trend (3 runs of 12.5 expected, p = 0.0004)', or
    what can be said: the words the report and the figure captions use."""
    if not g:
        return "goodness not recorded"
    parts = []
    if g.get("chi2_dof") is not None:
        dof = f" ({g['dof']:g} dof)" if g.get("dof") is not None else ""
        far = f", far out: χ² p = {_p(chi2_p(g))}" if chi2_far_out(g) else ""
        parts.append(f"χ²/dof = {g['chi2_dof']:.2f}{dof}{far}")
    else:
        parts.append("no degrees of freedom" if g.get("dof") == 0 else "no χ² (unweighted fit)")
    if g.get("trend_p") is None:
        parts.append("too few points for a trend test")
    else:
        word = "residuals trend" if g.get("trend") else "residuals do not trend"
        runs = f"{g['runs']} runs of {g['runs_expected']:.1f} expected, " if "runs" in g else ""
        parts.append(f"{word} ({runs}runs test p = {_p(g['trend_p'])})")
    return ", ".join(parts)


def rejection_text(g):
    """'model rejected (χ²/dof = 2.31, residuals trend, runs test p = 0.0004)': the report's
    words for a fit whose data reject its model; for a number built from other fits (inherited),
    'model rejected (φ_μ fit: χ²/dof = 2.31, residuals trend, runs test p = 0.0004)'."""
    return "model rejected (" + _why(g) + ")"


def _why(g):
    if g.get("from"):
        return "; ".join(g["from"])
    why = []
    if g.get("chi2_dof") is not None:
        p = chi2_p(g)
        far = f", χ² p = {_p(p)}" if chi2_far_out(g) else ""
        why.append(f"χ²/dof = {g['chi2_dof']:.2f}{far}")
    if g.get("trend"):
        why.append("residuals trend" + (f", runs test p = {_p(g['trend_p'])}" if g.get("trend_p") is not None else ""))
    return ", ".join(why)


def inherited(parts):
    """The goodness of a number that is not fitted itself but built from fits (the sum rule
    α_μ + φ_μ adds two fitted exponents): the data reject it when they reject any fit it is
    built from, whatever its own error says. parts: [(name, goodness dict)], e.g.
    [("φ_μ fit", {...}), ("α_μ fit", {...})]. Returns {} when none is rejected (nothing to say),
    else a dict that is_rejected and rejection_text read, naming each rejected part."""
    bad = [f"{name}: {_why(g)}" for name, g in parts if is_rejected(g)]
    return {"rejected": True, "trend": True, "from": bad} if bad else {}


def _p(p):
    return f"{p:.2g}"
