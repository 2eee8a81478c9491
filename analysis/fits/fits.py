"""Fits of the paper's laws, each returning values with standard errors.

Where the errors come from:
  fit_regimes             bootstrap refits, crossovers included (regimes.py)
  fit_theta, fit_linear,  least squares solved exactly, one nonlinear parameter profiled
                          (least_squares.py: no optimiser, the same on every SciPy); errors:
                          least-squares covariance (with the beds' shared errors: beds.py),
  fit_power_law,          scaled by the reduced chi^2 when above 1; NaN when there are no
  fit_saturation          degrees of freedom left
  fit_scaling_law         lambda and predictions: bootstrap of the regime fit on the collapsed
                          data resampling the beds (alpha and phi refitted), beds.BedDraws

The JSON fit file that keeps them: fit_file.py (save_fits, load_fits).
"""
import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..core import paper
from ..core.result import N_BOOT, Fit, Param
from ..core.table import (
    bed_labels,
    froude,
    is_yield,
    observable_errors,
    pooled_drag_err,
    reference_params,
    select,
    yield_rows,
)
from .beds import BedDraws, bed_covariance
from .goodness import goodness
from .least_squares import covariance, ill_posed, linear_fit, separable_fit
from .regimes import RegimeFitter, fit_regimes, regime_curve

__all__ = ["Fit", "Param", "fit_regimes", "regime_curve", "fit_theta", "fit_kappa",
           "fit_linear", "fit_broken_line", "fit_power_law", "fit_saturation", "fit_phi", "fit_alpha",
           "sum_rule", "fit_scaling_law", "ScalingLaw", "evaluate"]


# --- model functions -----------------------------------------------------

def theta_curve(Fr, U1, U2, U3):
    """Paper Eq. 7: theta = U1 Fr^U2 + pi/U3."""
    return U1 * np.power(np.asarray(Fr, float), U2) + np.pi / U3


def linear_curve(x, k0, k1):
    return k0 + k1 * np.asarray(x, float)


def broken_line_curve(x, level, below, above, knee=5.0):
    """A line broken at x = knee: slope `below` before it, `above` after, `level` at it."""
    x = np.asarray(x, float)
    return level + below * np.minimum(x - knee, 0.0) + above * np.maximum(x - knee, 0.0)


def power_curve(x, A, p):
    return A * np.power(np.asarray(x, float), p)


def saturation_curve(mu, F0, dF, mu_c):
    """F_Y(mu) rising from F0 by dF with friction scale mu_c, then flat."""
    return F0 + dF * (1.0 - np.exp(-np.asarray(mu, float) / mu_c))


MODELS = {"regimes": regime_curve, "theta": theta_curve, "linear": linear_curve,
          "power_law": power_curve, "saturation": saturation_curve, "broken_line": broken_line_curve}


def evaluate(fit, x):
    """The fitted curve of any Fit at x (with the parameters it held fixed, meta["fixed"])."""
    return MODELS[fit.model](x, **fit.values(), **fit.meta.get("fixed", {}))


def evaluate_replicates(fit, x):
    """The curve of every bootstrap refit, shape (n_refits, len(x))."""
    names = list(fit.params)
    fixed = fit.meta.get("fixed", {})
    return np.array([MODELS[fit.model](x, **dict(zip(names, row)), **fixed) for row in fit.replicates])


# --- least squares with covariance errors -------------------------------

def _weights(sigma, n):
    if sigma is None:
        return None
    s = np.asarray(sigma, float)
    return s if (len(s) == n and np.all(np.isfinite(s) & (s > 0))) else None


