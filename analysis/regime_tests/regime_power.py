"""What a regime test can see on a given curve: its detection threshold, false-positive rate and
power, calibrated on synthetic copies of the curve, and the verdict in words that follows.

A copy is a mean curve plus Gaussian noise of the curve's own errors on its own Fr points (drawn
from their covariance when they have one: regime_fits.draw). The threshold of a statistic
(larger: more evidence for the alternative) is the 95th percentile over copies of the null, the
best-fit line, so 5 % of lines pass it. The actual false-positive rate is
measured apart, on fresh copies of lines drawn from that fit's covariance (the true line is not
the fitted one: the paper shape's Δχ² is not invariant to the line's slope). Power is the fraction
of copies of the alternative that pass the threshold.

The alternative the verdict uses is the paper's size, fitted to the data: for regime III the least
quadratic whose slope does not drop at Fr₂ = 5, leaving the line tangentially (b' = b / 2Fr₂; the
fitted family allows weaker ones, regime_fits, so that the data may show one); for regime I a
plateau up to the paper's Fr₁ = 1 continued by the data's line. A test with little power against
it cannot say "not seen": the data cannot tell. How many more beds would reach 80 % power: the
errors shrink as 1/√beds; the same noise draws (common random numbers, so power grows smoothly) are
scaled and the threshold recalibrated.
"""
import math

import numpy as np
from scipy.stats import norm

from .regime_fits import (
    PAPER_FR1,
    PAPER_FR2,
    Line,
    PaperShape,
    PlateauLine,
    Quadratic,
    draw,
    fr1_grid,
    fr2_grid,
    line_design,
    paper_design,
    paper_tangent_design,
    plateau_design,
    shrink,
    wls,
)

N_SIM = 2000
LEVEL = 0.05          # false-positive rate the threshold is set at
TARGET_POWER = 0.8
MAX_BEDS = 128.0      # the largest factor of beds looked for
LINE_PLAIN = 0.16     # p above which the line is "preferred" (the data within 1 σ of it), not just kept


def statistic(test, x, sigma):
    """The statistic of a test as a function of copies Y (copies, n) of the curve at x with errors
    sigma; larger says more for the alternative.
      quadratic       c / σ_c of a + b Fr + c Fr² (one-sided: the paper's regime III curves up;
                      its Δχ² against the line is -(c/σ_c)²)
      paper_fr2_5     χ²(line) - χ²(paper's shape, Fr₂ = 5)  (= -Δχ²)
      paper_fr2_free  χ²(line) - χ²(paper's shape, Fr₂ profiled)
      regime1         χ²(line) - χ²(plateau to Fr₁, then a line; Fr₁ profiled)
      blind_fr2_only  -χ²(paper's shape, Fr₂ profiled): finds the knee and asks only whether the
                      shape fits, never whether the line fits as well; for the tests, which show
                      that such a test has no power (a line fits the paper's shape with Fr₂ high)."""
    x, sigma = np.asarray(x, float), np.asarray(sigma, float)
    line = Line(x, sigma)
    if test == "quadratic":
        quad = Quadratic(x, sigma)
        c_err = math.sqrt(wls(quad.designs[0], np.zeros(len(x)), sigma)[1][2, 2])
        return lambda Y: quad.best(Y)[2][:, 2] / c_err
    if test == "blind_fr2_only":
        shape = PaperShape(x, sigma, fr2_grid(x))
        return lambda Y: -shape.best(Y)[0]
    alt = {"paper_fr2_5": lambda: PaperShape(x, sigma, [PAPER_FR2]),
           "paper_fr2_free": lambda: PaperShape(x, sigma, fr2_grid(x)),
           "regime1": lambda: PlateauLine(x, sigma, fr1_grid(x))}[test]()
    return lambda Y: _ties_at_zero(line.best(Y)[0], alt.best(Y)[0])


