"""The depth law read as the paper reads it (Secs. III G-H, Figs. 17-19), on the deep intruders
(h >= h_min, the paper's 45 d) and on every depth, each apart, so that a verdict says which depths
it holds for. Per system II series (D, mu, K_n, gamma_n):

  alpha_yield   F_Y = g h^alpha over the yield pulls (Fig. 17)
  alpha_drag    the drag's depth exponent at each of the paper's speeds, averaged over them
                (Fig. 18a; analysis.fits.alpha_drag, its error with the beds' correlations)
  collapse      F(h, V) = G_V h^alpha, one alpha for every speed: Fig. 19's collapse at one D (F/h^alpha
                against Fr on one curve), its chi^2 and p the collapse's goodness
  alpha_by_speed  an alpha per speed against one (nested: delta chi^2 on speeds - 1 dof): whether
                the exponent depends on the speed, apart from a bend in h that the collapse's
                whole-model chi^2 also sees
  sum_yield, sum_drag   alpha + phi_mu on the deep depths, phi_mu from a system I study at the same
                contact law (its fit file's phi table), with the sum's degrees of freedom (Welch-
                Satterthwaite over alpha's nu and phi's, report.verdicts.component_dof) and the
                verdict against 3 at them: below
                2 dof a Student-t interval spans more than ±4.3 errors, and the test cannot fail
  shallow_yield, shallow_drag   the depths below h_min against the deep law carried down: chi^2 of
                their departures with the deep fit's own uncertainty, and each depth's relative
                departure (the paper, Sec. III H: "the data for shallow regions (h/d <~ 25) do not
                satisfy the scaling")

Errors, in log space: each point's within-run error independent, and its beds' shared part
(the between-bed variance pooled over every depth of the series and kind, point_errors) fully
correlated between the speeds pulled through the same beds (bed_labels), as alpha_drag counts
them. A bed that reads high reads high at every speed, which looks like a depth leaving the power
law. Counting all of the between-bed variance as shared is the lenient side for the shallow test
(its departures move every speed of a depth together) but not for the collapse: speed-to-speed
differences cancel a shared shift, so if a bed's shift is only partly shared (analysis.core
.bed_shift measured about half at box40-deep) the collapse's chi^2 overstates how far the speeds
disagree, and it may reject a true law more often than its size says. That pooled variance
rests on few degrees of freedom (two beds at each depth), so an exponent is judged by Student's t
at the beds' dof of its own rows (`nu_alpha`), and a chi^2 test by F(n, nu), nu Satterthwaite's,
conservative where the within-run part dominates. With the chi^2 law instead, two beds per depth
made 5 % tests reject a true law 11-14 % of the time and the exponents' z an RMS of 1.2-1.5
(tests/python/test_deep_law.py). Rows are refused by name where a drag or its error is not a
positive number. The `dof` column is the error's dof for exponents and sums (nu_alpha, or the
sum's Welch-Satterthwaite), and the F test's denominator nu for the shallow and alpha_by_speed rows; `n` is the
points (for a sum, phi's).
"""
import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import stats

from ..core import paper
from ..core.point_errors import pooled_drag_err
from ..core.result import Param
from ..core.table import bed_labels, is_yield, write_csv, write_text_atomic
from ..fits.alpha_drag import ALPHA_SPEEDS, SPEED_MATCH, fit_alpha_drag
from ..report.verdicts import MIN_DOF, component_dof, verdict

SERIES = ["D", "mu", "kn", "gamman"]
COLUMNS = SERIES + ["quantity", "depths", "h_lo", "h_hi", "n", "value", "err", "chi2", "dof", "p",
                    "verdict", "note"]
# The quantities of a deep_law.csv row, in the order the table lists them.
QUANTITIES = ("alpha_yield", "sum_yield", "alpha_drag", "sum_drag", "collapse", "alpha_by_speed", "shallow_yield",
              "shallow_drag")


