"""The fits that test the paper's claim (a) on one drag-vs-Fr curve: one line a + b Fr, a quadratic
a + b Fr + c Fr², the paper's shape (a line up to Fr₂, then a' + b' Fr² joined to it at Fr₂: a' = a +
b Fr₂ - b' Fr₂²) with Fr₂ fixed or profiled, and regime I's plateau up to Fr₁ continued by a line.

Every model is linear in its coefficients once its crossover is given, so each is a stack of design
matrices, one per crossover on a grid (Family), fitted by generalized least squares (the errors a
vector of standard errors or a covariance: a bed shifts all its speeds alike,
analysis.core.bed_shift) to many copies of the curve at once: the same code fits the data and the
thousands of synthetic copies the power calibration (analysis.regime_tests.regime_power) fits, so
the statistic it calibrates is the one reported.

The paper's shape is held to its own meaning: regime III rises at least as much as regime II's line
over the fitted range, b' (Fr_end² - Fr₂²) ≥ b (Fr_end - Fr₂), Fr_end the range's last speed.
Unconstrained, a' + b' Fr² with a small b' bends the line *down* past Fr₂ (b' = 0 is a plateau),
and a drag that flattens would "fit the paper's shape better than a line". Where the unconstrained
optimum breaks that, the constrained one lies on its boundary, b' = b / (Fr₂ + Fr_end) (Family's
fallback design). The constraint is the weakest that excludes flattening: it lets the slope drop at
Fr₂ (the paper's fits are continuous, not smooth), as the data of crossover-k2e6-box40-full want
(b' = 7.0 against b = 96 at Fr₂ = 5: the slope 70 just past 5; with the tangent join, b' ≥ b / 2Fr₂,
their χ² would be 7.1 instead of 4.3 on Fr 1-10). Regime I's line likewise may not fall (b ≥ 0;
else a constant). Chi-squares are against the errors given (errors in, not rescaled).
"""
import math

import numpy as np

from ..core import paper

PAPER_FR1 = paper.CROSSOVER_FR1
PAPER_FR2 = paper.CROSSOVER_FR2
GRID = 81   # crossover values profiled (plus the paper's, when inside)


def _rows(y):
    return np.atleast_2d(np.asarray(y, float))


def whitener(sigma):
    """W with W C Wᵀ = 1 for a curve's errors: sigma the points' standard errors (C diagonal) or
    their covariance C itself (n, n; the beds' shared shift, analysis.core.bed_shift)."""
    s = np.asarray(sigma, float)
    return np.diag(1 / s) if s.ndim == 1 else np.linalg.inv(np.linalg.cholesky(s))


def draw(sigma, z):
    """Noise of the curve's errors from standard normal draws z (copies, n)."""
    s = np.asarray(sigma, float)
    return s * z if s.ndim == 1 else z @ np.linalg.cholesky(s).T


def shrink(sigma, beds):
    """The errors with beds times as many beds: standard errors / √beds, a covariance / beds."""
    s = np.asarray(sigma, float)
    return s / math.sqrt(beds) if s.ndim == 1 else s / beds


def scale(sigma, factor):
    """The errors scaled up by factor (a covariance by factor²)."""
    s = np.asarray(sigma, float)
    return s * factor if s.ndim == 1 else s * factor ** 2


def wls(X, y, sigma):
    """Generalized least squares of y, shape (n,) or (copies, n), on the columns of X (n, p), with
    the errors sigma (whitener's: standard errors or a covariance): coefficients (copies, p), their
    covariance (p, p) from the errors alone (not scaled by χ²/dof) and χ² (copies,)."""
    W = whitener(sigma)
    Xw = W @ np.asarray(X, float)
    pinv = np.linalg.pinv(Xw)
    Y = _rows(y) @ W.T
    beta = Y @ pinv.T
    return beta, pinv @ pinv.T, np.sum((Y - beta @ Xw.T) ** 2, axis=1)


def line_design(x):
    return np.column_stack([np.ones_like(x), x])


def quadratic_design(x):
    return np.column_stack([np.ones_like(x), x, x * x])