def _ties_at_zero(chi2_line, chi2_alt):
    """χ²(line) - χ²(alternative), exactly 0 where the alternative is the line itself (regime I's
    plateau at the slowest speed) rather than a rounding error's ±1e-12, so that ties count as ties."""
    d = chi2_line - chi2_alt
    return np.where(np.abs(d) <= 1e-9 * (1.0 + chi2_line), 0.0, d)


def paper_sized(test, x, F, sigma):
    """The mean curve of the paper-sized alternative fitted to the data (module docstring)."""
    x = np.asarray(x, float)
    if test == "regime1":
        shape = PlateauLine(x, sigma, [PAPER_FR1])
        return plateau_design(x, [PAPER_FR1])[0] @ shape.best(F)[2][0]
    design = paper_tangent_design(x, [PAPER_FR2])[0]
    return design @ wls(design, F, sigma)[0][0]


def best_fit(test, x, F, sigma):
    """The mean curve of the alternative as fitted (regime III: the paper's shape at Fr₂ = 5; regime I:
    the profiled plateau-then-line)."""
    x = np.asarray(x, float)
    if test == "regime1":
        grid = fr1_grid(x)
        _, k, beta = PlateauLine(x, sigma, grid).best(F)
        return plateau_design(x, [grid[k[0]]])[0] @ beta[0]
    return paper_design(x, [PAPER_FR2])[0] @ PaperShape(x, sigma, [PAPER_FR2]).best(F)[2][0]


class Calibration:
    """A statistic calibrated on copies of the curve (x, F, sigma) for one test."""

    def __init__(self, test, x, F, sigma, n_sim=N_SIM, seed=0):
        if n_sim < 100:
            raise ValueError(f"a calibration needs at least 100 synthetic copies, got {n_sim}")
        self.test, self.n_sim = test, n_sim
        self.x, self.F, self.sigma = np.asarray(x, float), np.asarray(F, float), np.asarray(sigma, float)
        self.stat = statistic(test, self.x, self.sigma)
        rng = np.random.default_rng(seed)
        n = len(self.x)
        self._z_null, self._z_alt, z_check = (rng.standard_normal((n_sim, n)) for _ in range(3))
        beta, cov, _ = wls(line_design(self.x), self.F, self.sigma)
        self.null = line_design(self.x) @ beta[0]
        self.alt = paper_sized(test, self.x, self.F, self.sigma)
        self.observed = float(self.stat(self.F)[0])
        self.null_sample = self.stat(self.null + draw(self.sigma, self._z_null))
        self.threshold = float(np.quantile(self.null_sample, 1 - LEVEL))
        lines = rng.multivariate_normal(beta[0], cov, n_sim) @ line_design(self.x).T
        self.false_positive_rate = float(np.mean(self.stat(lines + draw(self.sigma, z_check)) > self.threshold))
        self.alt_sample = self.stat(self.alt + draw(self.sigma, self._z_alt))
        self.power = float(np.mean(self.alt_sample > self.threshold))
        fitted = best_fit(test, self.x, self.F, self.sigma)
        self.power_best_fit = float(np.mean(self.stat(fitted + draw(self.sigma, self._z_alt)) > self.threshold))

    @property
    def p(self):
        """The observed statistic's p-value under the null: the fraction of null copies at least as large."""
        return (1 + int(np.sum(self.null_sample >= self.observed))) / (self.n_sim + 1)

    @property
    def excluded_sigma(self):
        """How far the observation lies below the paper-sized alternative, in normal standard
        deviations: Φ⁻¹(1 - p_alt), p_alt the fraction of its copies at most as large; (value,
        at_limit: no copy was, the value is then a lower bound)."""
        below = int(np.sum(self.alt_sample <= self.observed))
        return float(norm.isf((1 + below) / (self.n_sim + 1))), below == 0

    def power_at(self, beds):
        """Power against the paper-sized alternative with the errors shrunk by √beds (same draws)."""
        scale = shrink(self.sigma, beds)
        thr = np.quantile(self.stat(self.null + draw(scale, self._z_null)), 1 - LEVEL)
        return float(np.mean(self.stat(self.alt + draw(scale, self._z_alt)) > thr))

    def beds_for(self, target=TARGET_POWER, max_beds=MAX_BEDS):
        """The factor of beds at which the power reaches target: doubled until it does, then
        bisected in log; inf beyond max_beds."""
        if self.power >= target:
            return 1.0
        lo, hi = 1.0, 2.0
        while self.power_at(hi) < target:
            lo, hi = hi, hi * 2
            if hi > max_beds:
                return math.inf
        for _ in range(4):
            mid = math.sqrt(lo * hi)
            lo, hi = (mid, hi) if self.power_at(mid) < target else (lo, mid)
        return hi