@dataclass
class DepthFit:
    """F = G_k h^alpha by generalised least squares in log space, one G_k per group k (a speed;
    the yield pulls are one group): beta = (ln G_k..., alpha), its covariance, and the fit's
    chi^2 at dof = points - groups - 1."""
    keys: list
    beta: np.ndarray
    cov: np.ndarray
    chi2: float
    dof: int
    nu: float = math.inf         # the points' errors' effective dof (tests: chi2_p)
    nu_alpha: float = math.inf   # alpha's error's (its variance's bed part estimated on nu_bed)

    @property
    def alpha(self):
        return Param(float(self.beta[-1]), float(math.sqrt(self.cov[-1, -1])))

    @property
    def p(self):
        return chi2_p(self.chi2, self.dof, self.nu)

    def design(self, group, h):
        return np.column_stack([(np.asarray(group) == k).astype(float) for k in self.keys] + [np.log(h)])


def bed_dof(pool):
    """Degrees of freedom of the between-bed variance pooled over `pool`: its beds less one per
    set of points pulled through the same beds (bed_labels, n_beds)."""
    if "n_beds" not in pool.columns or pool.empty:
        return 0.0
    k = pd.DataFrame({"label": bed_labels(pool).to_numpy(), "k": pool["n_beds"].to_numpy(float)})
    return float((k.groupby("label").k.max() - 1).clip(lower=0).sum())


def effective_dof(bed, nu_bed, total=None):
    """The dof an error rests on when its between-bed part `bed` (a variance) was estimated from
    the beds' scatter on nu_bed dof; inf when the beds add nothing. For an exponent's error (total
    None): nu_bed, not inflated by the within-run part, which is in every pair of beds' scatter
    too (Satterthwaite's nu_bed (total / bed)^2 gave 95 % intervals that held the truth 91 % of the
    time on synthetic rungs of two beds at five depths). For a chi^2 test of several points,
    Satterthwaite's (at nu_bed itself, F(n, 3) could not see a 25 % shallow excess), inf when the
    beds add nothing."""
    if nu_bed <= 0:
        return math.inf
    if total is None:
        return float(nu_bed)   # also when the pooled bed part came out nil: that too is an estimate
    return math.inf if not bed > 0 else float(nu_bed) * (total / bed) ** 2


def log_covariance(rows, pool=None):
    """(ln F, C, C_bed, nu_bed): the rows' log drags; their covariance, each point's relative
    variance (within-run and between-bed, pooled over `pool`, default the rows) on the diagonal
    and its beds' shared relative deviation b_i b_j between points of the same beds; C's bed part;
    and the dof that bed part is taken to rest on: bed_dof of the rows themselves, not of the pool
    (conservative: on synthetic rungs of two beds at five depths, a deep law's 95 % interval held
    the truth 91-92 % of the time at the pool's dof, and more than 95 % at the rows' own)."""
    pool = rows if pool is None else pool
    F = rows.drag.to_numpy(float)
    total = (np.asarray(pooled_drag_err(rows, pool), float) / F) ** 2
    within = (rows["drag_err_within"].to_numpy(float) / F) ** 2 if "drag_err_within" in rows.columns else total
    b2 = np.clip(total - within, 0.0, None)
    labels = bed_labels(rows).to_numpy()
    b = np.sqrt(b2)
    CB = np.outer(b, b) * (labels[:, None] == labels[None, :])
    C = CB.copy()
    C[np.diag_indices_from(C)] = total
    return np.log(F), C, CB, bed_dof(rows)


def chi2_p(chi2, n, nu=math.inf):
    """p of a chi^2 on n dof whose covariance was estimated on nu dof: F(n, nu) of chi^2 / n
    (conservative when part of the variance is known), the chi^2 law at nu = inf."""
    if not n > 0:
        return math.nan
    return float(stats.chi2.sf(chi2, n) if math.isinf(nu) else stats.f.sf(chi2 / n, n, nu))


def gls(X, y, C):
    """Generalised least squares of y (covariance C) on X: (beta, its covariance, chi^2, the
    whitener W with W C W' = 1, W X)."""
    W = np.linalg.inv(np.linalg.cholesky(C))
    Xw, yw = W @ X, W @ y
    beta = np.linalg.lstsq(Xw, yw, rcond=None)[0]
    r = yw - Xw @ beta
    return beta, np.linalg.inv(Xw.T @ Xw), float(r @ r), W, Xw