def _covariance_fit(model, name, x, y, sigma, solve, names, bounds=(-np.inf, np.inf), groups=None,
                    shared=None, beds=None):
    """solve(x, y, s): the parameters (least_squares.py; None: the model is linear in all).
    groups: each point's series, for the goodness's runs test (goodness.py); shared, beds: the
    part of each point's error its bed shares, and its bed (beds.bed_covariance)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    ok = np.isfinite(x) & np.isfinite(y)
    s = _weights(None if sigma is None else np.asarray(sigma, float)[ok], ok.sum())
    x, y = x[ok], y[ok]
    groups = None if groups is None else np.asarray(groups)[ok]
    if shared is not None:
        shared, beds = np.asarray(shared, float)[ok], np.asarray(beds)[ok]
    if len(x) < len(names):
        raise ValueError(f"{name} fit needs at least {len(names)} points, got {len(x)}")
    # With errors: the covariance they give (absolute), scaled below; an exact fit (chi^2 = 0)
    # then keeps the measurements' error.
    popt = linear_fit(model, x, y, s, len(names)) if solve is None else solve(x, y, s)
    pcov = covariance(model, x, y, popt, s)
    dof = len(x) - len(names)
    method = "least-squares covariance scaled by reduced chi^2"
    if s is not None and shared is not None and np.any(shared > 0):   # the beds' shared errors
        pcov = bed_covariance(model, x, popt, s, shared, beds)
    if s is not None and dof > 0:
        # With measurement errors, scale only up (the PDG convention): a few points that happen
        # to lie on the curve (chi^2/dof << 1; 3 yield forces, 2 parameters) would otherwise
        # claim a far smaller error than the measurements carry.
        chi2 = float(np.sum(((y - model(x, *popt)) / s) ** 2)) / dof
        if chi2 > 1:
            pcov = pcov * chi2
        method = "least-squares covariance scaled by reduced chi^2 when > 1"
    # Ill-posed (least_squares.ill_posed): no error rather than one of no precision, which moved
    # with the library's rounding; the report calls its numbers inconclusive and says why.
    why = ill_posed(model, x, popt, s)
    err = np.sqrt(np.diag(pcov)) if dof > 0 and not why else np.full(len(names), np.nan)
    return Fit(model=name, params={k: Param(float(v), float(e)) for k, v, e in zip(names, popt, err)},
               covariance=pcov if dof > 0 and not why else None,
               method=method + ("" if s is not None else " (unweighted: no per-point errors)"),
               n_points=len(x), x_range=(float(x.min()), float(x.max())),
               meta={"at_bounds": _at_bounds(names, popt, bounds), "weighted": s is not None,
                     **({"ill_posed": why} if why else {}),
                     "errors_from": "points" if s is not None and dof > 0 and chi2 <= 1 else "residuals",
                     "goodness": goodness(x, y, model(x, *popt), len(names), s, groups)})


def _at_bounds(names, values, bounds):
    """Parameters that ended on a finite bound of the fit, in words."""
    lo, hi = (np.broadcast_to(np.asarray(b, float), (len(names),)) for b in bounds)
    out = []
    for k, v, a, b in zip(names, values, lo, hi):
        for bound, side in ((a, "lower"), (b, "upper")):
            if np.isfinite(bound) and abs(v - bound) <= 1e-4 * max(1.0, abs(bound)):
                out.append(f"{k} = {v:.4g} at its {side} bound {bound:g}")
    return out


# Eq. 7's bounds: U2 (profiled) and U3, held as pi/U3, the constant it is linear in.
THETA_BOUNDS = ([-np.inf, 1e-3, 0.1], [np.inf, 5.0, 100.0])


def _theta_solve(Fr, theta, s):
    """(U1, U2, U3): for each U2 the model is linear in U1 and pi/U3 (least_squares.separable_fit)."""
    (_, lo2, lo3), (_, hi2, hi3) = THETA_BOUNDS
    columns = lambda x, U2: np.column_stack([x ** U2, np.ones_like(x)])   # noqa: E731
    U2, (U1, c) = separable_fit(columns, Fr, theta, s, (lo2, hi2), bound=(1, np.pi / hi3, np.pi / lo3))
    return np.array([U1, U2, np.pi / c])


THETA_MIN_POINTS = 3   # Eq. 7 has three parameters
# θ's two definitions, each fitted by Eq. 7 (fits.json keys `theta`, `theta_present`): table column ->
# what it averages (its fit's meta `definition`).
THETA_DEFINITIONS = {"theta": "per contact formation",
                     "theta_present": "time-weighted, over the contacts present at each sample"}


def fit_theta(Fr, theta, sigma=None, groups=None, shared=None, beds=None):
    """theta(Fr) = U1 Fr^U2 + pi/U3 (paper Eq. 7; paper: -0.15, 0.38, 2.45), weighted by
    the per-point errors sigma when given. U2 is profiled over its bounds (_theta_solve), with
    no start from the paper's numbers; bounds U2 in [1e-3, 5] and
    U3 in [0.1, 100] are reported in meta["at_bounds"] when reached. groups: each point's series
    (its D), for the goodness's runs test. shared, beds: the part of each point's error its bed
    shares and the beds (beds.bed_covariance; table.observable_errors)."""
    Fr, theta = np.asarray(Fr, float), np.asarray(theta, float)
    ok = np.isfinite(Fr) & np.isfinite(theta) & (Fr > 0)
    s = _weights(None if sigma is None else np.asarray(sigma, float)[ok], ok.sum())
    if ok.sum() < THETA_MIN_POINTS:
        raise ValueError(f"theta fit needs at least {THETA_MIN_POINTS} points, got {ok.sum()}")
    sub = lambda v: None if v is None else np.asarray(v)[ok]   # noqa: E731
    return _covariance_fit(theta_curve, "theta", Fr[ok], theta[ok], s, _theta_solve, ["U1", "U2", "U3"],
                           bounds=THETA_BOUNDS, groups=sub(groups), shared=sub(shared), beds=sub(beds))


def fit_linear(x, y, sigma=None, groups=None, shared=None, beds=None):
    """y = k0 + k1 x."""
    return _covariance_fit(linear_curve, "linear", x, y, sigma, None, ["k0", "k1"], groups=groups,
                           shared=shared, beds=beds)


def fit_broken_line(x, y, sigma=None, knee=5.0):
    """y = level + below min(x - knee, 0) + above max(x - knee, 0), the knee held fixed
    (meta["fixed"]); Fit.covariance is the parameters' covariance, for a ratio or a difference of
    the slopes."""
    def model(x, level, below, above):
        return broken_line_curve(x, level, below, above, knee)
    y = np.asarray(y, float)
    fit = _covariance_fit(model, "broken_line", x, y, sigma, None, ["level", "below", "above"])
    fit.meta["fixed"] = {"knee": float(knee)}
    return fit


def fit_kappa(df, pool=None):
    """kappa(Fr) = k0 + k1 Fr over all rows with kappa (paper: 0.887 + 0.185 Fr), weighted
    by the per-point errors (column kappa_err) when the table has them for every row. The
    residuals' runs are counted per series (series_labels: D, and depth when D has several). The
    beds' part of the errors, pooled over `pool`, is shared (table.observable_errors)."""
    if "kappa_err" not in df.columns:
        return fit_linear(df.Fr, df.kappa, None, groups=series_labels(df))
    sigma, shared = observable_errors(df, "kappa", pool)
    return fit_linear(df.Fr, df.kappa, sigma, groups=series_labels(df), shared=shared, beds=bed_labels(df))