def paper_design(x, fr2):
    """(len(fr2), n, 3): columns 1, min(Fr, Fr₂), max(Fr, Fr₂)² - Fr₂² for the coefficients a, b, b'
    (continuity gives a' = a + b Fr₂ - b' Fr₂²)."""
    f = np.atleast_1d(np.asarray(fr2, float))[:, None]
    X = np.asarray(x, float)[None, :]
    return np.stack([np.ones_like(X * f), np.minimum(X, f) * np.ones_like(f), np.maximum(X, f) ** 2 - f ** 2], axis=-1)


def paper_tied_design(x, fr2, ratio):
    """The paper's shape with b' tied to b, b' = ratio b (ratio per Fr₂): columns 1 and
    min(Fr, Fr₂) + ratio (max(Fr, Fr₂)² - Fr₂²) for a, b."""
    d = paper_design(x, fr2)
    r = np.broadcast_to(np.asarray(ratio, float), (len(d),))[:, None]
    return np.stack([d[..., 0], d[..., 1] + r * d[..., 2]], axis=-1)


def paper_tangent_design(x, fr2):
    """The quadratic leaving the line tangentially at Fr₂ (b' = b / 2Fr₂): the least regime III whose
    slope does not drop at Fr₂."""
    f = np.atleast_1d(np.asarray(fr2, float))
    return paper_tied_design(x, f, 1 / (2 * f))


def paper_least_design(x, fr2, end):
    """The quadratic meeting the line continued again at Fr = end (b' = b / (Fr₂ + end)): the least
    regime III PaperShape allows."""
    f = np.atleast_1d(np.asarray(fr2, float))
    return paper_tied_design(x, f, 1 / (f + end))


def plateau_design(x, fr1):
    """(len(fr1), n, 2): regime I's plateau a up to Fr₁, then a line a + b (Fr - Fr₁)."""
    f = np.atleast_1d(np.asarray(fr1, float))[:, None]
    X = np.asarray(x, float)[None, :]
    return np.stack([np.ones_like(X * f), np.maximum(X - f, 0.0)], axis=-1)


class Family:
    """One model on fixed Fr points and errors: a design per crossover value (designs (G, n, p)),
    each with an optional fallback (G, n, q) used where the fitted coefficients break the model's
    meaning (`breaks(beta, crossovers)` true), its coefficients mapped back by `expand`. Each
    weighted design is factored once (QR), so fitting thousands of copies is two matrix products."""

    def __init__(self, x, sigma, designs, crossovers=None, fallback=None, breaks=None, expand=None):
        self.x, self.sigma = np.asarray(x, float), np.asarray(sigma, float)
        self.W = whitener(self.sigma)
        self.designs = np.asarray(designs, float)
        if self.designs.ndim == 2:
            self.designs = self.designs[None]
        self.crossovers = np.full(len(self.designs), np.nan) if crossovers is None else np.asarray(crossovers, float)
        self.breaks, self.expand = breaks, expand
        self._main = self._factor(self.designs)
        self._fallback = None if fallback is None else self._factor(np.asarray(fallback, float))

    def _factor(self, designs):
        Q, R = np.linalg.qr(np.matmul(self.W, designs))
        return Q, np.linalg.pinv(R).transpose(0, 2, 1)   # pinv: a degenerate design fits, minimum-norm

    @staticmethod
    def _fit(factors, Yw, norm2):
        Q, RinvT = factors
        proj = np.matmul(Yw[None], Q)            # (G, copies, p): the fit in Q's basis
        return np.matmul(proj, RinvT), np.maximum(norm2 - np.sum(proj * proj, axis=-1), 0.0)

    def fit_all(self, y):
        """Coefficients (G, copies, p) and χ² (G, copies) of every copy at every crossover."""
        Yw = _rows(y) @ self.W.T
        norm2 = np.sum(Yw * Yw, axis=1)
        beta, chi2 = self._fit(self._main, Yw, norm2)
        if self._fallback is not None:
            bad = self.breaks(beta, self.crossovers[:, None])
            if bad.any():
                b2, c2 = self._fit(self._fallback, Yw, norm2)
                beta = np.where(bad[..., None], self.expand(b2, self.crossovers[:, None]), beta)
                chi2 = np.where(bad, c2, chi2)
        return beta, chi2

    def best(self, y):
        """Per copy: the least χ² over the crossovers, its index and coefficients."""
        beta, chi2 = self.fit_all(y)
        k = np.argmin(chi2, axis=0)
        i = np.arange(chi2.shape[1])
        return chi2[k, i], k, beta[k, i]