def fit_depth_law(y, C, group, h, CB=None, nu_bed=math.inf):
    """DepthFit of ln F = y (covariance C, of which CB is the beds' part, estimated on nu_bed dof)
    on ln G_group + alpha ln h; None with fewer than two depths or no points."""
    group, h = np.asarray(group), np.asarray(h, float)
    if len(y) == 0 or len(np.unique(np.round(h, 6))) < 2:
        return None
    keys = sorted(set(group.tolist()))
    fit = DepthFit(keys, None, None, math.nan, len(y) - len(keys) - 1)
    X = fit.design(group, h)
    if np.linalg.matrix_rank(X) < X.shape[1]:   # no group spans two depths: alpha not identified
        return None
    fit.beta, fit.cov, fit.chi2, W, Xw = gls(X, y, C)
    if CB is not None:
        g = (fit.cov @ Xw.T @ W)[-1]   # alpha as a weighted sum of the y
        fit.nu_alpha = effective_dof(float(g @ CB @ g), nu_bed)
        fit.nu = effective_dof(float(np.trace(CB)), nu_bed, float(np.trace(C)))
    return fit


def speed_alphas(y, C, group, h):
    """ln F = ln G_k + alpha_k ln h, an exponent per group k, by the same GLS as fit_depth_law:
    ({k: Param(alpha_k)}, chi^2); None unless every group spans two depths."""
    group, h = np.asarray(group), np.asarray(h, float)
    keys = sorted(set(group.tolist()))
    on = [(group == k).astype(float) for k in keys]
    X = np.column_stack(on + [g * np.log(h) for g in on])
    if len(y) == 0 or np.linalg.matrix_rank(X) < X.shape[1]:
        return None
    beta, cov, chi2, _, _ = gls(X, y, C)
    n = len(keys)
    return {k: Param(float(beta[n + i]), float(math.sqrt(cov[n + i, n + i]))) for i, k in enumerate(keys)}, chi2


def _speed_alpha_row(key, depths, hs, m_fit, y, C, group, h):
    """Does alpha depend on the speed? One alpha for every speed (the collapse's fit, m_fit)
    against an alpha per speed, nested: delta chi^2 on (speeds - 1) dof, p by F(speeds - 1, nu) at
    the collapse's points' nu. It isolates the speed dependence from the collapse's whole-model
    chi^2 (which also sees a bend in h); on two depths the free fit is exact and the two coincide."""
    free = speed_alphas(y, C, group, h)
    if free is None or len(free[0]) < 2:
        return None
    alphas, chi2_free = free
    q = len(alphas) - 1
    delta = max(m_fit.chi2 - chi2_free, 0.0)
    p = chi2_p(delta, q, m_fit.nu)
    each = ", ".join(f"V {k:g}: {a}" for k, a in alphas.items())
    return _row(key, "alpha_by_speed", depths, hs, len(hs), chi2=delta, dof=m_fit.nu, p=p,
                verdict_text="alpha depends on the speed" if p < 0.05 else "not told apart from one alpha",
                note=f"an alpha per speed ({each}) against one: delta chi^2 {delta:.1f} for {q} dof, "
                     f"p by F({q}, {m_fit.nu:.3g})")


def departures(fit, y, C, group, h):
    """The points (y, C) against the law `fit` carried to them, points independent of the fit's
    (other beds): (relative departures exp(r) - 1, their z, chi^2 of all with the fit's own
    uncertainty, dof = points)."""
    X = fit.design(group, h)
    r = y - X @ fit.beta
    V = C + X @ fit.cov @ X.T
    chi2 = float(r @ np.linalg.solve(V, r))
    return np.expm1(r), r / np.sqrt(np.diag(V)), chi2, len(r)


