"""Least squares without an iterative optimiser: the same answer on every NumPy and SciPy.

SciPy's curve_fit stops where its tolerances say, and where that is moved between releases: on
one table (results/reproduction/config) θ's Υ1 differed by 2e-6 between Debian's SciPy 1.10 and
the project environment's 1.17, φ and α by 1e-8, and tightening the tolerances to 1e-15 still
left 3e-7 in θ's flat valley (issue 76). Every model fitted here is linear in all its parameters
but at most one, so none needs the optimiser:

    linear_fit      a model linear in every parameter: the weighted least-squares solution
    separable_fit   linear but for one parameter q: for each q the linear ones are solved
                    exactly (one of them within bounds), and q is profiled, a grid over its
                    bounds then a golden-section search between the best grid point's
                    neighbours, to 1e-12 of q (a flat valley's minimum still moves with each
                    library's rounding: θ's Υ2 on results/reproduction/config by 2e-7)
    covariance      (J'WJ)^-1 at the solution, J by central differences (jacobian), as
                    curve_fit's absolute_sigma; unweighted, scaled by the residuals' variance;
                    and ill_posed: why the covariance means nothing, when it does not

The fit's own choices (bounds, grid, golden section) are the only ones: nothing depends on a
library's default.
"""
import math

import numpy as np

GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0
Q_GRID = 60          # profile grid points over the nonlinear parameter's bounds (log spaced)
Q_RTOL = 1e-12       # golden-section stop: the bracket's width in log q


def jacobian(model, x, p):
    """d model(x, *p) / dp by central differences, shape (len(x), len(p))."""
    p = np.asarray(p, float)
    J = np.empty((len(x), len(p)))
    for j in range(len(p)):
        h = 1e-6 * max(1.0, abs(p[j]))
        up, dn = p.copy(), p.copy()
        up[j] += h
        dn[j] -= h
        J[:, j] = (model(x, *up) - model(x, *dn)) / (2 * h)
    return J


def _root_weights(s, n):
    return np.ones(n) if s is None else 1.0 / np.asarray(s, float)


def _solve(X, y, sw, bound=None):
    """Weighted least squares of y on the columns X; bound (j, lo, hi) keeps beta_j within
    [lo, hi]: outside, beta_j sits on the nearer bound and the others are solved again (the
    squared error is a convex quadratic, so its minimum on the box is there). (beta, sse)."""
    Xw, yw = X * sw[:, None], y * sw
    beta = np.linalg.lstsq(Xw, yw, rcond=None)[0]
    if bound is not None:
        j, lo, hi = bound
        if not lo <= beta[j] <= hi:
            fixed = min(max(beta[j], lo), hi)
            rest = [k for k in range(X.shape[1]) if k != j]
            beta = np.empty(X.shape[1])
            beta[j] = fixed
            beta[rest] = np.linalg.lstsq(Xw[:, rest], yw - fixed * Xw[:, j], rcond=None)[0]
    r = yw - Xw @ beta
    return beta, float(r @ r)


def linear_fit(model, x, y, s, n_params):
    """The exact weighted least-squares parameters of a model linear in all n_params (its
    columns: the model at each unit parameter vector)."""
    X = np.column_stack([model(x, *row) for row in np.eye(n_params)])
    return _solve(X, y, _root_weights(s, len(x)))[0]


def separable_fit(columns, x, y, s, q_bounds, bound=None):
    """(q, beta) minimising the weighted squared error of y = columns(x, q) @ beta with q in
    q_bounds (both > 0; profiled in log q) and beta within `bound` (_solve)."""
    sw = _root_weights(s, len(x))
    sse = lambda lq: _solve(columns(x, math.exp(lq)), y, sw, bound)[1]   # noqa: E731
    lo, hi = math.log(q_bounds[0]), math.log(q_bounds[1])
    grid = np.linspace(lo, hi, Q_GRID)
    k = int(np.argmin([sse(g) for g in grid]))
    a, b = grid[max(k - 1, 0)], grid[min(k + 1, Q_GRID - 1)]
    c, d = b - GOLDEN * (b - a), a + GOLDEN * (b - a)
    fc, fd = sse(c), sse(d)
    while b - a > Q_RTOL:
        if fc <= fd:
            b, d, fd = d, c, fc
            c = b - GOLDEN * (b - a)
            fc = sse(c)
        else:
            a, c, fc = c, d, fd
            d = a + GOLDEN * (b - a)
            fd = sse(d)
    # The best point seen: the search's last bracket, or the grid point when the profile rises
    # from a bound (the minimum on the bound itself).
    cands = [(sse(grid[k]), grid[k]), (fc, c), (fd, d)]
    lq = min(cands, key=lambda t: t[0])[1]
    q = math.exp(lq)
    return q, _solve(columns(x, q), y, sw, bound)[0]


# A minimum is fixed only to about sqrt(machine epsilon) of each parameter; a covariance whose
# normal matrix (columns scaled to unit diagonal) has a condition number beyond its inverse
# turns that into errors of no precision at all. θ(Fr) on the smoke study's two series at three
# speeds, U3 on its bound: 1.3e10, and its errors 7e-5 apart between the stacks (results/
# reproduction/config's θ: 5.6e5, 3.7e-7 apart).
MAX_CONDITION = 1.0 / math.sqrt(np.finfo(float).eps)


def ill_posed(model, x, popt, s):
    """Why the parameters' covariance at popt is not estimable, in words; "" when it is."""
    J = jacobian(model, x, popt) * _root_weights(s, len(x))[:, None]
    norm = np.linalg.norm(J, axis=0)
    if not np.all(norm > 0):
        return "a parameter moves no fitted value: its error is not estimable"
    cond = float(np.linalg.cond((J / norm).T @ (J / norm)))
    if cond > MAX_CONDITION:
        return (f"ill-posed: the parameters' covariance is singular to the precision the fit fixes them "
                f"to (condition number {cond:.2g}, above {MAX_CONDITION:.2g}): errors not estimable")
    return ""


def covariance(model, x, y, popt, s):
    """The parameters' covariance at popt: (J'WJ)^-1 with W = 1/s^2 (curve_fit's absolute_sigma);
    without errors, (J'J)^-1 times the residuals' variance (inf without degrees of freedom)."""
    J = jacobian(model, x, popt)
    W = _root_weights(s, len(x)) ** 2
    cov = np.linalg.pinv(J.T @ (W[:, None] * J))
    if s is None:
        dof = len(x) - len(popt)
        r = y - model(x, *popt)
        cov = cov * (float(r @ r) / dof if dof > 0 else np.inf)
    return cov