def series_labels(df):
    """A label per row naming its series: D, with the depth (h to 0.1 d) where one D was pulled
    at several depths (two beds' series would otherwise pass for one)."""
    h = df.h.round(1) if "h" in df.columns else pd.Series(0.0, index=df.index)
    many = h.groupby(df.D).transform("nunique") > 1
    return np.where(many, [f"D = {D:g}, h = {v:g}" for D, v in zip(df.D, h)], [f"D = {D:g}" for D in df.D])


def fit_power_law(x, y, sigma=None):
    """y = A x^p, fitted as a straight line in log-log (relative errors)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    if np.any(x <= 0) or np.any(y <= 0):
        raise ValueError("power-law fit needs positive x and y")
    rel = None if sigma is None else np.asarray(sigma, float) / y
    line = fit_linear(np.log(x), np.log(y), rel)
    lnA, p = line["k0"], line["k1"]
    A = math.exp(lnA.value)
    return Fit(model="power_law", params={"A": Param(A, A * lnA.err), "p": p},
               method=line.method + " (straight line in log-log)",
               n_points=line.n_points, x_range=(float(x.min()), float(x.max())),
               meta={"goodness": line.meta["goodness"], "weighted": line.meta["weighted"]})


def fit_saturation(mu, FY, sigma=None):
    """F_Y(mu) = F0 + dF (1 - exp(-mu/mu_c)): mu_c small against the sampled
    range of mu means the yield force saturates there (paper Sec. III E)."""
    mu, FY = np.asarray(mu, float), np.asarray(FY, float)
    lo, hi = [-np.inf, 0.0, 1e-3], [np.inf, np.inf, 10.0]

    def solve(x, y, s):   # linear in F0 and dF for each mu_c, which is profiled
        columns = lambda m, mu_c: np.column_stack([np.ones_like(m), 1.0 - np.exp(-m / mu_c)])   # noqa: E731
        mu_c, (F0, dF) = separable_fit(columns, x, y, s, (lo[2], hi[2]), bound=(1, lo[1], hi[1]))
        return np.array([F0, dF, mu_c])
    return _covariance_fit(saturation_curve, "saturation", mu, FY, sigma, solve,
                           ["F0", "dF", "mu_c"], bounds=(lo, hi))


# --- exponents of the yield force ---------------------------------------

def _exponent_table(df, variable, system, names, speed):
    rows = yield_rows(df, speed)
    rows = rows[rows.system == system]
    out = []
    for (mu, kn, gn), g in rows.groupby(["mu", "kn", "gamman"]):
        x = (g.D + 1.0) if variable == "D" else g.h
        if x.nunique() < 2:
            continue
        f = fit_power_law(x, g.drag, pooled_drag_err(g))
        out.append({"mu": mu, "kn": kn, "gamman": gn,
                    names[0]: f["p"].value, names[0] + "_err": f["p"].err,
                    names[1]: f["A"].value, names[1] + "_err": f["A"].err,
                    "n": f.n_points, variable + "_min": g[variable].min(),
                    variable + "_max": g[variable].max(), **goodness_columns(f)})
    cols = ["mu", "kn", "gamman", names[0], names[0] + "_err", names[1], names[1] + "_err",
            "n", variable + "_min", variable + "_max"] + GOODNESS_COLUMNS
    table = pd.DataFrame(out, columns=cols)
    # An empty table keeps numeric columns, so later selections on it stay valid.
    return table.astype(float) if table.empty else table


GOODNESS_COLUMNS = ["chi2_dof", "trend_p", "rejected"]   # a fitted table's row: its fit's goodness


def goodness_columns(fit):
    """The GOODNESS_COLUMNS of a fit (NaN where not estimable; rejected as 0/1)."""
    g = fit.meta.get("goodness") or {}
    num = lambda v: np.nan if v is None else float(v)
    return {"chi2_dof": num(g.get("chi2_dof")), "trend_p": num(g.get("trend_p")),
            "rejected": float(bool(g.get("rejected")))}


def fit_phi(df, speed=None, system="I"):
    """phi_mu and f(mu) from F_Y = f(mu) (D*+1)^phi_mu, one fit per (mu, kn, gamman).

    f(mu) is the fitted prefactor: the paper draws it (Fig. 13c) but gives
    no closed form, so none is imposed here.
    """
    return _exponent_table(df, "D", system, ("phi", "f"), speed)


def fit_alpha(df, speed=None, system="II"):
    """alpha_mu and g(mu) from F_Y = g(mu) h^alpha_mu, one fit per (mu, kn, gamman)."""
    return _exponent_table(df, "h", system, ("alpha", "g"), speed)


def sum_rule(phi, alpha):
    """alpha_mu + phi_mu where both were fitted (errors added in quadrature); n_min, the fewer
    points of the two fits (NaN for the alpha averaged over speeds, which has no one fit)."""
    m = pd.merge(phi, alpha.rename(columns={"n": "n_alpha"}), on=["mu", "kn", "gamman"])
    m["sum"] = m.alpha + m.phi
    m["sum_err"] = np.hypot(m.alpha_err, m.phi_err)
    m["n_min"] = np.minimum(m["n"], m["n_alpha"]) if "n_alpha" in m.columns else np.nan
    return m[["mu", "kn", "gamman", "phi", "phi_err", "alpha", "alpha_err", "sum", "sum_err", "n_min"]]


def _lookup(table, mu, kn, gamman):
    hit = table[np.isclose(table.mu, mu) & np.isclose(table.kn, kn) & np.isclose(table.gamman, gamman)]
    return None if hit.empty else hit.iloc[0]


# --- the scaling law, Eq. 12 --------------------------------------------

LAMBDA_NAMES = {"a0": "lambda^I", "b1": "lambda_1^II", "a1": "lambda_2^II",
                "b2": "lambda_1^III", "a2": "lambda_2^III"}


@dataclass
class ScalingLaw:
    """F_drag* = h^alpha (D*+1)^phi G(Fr), with G the three-regime fit (Eq. 12).

    regimes.replicates and exponent_replicates (columns alpha, phi) are the
    same bootstrap refits row by row, so predictions keep their correlations.
    """
    mu: float
    kn: float
    gamman: float
    alpha: Param
    phi: Param
    regimes: Fit
    ranges: dict = field(default_factory=dict)   # name -> [min, max] of the data
    exponent_replicates: np.ndarray = None

    def lambdas(self):
        """The lambda coefficients of Eq. 12 (plus b0, c0 when mu = 0)."""
        p = self.regimes.params
        out = {LAMBDA_NAMES[k]: p[k] for k in LAMBDA_NAMES}
        for k in ("b0", "c0"):
            if k in p:
                out["lambda^I_" + k] = p[k]
        return out

    def predict(self, D, h, V):
        """(drag, standard error) at one point, the error being the spread of
        the law's bootstrap refits evaluated there."""
        Fr = float(froude(V, D))
        F = h ** self.alpha.value * (D + 1.0) ** self.phi.value * float(evaluate(self.regimes, [Fr])[0])
        reps = self.regimes.replicates
        if reps is None or self.exponent_replicates is None or len(reps) < 2:
            return F, math.nan
        G = evaluate_replicates(self.regimes, [Fr])[:, 0]
        a, p = self.exponent_replicates[:, 0], self.exponent_replicates[:, 1]
        return F, float(np.std(h ** a * (D + 1.0) ** p * G, ddof=1))

    def to_dict(self):
        d = {"mu": self.mu, "kn": self.kn, "gamman": self.gamman,
             "alpha": self.alpha.to_dict(), "phi": self.phi.to_dict(),
             "regimes": self.regimes.to_dict(), "ranges": self.ranges}
        if self.exponent_replicates is not None:
            d["exponent_replicates"] = self.exponent_replicates.tolist()
        return d

    @classmethod
    def from_dict(cls, d):
        ex = d.get("exponent_replicates")
        return cls(mu=float(d["mu"]), kn=float(d["kn"]), gamman=float(d["gamman"]),
                   alpha=Param.from_dict(d["alpha"]), phi=Param.from_dict(d["phi"]),
                   regimes=Fit.from_dict(d["regimes"]),
                   ranges={k: [float(v) for v in r] for k, r in d.get("ranges", {}).items()},
                   exponent_replicates=None if ex is None else np.array(ex, dtype=float))