def speed_groups(rows, speeds=ALPHA_SPEEDS, match=SPEED_MATCH):
    """Each row's target speed: the nearest of `speeds` within `match` (relative, as alpha_drag
    matches), NaN when none is. Table speeds that share a target share its G_V."""
    V = rows.V.to_numpy(float)
    targets = np.asarray(speeds, float)
    if not len(V) or not len(targets):
        return np.full(len(V), np.nan)
    rel = np.abs(V[:, None] / targets[None, :] - 1.0)
    best = np.argmin(rel, axis=1)
    return np.where(rel[np.arange(len(V)), best] <= match, targets[best], np.nan)


def _row(key, quantity, depths, h, n, value=math.nan, err=math.nan, chi2=math.nan, dof=math.nan,
         p=math.nan, verdict_text="", note=""):
    h = np.asarray(h, float)
    return dict(zip(SERIES, key), quantity=quantity, depths=depths, h_lo=float(h.min()) if h.size else math.nan,
                h_hi=float(h.max()) if h.size else math.nan, n=n, value=value, err=err, chi2=chi2, dof=dof,
                p=p, verdict=verdict_text, note=note)


def _alpha_word(mu, alpha, nu):
    """The verdict of an alpha (Param) at mu = 0 against the paper's alpha_0 (Sec. III H), Student's
    t at its errors' nu; the paper gives no number for mu > 0 (its sum rule does: sum_*)."""
    if mu != 0 or not math.isfinite(alpha.value):
        return ""
    return verdict(alpha, paper.ALPHA_0, dof=None if math.isinf(nu) else nu)[0]


def _sum_row(key, label, alpha, nu, phi, depths, h):
    """The sum rule at key's (mu, kn, gamman): alpha (Param, its errors' dof nu) plus phi_mu from
    the phi table `phi` (fits.fit_phi's columns), the sum's dof by Welch-Satterthwaite (phi's by
    report.verdicts.component_dof: its points less two unless its errors are its points'), and the
    verdict against 3. None without phi at that contact law."""
    if phi is None:
        return None
    hit = phi[np.isclose(phi.mu, key[1]) & np.isclose(phi.kn, key[2]) & np.isclose(phi.gamman, key[3])]
    if hit.empty:
        return None
    f = hit.iloc[0]
    parts = ((alpha.err ** 2, nu), (float(f.phi_err) ** 2, component_dof(f, phi)))
    if any(n < 1 for _, n in parts):       # a part fitted on as many points as parameters
        dof = min(n for _, n in parts)
    else:
        den = sum(v * v / n for v, n in parts if math.isfinite(n))
        dof = math.inf if den == 0 else sum(v for v, _ in parts) ** 2 / den
    total = Param(alpha.value + float(f.phi), math.hypot(alpha.err, float(f.phi_err)))
    # A phi_mu whose own fit the data reject (fits.goodness) carries no verdict into the sum.
    rejected = (f"model rejected (the phi_mu fit: chi^2/dof {float(f.chi2_dof):.2g})"
                if "rejected" in f and float(f.rejected or 0) > 0 else "")
    word, why = verdict(total, paper.SUM_RULE, dof=None if math.isinf(dof) else dof, rejected=rejected)
    if dof < MIN_DOF:
        why += "; the test cannot fail here"
    return _row(key, label, depths, h, int(f.n), total.value, total.err, dof=dof, verdict_text=word,
                note=f"alpha {alpha} + phi {float(f.phi):.3f} ± {float(f.phi_err):.3f} "
                     f"(D {f.D_min:g}-{f.D_max:g}): {why}")


def _deep(h, h_min):
    """The depths (a Series) at h >= h_min (paper.at_least: within its slack), all without h_min."""
    return h == h if h_min is None else paper.at_least(h, h_min)


def _law(rows, pool, group, h_min=None):
    """DepthFit of rows (those at h >= h_min when given) with errors pooled over `pool`."""
    keep = _deep(rows.h, h_min).to_numpy()
    if not keep.any():
        return None
    y, C, CB, nu_bed = log_covariance(rows[keep], pool)
    return fit_depth_law(y, C, np.asarray(group)[keep], rows.h.to_numpy(float)[keep], CB, nu_bed)