class Line(Family):
    def __init__(self, x, sigma):
        super().__init__(x, sigma, line_design(np.asarray(x, float)))


class Quadratic(Family):
    def __init__(self, x, sigma):
        super().__init__(x, sigma, quadratic_design(np.asarray(x, float)))


class PaperShape(Family):
    """Line up to Fr₂, then a' + b' Fr² ending the range (at fr_end, default the last speed) at or
    above the line continued; Fr₂ one value or a grid (profiled)."""

    def __init__(self, x, sigma, fr2, fr_end=None):
        fr2 = np.atleast_1d(np.asarray(fr2, float))
        end = float(np.max(x)) if fr_end is None else float(fr_end)
        least = lambda b, f: b / (f + end)   # b' with the quadratic's secant slope over (Fr₂, end] = b
        super().__init__(x, sigma, paper_design(x, fr2), fr2, paper_least_design(x, fr2, end),
                         lambda beta, f: beta[..., 2] < least(beta[..., 1], f),
                         lambda beta, f: np.stack([beta[..., 0], beta[..., 1], least(beta[..., 1], f)], axis=-1))


class PlateauLine(Family):
    """Regime I: a plateau up to Fr₁, then a line that does not fall; Fr₁ one value or a grid."""

    def __init__(self, x, sigma, fr1):
        fr1 = np.atleast_1d(np.asarray(fr1, float))
        super().__init__(x, sigma, plateau_design(x, fr1), fr1, np.ones((len(fr1), len(x), 1)),
                         lambda beta, _f: beta[..., 1] < 0,
                         lambda beta, _f: np.stack([beta[..., 0], np.zeros_like(beta[..., 0])], axis=-1))


def interior_grid(x, keep_low, keep_high, paper_value, n=GRID):
    """Crossover values from the keep_low-th smallest distinct Fr to the keep_high-th largest (so
    that each side keeps that many speeds), with the paper's value added when inside; empty when
    the range has too few distinct speeds."""
    u = np.unique(np.asarray(x, float))
    if len(u) < keep_low + keep_high or u[keep_low - 1] >= u[-keep_high]:
        return np.array([])
    g = np.linspace(u[keep_low - 1], u[-keep_high], n)
    if g[0] <= paper_value <= g[-1]:
        g = np.union1d(g, [paper_value])
    return g


def fr2_grid(x):
    """Fr₂ profiled where the line keeps 2 speeds and the quadratic 2, the joint's speed counted in
    both (from the second slowest to the second fastest)."""
    return interior_grid(x, 2, 2, PAPER_FR2)


def fr1_grid(x):
    """Fr₁ profiled from the slowest speed (where the plateau is empty: the model is then the line
    itself) to the last but one (the line after it keeps one speed besides its start)."""
    return interior_grid(x, 1, 2, PAPER_FR1)


def profile_interval(crossovers, chi2, delta=1.0):
    """(lo, hi, at_edge): the extent of the crossovers whose χ² lies within delta of the least, and
    whether it reaches the grid's end (then the interval is open on that side)."""
    inside = np.flatnonzero(chi2 <= np.min(chi2) + delta)
    return (float(crossovers[inside[0]]), float(crossovers[inside[-1]]),
            bool(inside[0] == 0 or inside[-1] == len(crossovers) - 1))


# --- one curve -----------------------------------------------------------------


def fit_line(fr, F, err):
    """a + b Fr: a, b, their errors, χ², dof."""
    beta, cov, chi2 = wls(line_design(np.asarray(fr, float)), F, err)
    e = np.sqrt(np.diag(cov))
    return {"a": beta[0, 0], "b": beta[0, 1], "a_err": e[0], "b_err": e[1], "chi2": chi2[0], "dof": len(fr) - 2}