# --- the verdict ------------------------------------------------------------------


def _num(v, digits=2):
    return f"{v:.{digits}g}" if abs(v) < 10 ** digits else f"{v:.0f}"


def outcome(cal, target=TARGET_POWER, fits_worse=False):
    """The kind of verdict (verdict's branches, which it words): "shown", "neither" (p < LEVEL but
    the shape fits worse than the line), "cannot tell" (power below target), "disfavoured" (the
    paper's size below 1.64 σ away), "line preferred" (excluded, p ≥ LINE_PLAIN) or "between"."""
    if cal.p < LEVEL:
        return "neither" if fits_worse else "shown"
    if cal.power < target:
        return "cannot tell"
    if cal.excluded_sigma[0] < norm.isf(LEVEL):
        return "disfavoured"
    return "line preferred" if cal.p >= LINE_PLAIN else "between"


def verdict(shown, found, cal, alternative, beds=None, target=TARGET_POWER, fits_worse=False):
    """The verdict in words. shown: what a detection shows ("a quadratic from Fr ≈ 5"); found: the
    measured numbers ("Δχ² = -1.0"); alternative: the paper-sized alternative ("a quadratic of the
    paper's size"); beds: the curve's beds now; fits_worse: the alternative's fit has a larger χ²
    than the line's (Δχ² > 0; the paper's shape does not contain the line). Shown when p < LEVEL
    and the alternative fits better; when p < LEVEL but it fits worse, the line is strained in the
    alternative's direction (its copies fit the shape worse still) without the shape describing the
    data: neither is shown. Else, when the power against the paper's size is below target, the
    data cannot tell (and how many more beds would); else the paper's size is excluded (at ≥ 1.64 σ;
    "a line preferred" only when the line is within about 1 σ, p ≥ LINE_PLAIN, else the data lie
    between the two) or only disfavoured."""
    p, kind = cal.p, outcome(cal, target, fits_worse)
    if kind == "neither":
        return (f"not shown: the shape fits worse than one line ({found}), though better than lines "
                f"usually do (p = {p:.2g}): the data are neither")
    if kind == "shown":
        return f"{shown} shown ({found}, p = {p:.2g})"
    if kind == "cannot tell":
        k = cal.beds_for(target)
        now = f"{math.ceil(k * beds)} instead of {beds}; " if beds and math.isfinite(k) else ""
        more = (f"more than {MAX_BEDS:g}× as many beds would be needed" if not math.isfinite(k) else
                f"about {_num(k)}× as many beds would ({now}or as many times the speeds on this range)")
        return (f"these data cannot tell ({found}, p = {p:.2g}; power {cal.power:.2f} against {alternative} "
                f"at {LEVEL * 100:g} % false positives): {more}")
    n, limit = cal.excluded_sigma
    size = f"{'≥ ' if limit else ''}{n:.1f} σ"
    if kind == "disfavoured":
        return (f"not shown ({found}, p = {p:.2g}); {alternative} disfavoured at {size} only, not excluded "
                f"(power {cal.power:.2f})")
    if kind == "line preferred":
        return f"a line preferred ({found}, p = {p:.2g}); {alternative} excluded at {size} (power {cal.power:.2f})"
    return (f"between a line ({found}, p = {p:.2g}) and {alternative} (excluded at {size}, power "
            f"{cal.power:.2f}): weaker than the paper's")