def read_deep_law(df, h_min=paper.DEEP_H, speeds=ALPHA_SPEEDS, phi=None, system="II"):
    """Every quantity of the module's doc, per system II series of the point table df: a table of
    COLUMNS. phi: a phi table (fits.fit_phi's columns) for the sum rule, or None."""
    rows = df[df.system == system]
    if rows.empty:
        raise ValueError(f"the table has no system {system} pulls: the depth law needs pulls at several "
                         f"depths h (config: a sweep of system {system} with a list under `depth`)")
    bad = ~(rows.drag > 0) | ~(rows.drag_err > 0)
    if "drag_err_within" in rows.columns:
        bad |= ~(rows.drag_err_within >= 0)
    if bad.any():
        raise ValueError(f"{int(bad.sum())} system {system} row(s) have no positive drag or error "
                         f"(h = {', '.join(f'{h:.3g}' for h in rows.h[bad][:5])}): the depth law is read in "
                         f"log space with each point's error; leave those pulls out of the table")
    out = []
    for key, g in rows.groupby(SERIES):
        yld, moving = g[is_yield(g)], g[~is_yield(g)]
        moving = moving[np.isfinite(speed_groups(moving, speeds))]
        group = speed_groups(moving, speeds)
        for depths, cut in ((f"h >= {h_min:g}", h_min), ("all", None)):
            y_fit = _law(yld, yld, np.zeros(len(yld)), cut)
            if y_fit is not None:
                hs = yld.h[_deep(yld.h, cut)]
                out.append(_row(key, "alpha_yield", depths, hs, len(hs), y_fit.alpha.value, y_fit.alpha.err,
                                y_fit.chi2, y_fit.nu_alpha, y_fit.p, _alpha_word(key[1], y_fit.alpha, y_fit.nu_alpha),
                                note=f"F_Y = g h^alpha (Fig. 17); chi^2 {y_fit.chi2:.1f} for {y_fit.dof} dof; "
                                     f"dof: its error's"))
                if cut is not None:
                    out.append(_sum_row(key, "sum_yield", y_fit.alpha, y_fit.nu_alpha, phi, depths, hs))
            m_fit = _law(moving, moving, group, cut)
            if m_fit is None:
                continue
            hs = moving.h[_deep(moving.h, cut)]
            a_drag = fit_alpha_drag(moving[_deep(moving.h, cut)], speeds=speeds, system=system)[0]
            if len(a_drag):
                a = a_drag.iloc[0]
                mean = Param(float(a.alpha), float(a.alpha_err))
                out.append(_row(key, "alpha_drag", depths, hs, int(a.n_speeds), mean.value, mean.err,
                                dof=m_fit.nu_alpha, verdict_text=_alpha_word(key[1], mean, m_fit.nu_alpha),
                                note=f"averaged over V = {a.speeds} (Fig. 18a); spread over speeds {a.spread:.3f}; "
                                     f"dof: the collapse's alpha's"))
                if cut is not None:
                    out.append(_sum_row(key, "sum_drag", mean, m_fit.nu_alpha, phi, depths, hs))
            # The chi^2 is the whole model's: one alpha for every speed and a power law in h.
            word = ("" if not m_fit.dof > 0 else "G_V h^alpha rejected (one alpha, one power law)" if m_fit.p < 0.05
                    else "not told apart from one alpha for every speed")
            out.append(_row(key, "collapse", depths, hs, len(hs), m_fit.alpha.value, m_fit.alpha.err,
                            m_fit.chi2, m_fit.nu_alpha, m_fit.p, word,
                            note=f"one alpha for {len(m_fit.keys)} speeds (Fig. 19 at one D): chi^2 {m_fit.chi2:.1f} "
                                 f"for {m_fit.dof} dof, p by F({m_fit.dof}, {m_fit.nu:.3g})"))
            at = _deep(moving.h, cut).to_numpy()
            y, C, _, _ = log_covariance(moving[at], moving)
            out.append(_speed_alpha_row(key, depths, hs, m_fit, y, C, group[at], moving.h.to_numpy(float)[at]))
        out += _shallow_rows(key, yld, moving, h_min, speeds)
    return pd.DataFrame([r for r in out if r is not None], columns=COLUMNS)