def fit_scaling_law(df, phi, alpha, *, mu, kn=None, gamman=None, h_min=None,
                    n_boot=N_BOOT, seed=0):
    """Collapse every pull at (mu, kn, gamman) by h^alpha (D*+1)^phi and fit
    the three regimes to the collapsed drag: the lambdas of Eq. 12.

    Regime I is a0 + b0 Fr^c0 for mu = 0 (Eq. 10), a constant otherwise.
    h_min drops shallow pulls, which the paper finds do not collapse (Fig. 19).

    Errors: bootstrap refits. A point table (drag_err_within) is resampled by bed, phi and alpha
    refitted from the yield pulls in each (beds.BedDraws); else each refit draws alpha and phi
    from their errors and collapses wild-bootstrap drag with them. Weighted by pooled_drag_err.
    """
    if kn is None or gamman is None:
        kn, gamman = reference_params(df)
    p, a = _lookup(phi, mu, kn, gamman), _lookup(alpha, mu, kn, gamman)
    if p is None or a is None:
        raise ValueError(f"no phi and alpha fitted for mu={mu}, kn={kn:g}, gamman={gamman:g}")
    rows = select(df, mu=mu, kn=kn, gamman=gamman)
    if h_min:
        rows = rows[paper.at_least(rows.h, h_min)]
    # The regimes are fitted to the pulls at speed, as the paper's Figs. 5, 10 and 19: the
    # yield pulls' Fr values differ only through D and would otherwise pass for a whole
    # regime, and at mu = 0 they alone would fix a0 of a0 + b0 Fr^c0.
    moving = rows[~is_yield(rows)]
    if moving.Fr.round(6).nunique() < 8:
        raise ValueError(f"needs pulls at 8 or more Froude numbers above the yield speed "
                         f"at mu={mu:g}" + (f", h >= {h_min:g}" if h_min else "")
                         + f", has {moving.Fr.round(6).nunique()}")
    rows = moving.sort_values("Fr", kind="stable")
    lnh, lnD = np.log(rows.h.to_numpy()), np.log(rows.D.to_numpy() + 1.0)
    drag, err = rows.drag.to_numpy(), pooled_drag_err(rows).to_numpy(float)

    fitter = RegimeFitter("power" if mu == 0 else "constant")
    scale = np.exp(a.alpha * lnh + p.phi * lnD)
    x, y, w = fitter.prepare(rows.Fr, drag / scale, err / scale)
    best = fitter.best(x, y, w)
    fitted = scale * regime_curve(x, **best)
    resid = scale * fitter.noise_residuals(x, y, w, best)
    rng = np.random.default_rng(seed)
    sd = [e if np.isfinite(e) else 0.0 for e in (a.alpha_err, p.phi_err)]
    series = [f"D = {D:g}, h = {h:.1f}" for D, h in zip(rows.D, rows.h)]   # the goodness's series
    beds = BedDraws.of(df, rows, (mu, kn, gamman), (p, a), fitter, x, y, w, best) if n_boot > 0 else None
    reps, expo = [], []
    for _ in range(n_boot):
        if beds is None:
            ab, pb = a.alpha + sd[0] * rng.standard_normal(), p.phi + sd[1] * rng.standard_normal()
            dragb = fitted + resid * rng.choice([-1.0, 1.0], size=len(x))
        else:
            dev, pb, ab = beds.draw(rng)
            dragb = fitted * np.exp(dev)
        sb = np.exp(ab * lnh + pb * lnD)
        reps.append(fitter.fit(x, dragb / sb, w * (sb / scale) ** 2))
        expo.append((ab, pb))
    how = (f"{n_boot} refits resampling the beds (a shared factor per bed; the yield pulls' phi, alpha refitted)"
           if beds is not None else f"{n_boot} wild-bootstrap refits with alpha, phi drawn from their errors")
    reg = fitter.result(x, best, reps, how + f" (seed {seed})", y, w, series if len(series) == len(x) else None)
    reg.meta.update(collapsed=True, mu=mu, h_min=float(h_min or 0.0),
                    errors_from="points" if beds is not None and not beds.scaled else "residuals")
    keep = [r is not None for r in reps]
    ranges = {"D": [float(p.D_min), float(p.D_max)], "h": [max(float(a.h_min), float(h_min or 0.0)), float(a.h_max)],
              "Fr": [float(rows.Fr.min()), float(rows.Fr.max())]}
    return ScalingLaw(mu=float(mu), kn=float(kn), gamman=float(gamman),
                      alpha=Param(float(a.alpha), float(a.alpha_err)),
                      phi=Param(float(p.phi), float(p.phi_err)), regimes=reg, ranges=ranges,
                      exponent_replicates=np.array(expo)[keep] if reg.replicates is not None else None)