def fit_quadratic(fr, F, err):
    """a + b Fr + c Fr²: the coefficients, c's standard error, χ², dof."""
    beta, cov, chi2 = wls(quadratic_design(np.asarray(fr, float)), F, err)
    return {"a": beta[0, 0], "b": beta[0, 1], "c": beta[0, 2], "c_err": float(np.sqrt(cov[2, 2])),
            "chi2": chi2[0], "dof": len(fr) - 3}


def fit_paper_shape(fr, F, err, fr2=PAPER_FR2):
    """The paper's shape at a fixed Fr₂: a, b, b' (and its error), a' (continuity), whether it was held on its
    constraint (held: the free optimum flattened; PaperShape), χ², dof (3 coefficients)."""
    fam = PaperShape(fr, err, [fr2])
    chi2, _, beta = fam.best(F)
    return _paper_row(beta[0], fr2, chi2[0], len(fr) - 3, fr, err)


def profile_paper_shape(fr, F, err, grid=None):
    """The paper's shape with Fr₂ profiled over grid (default fr2_grid): the best Fr₂, its Δχ² ≤ 1
    interval (Fr2_lo, Fr2_hi, open when at_edge), χ², dof (3 coefficients and Fr₂) and the profile
    (grid, chi2). None when the range has too few speeds."""
    grid = fr2_grid(fr) if grid is None else np.asarray(grid, float)
    if not len(grid):
        return None
    fam = PaperShape(fr, err, grid)
    beta, chi2 = fam.fit_all(F)
    k = int(np.argmin(chi2[:, 0]))
    lo, hi, edge = profile_interval(grid, chi2[:, 0])
    return {**_paper_row(beta[k, 0], grid[k], chi2[k, 0], len(fr) - 4, fr, err), "Fr2_lo": lo, "Fr2_hi": hi,
            "at_edge": edge, "grid": grid, "profile": chi2[:, 0]}


def _paper_row(beta, fr2, chi2, dof, fr, err):
    """b2_err: b''s standard error at this Fr₂ from the errors, as if unconstrained."""
    a, b, b2 = (float(v) for v in beta)
    end = float(np.max(fr))
    b2_err = math.sqrt(wls(paper_design(np.asarray(fr, float), [fr2])[0], np.zeros(len(fr)), err)[1][2, 2])
    return {"a": a, "b": b, "b2": b2, "b2_err": b2_err, "a2": a + b * fr2 - b2 * fr2 ** 2, "Fr2": float(fr2),
            "held": bool(np.isclose(b2 * (fr2 + end), b, rtol=1e-9, atol=1e-12 * max(1.0, abs(b)))),
            "chi2": float(chi2), "dof": dof}


def paper_curve(fr, a, b, b2, Fr2, **_):
    """The paper's shape at fr from a fit row (fit_paper_shape, profile_paper_shape)."""
    return paper_design(np.asarray(fr, float), [Fr2])[0] @ np.array([a, b, b2])


def profile_plateau_line(fr, F, err, grid=None):
    """Regime I's plateau up to Fr₁, then a line, Fr₁ profiled over grid (default fr1_grid): the
    plateau a, slope b, Fr₁ with its Δχ² ≤ 1 interval, χ², dof (2 coefficients and Fr₁). None when
    the range has too few speeds."""
    grid = fr1_grid(fr) if grid is None else np.asarray(grid, float)
    if not len(grid):
        return None
    fam = PlateauLine(fr, err, grid)
    beta, chi2 = fam.fit_all(F)
    k = int(np.argmin(chi2[:, 0]))
    lo, hi, edge = profile_interval(grid, chi2[:, 0])
    return {"a": float(beta[k, 0, 0]), "b": float(beta[k, 0, 1]), "Fr1": float(grid[k]), "Fr1_lo": lo,
            "Fr1_hi": hi, "at_edge": edge, "chi2": float(chi2[k, 0]), "dof": len(fr) - 3, "grid": grid,
            "profile": chi2[:, 0]}


def plateau_curve(fr, a, b, Fr1, **_):
    """Regime I's plateau-then-line at fr from a fit row (profile_plateau_line)."""
    return a + b * np.maximum(np.asarray(fr, float) - Fr1, 0.0)