def _shallow_rows(key, yld, moving, h_min, speeds):
    """The shallow depths against the deep law, for the yield force and for the drag at speed."""
    out = []
    for name, t, group in (("shallow_yield", yld, np.zeros(len(yld))),
                           ("shallow_drag", moving, speed_groups(moving, speeds))):
        h = t.h.to_numpy(float)
        shallow = ~paper.at_least(h, h_min)
        fit = _law(t, t, group, h_min)
        if fit is None or not shallow.any():
            continue
        part = shallow & np.isin(group, fit.keys)
        if not part.any():
            continue
        y, C, CB, nu_bed = log_covariance(t[part], t)
        hs = h[part]
        rel, z, chi2, n = departures(fit, y, C, group[part], hs)
        nu = effective_dof(float(np.trace(CB)), nu_bed, float(np.trace(C)))
        depth = np.round(hs, 3)
        each = "; ".join(f"h {v:.3g}: {100 * np.mean(rel[depth == v]):+.1f} % (z {np.mean(z[depth == v]):+.1f})"
                         for v in np.unique(depth))
        p = chi2_p(chi2, n, nu)
        out.append(_row(key, name, f"h < {h_min:g}", hs, n, chi2=chi2, dof=nu, p=p,
                        verdict_text="leaves the deep law" if p < 0.05 else "not told apart from the deep law",
                        note=f"mean departure from the law of h >= {h_min:g} (alpha {fit.alpha}): {each}; "
                             f"chi^2 {chi2:.1f} for {n} points, p by F({n}, {nu:.3g})"))
    return out


def phi_from_fits(path):
    """The phi_mu table of a fit file (fits.fit_phi's columns, its JSON nulls as NaN); None when it
    has none. FitFileError for a file that is not a fit file."""
    from ..fits.fit_file import load_fits

    phi = load_fits(path).tables.get("phi")
    if phi is None or not len(phi):
        return None
    return phi.apply(lambda c: pd.to_numeric(c, errors="coerce"))


def summary_markdown(table, h_min):
    """The table in words: one line per quantity and depth range."""
    lines = [f"# The depth law on deep intruders (h >= {h_min:g} d) and on every depth", "",
             "| D | mu | K_n | quantity | depths | value | dof | p | verdict | note |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in table.itertuples():
        value = ("" if not math.isfinite(r.value)
                 else f"{r.value:.3f} ± {r.err:.3f}" if math.isfinite(r.err) else f"{r.value:.3f}")
        lines.append(f"| {r.D:g} | {r.mu:g} | {r.kn:.3g} | {r.quantity} | {r.depths} ({r.h_lo:.3g}-{r.h_hi:.3g} d) | "
                     f"{value} | {'' if not math.isfinite(r.dof) else f'{r.dof:.3g}'} | "
                     f"{'' if not math.isfinite(r.p) else f'{r.p:.3g}'} | {r.verdict} | {r.note} |")
    lines += ["", "Errors count each point's beds' scatter as shared by every speed pulled through them: the "
              "lenient side for the shallow test, the strict side for the collapse (analysis.deep_law.deep_law)."]
    return "\n".join(lines) + "\n"


def load_deep_law(path):
    """A deep_law.csv as write_deep_law wrote it; a clear error when it is not one."""
    try:
        table = pd.read_csv(path)
    except (OSError, pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: not a readable deep_law.csv ({exc}); write it again: "
                         "granudrag-analysis deep-law TABLE --out DIR") from None
    missing = sorted(set(COLUMNS) - set(table.columns))
    if missing:
        raise ValueError(f"{path}: not a deep_law.csv (no column {', '.join(missing)}); write it again: "
                         "granudrag-analysis deep-law TABLE --out DIR")
    return table


def write_deep_law(df, out_dir, h_min=paper.DEEP_H, speeds=ALPHA_SPEEDS, phi=None):
    """deep_law.csv and deep_law.md in out_dir; returns (table, csv path)."""
    from pathlib import Path

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    table = read_deep_law(df, h_min=h_min, speeds=speeds, phi=phi)
    write_csv(table, out / "deep_law.csv")
    write_text_atomic(out / "deep_law.md", summary_markdown(table, h_min))
    return table, out / "deep_law.csv"
