"""The figures of the yield force and the scaling laws fitted to it (Figs. 12-15, 17-19): F_Y
against μ, D and h with their collapse, the exponents φ_μ and α_μ and the sum rule, and the
drag scaled by (D*+1)^φ_μ or h^α_μ."""
import matplotlib.pyplot as plt
import numpy as np

from ..core import paper
from ..core.table import pooled_drag_err, reference_params, select, yield_rows
from ..fits.fits import fit_alpha, fit_phi, fit_saturation
from .figures_drawing import (
    DP1_LABEL,
    FR_LABEL,
    FY_LABEL,
    H_LABEL,
    MARKERS,
    MU_LABEL,
    NoData,
    _curve,
    _errorbars,
    _moving,
    _need,
    _plain_log,
    _record,
    _reference,
    _save,
    _sci,
    _subplots,
)


def _yield_I(df):
    return _need(yield_rows(_reference(df)).query("system == 'I'"), "yield pulls of system I")


def fig12_yield_vs_mu(df, outdir, saturation=None):
    """Fig. 12: yield force vs mu per D; dashed: saturating fits (D -> Fit)."""
    rows = _yield_I(df)
    fig, ax = _subplots(figsize=(5, 3.8))
    for i, (D, g) in enumerate(rows.groupby("D")):
        err = np.asarray(pooled_drag_err(g, rows), float)   # as fitset.run_fits weighs them
        color = _errorbars(ax, g.mu, g.drag, err, i, f"$D = {D:g}d$")
        fit = (saturation or {}).get(D)
        if fit is None and g.mu.nunique() >= 4:
            try:
                fit = fit_saturation(g.mu, g.drag, err)
            except (ValueError, RuntimeError):
                fit = None
        if fit is not None:
            _curve(ax, fit, 0.0, g.mu.max(), color=color, ls="--", lw=0.8)
    ax.set_xlabel(MU_LABEL)
    ax.set_ylabel(FY_LABEL)
    ax.legend(fontsize=7)
    return _save(fig, outdir, "fig12_yield_vs_mu")


def _scaling_panels(rows, xcol, xlabel, table, expo, pref, name, outdir, logx_b):
    """Figs. 13 and 17: (a) log-log F_Y vs x per mu, (b) collapse, (c) prefactor vs mu. The
    yield forces carry the errors their power-law fit was weighted by (pooled_drag_err, as
    fits._exponent_table)."""
    fig, axes = _subplots(1, 3, figsize=(14, 4))
    for i, (mu, g) in enumerate(rows.groupby("mu")):
        t = table[np.isclose(table.mu, mu)]
        x = g[xcol] + (1.0 if xcol == "D" else 0.0)
        err = np.asarray(pooled_drag_err(g), float)
        color = _errorbars(axes[0], x, g.drag, err, i, rf"$\mu = {mu:g}$")
        if len(t):
            r = t.iloc[0]
            xs = np.geomspace(x.min(), x.max(), 50)
            axes[0].plot(xs, r[pref] * xs ** r[expo], color=color, lw=0.8)
            _record(axes[0], f"fit mu = {mu:g}", xs, r[pref] * xs ** r[expo], kind="curve")
            _errorbars(axes[1], x, g.drag, err, i, None, scale=r[pref] * x ** r[expo],
                       series=f"mu = {mu:g}")
    _plain_log(axes[0], "x")
    axes[0].set(yscale="log", xlabel=xlabel, ylabel=FY_LABEL)
    axes[0].legend(fontsize=7)
    axes[1].axhline(1.0, color="k", lw=0.8)
    axes[1].set_xlabel(xlabel)
    if logx_b:
        _plain_log(axes[1], "x")
    sym = pref
    base = "(D^*+1)" if xcol == "D" else "{h^*}"
    axes[1].set_ylabel(f"$F^*_Y / [{sym}(\\mu)\\,{base}^{{\\{expo}_\\mu}}]$")
    axes[2].errorbar(table.mu, table[pref], yerr=table[pref + "_err"].fillna(0), fmt="o", capsize=2)
    _record(axes[2], f"{pref}(mu)", table.mu, table[pref], table[pref + "_err"])
    axes[2].set(xlabel=MU_LABEL, ylabel=rf"${sym}(\mu)$")
    for ax, tag in zip(axes, "abc"):
        ax.set_title(f"({tag})", loc="left")
    return _save(fig, outdir, name)


def fig13_yield_vs_D(df, outdir, phi=None):
    """Fig. 13: F_Y vs D*+1 (log-log), collapse by f(mu)(D*+1)^phi_mu, f(mu)."""
    rows = _yield_I(df)
    phi = fit_phi(rows) if phi is None else phi
    kn, gn = reference_params(df)
    phi = phi[np.isclose(phi.kn, kn) & np.isclose(phi.gamman, gn)]
    return _scaling_panels(rows, "D", DP1_LABEL, phi, "phi", "f", "fig13_yield_vs_D", outdir, True)


def fig17_yield_vs_h(df, outdir, alpha=None):
    """Fig. 17: F_Y vs h (log-log), collapse by g(mu) h^alpha_mu, g(mu)."""
    rows = _need(yield_rows(_reference(df)).query("system == 'II'"), "yield pulls of system II")
    alpha = fit_alpha(rows) if alpha is None else alpha
    kn, gn = reference_params(df)
    alpha = alpha[np.isclose(alpha.kn, kn) & np.isclose(alpha.gamman, gn)]
    return _scaling_panels(rows, "h", H_LABEL, alpha, "alpha", "g", "fig17_yield_vs_h", outdir, False)


def _by_kn(ax, table, col, err):
    for i, (kn, t) in enumerate(table.groupby("kn")):
        t = t.sort_values("mu")
        _record(ax, f"K_n = {kn:.3g}", t.mu, t[col], t[err], kind="line")
        ax.errorbar(t.mu, t[col], yerr=t[err].fillna(0), fmt=MARKERS[i % len(MARKERS)] + "-",
                    mfc="none", capsize=2, ms=4, label=rf"$K_n = {_sci(kn)}$")
    ax.set_xlabel(MU_LABEL)
    ax.legend(fontsize=7)


def fig14_phi_vs_mu(df, outdir, phi=None):
    """Fig. 14: phi_mu vs mu for each K_n (the paper finds it K_n-independent)."""
    phi = fit_phi(df) if phi is None else phi
    if phi.empty:
        raise NoData("no phi_mu fitted (system I yield pulls at two or more D)")
    fig, ax = _subplots(figsize=(5, 3.8))
    _by_kn(ax, phi, "phi", "phi_err")
    ax.axhline(paper.PHI_0, color="0.5", ls=":", lw=0.8)
    ax.set_ylabel(r"$\phi_\mu$")
    return _save(fig, outdir, "fig14_phi_vs_mu")


def fig18_alpha(df, outdir, phi=None, alpha=None, alpha_drag=None, speeds=None):
    """Fig. 18: (a) alpha_mu vs mu per K_n: the paper's, the drag's depth exponent at the
    speeds averaged (alpha_drag), with Fig. 17's from the yield force beside it (open);
    (b) the sum rule alpha_mu + phi_mu ~ 3 with the averaged alpha_mu (with the yield
    force's when the study has no drag at speed over depth)."""
    from ..fits.alpha_drag import ALPHA_SPEEDS, fit_alpha_drag
    from ..fits.fits import sum_rule
    phi = fit_phi(df) if phi is None else phi
    alpha = fit_alpha(df) if alpha is None else alpha
    if alpha_drag is None:
        alpha_drag = fit_alpha_drag(df, speeds=speeds or ALPHA_SPEEDS)[0]
    if alpha.empty and alpha_drag.empty:
        raise NoData("no alpha_mu fitted (system II pulls at two or more h)")
    fig, axes = _subplots(1, 2, figsize=(10, 3.8))
    ax = axes[0]
    for i, (kn, t) in enumerate(alpha_drag.groupby("kn")):
        t = t.sort_values("mu")
        _record(ax, f"drag, averaged over speeds, K_n = {kn:.3g}", t.mu, t.alpha, t.alpha_err, kind="line")
        ax.errorbar(t.mu, t.alpha, yerr=t.alpha_err.fillna(0), fmt=MARKERS[i % len(MARKERS)] + "-", ms=4,
                    capsize=2, label=rf"$K_n = {_sci(kn)}$ (drag at speed)")
    for i, (kn, t) in enumerate(alpha.groupby("kn")):
        t = t.sort_values("mu")
        _record(ax, f"yield force, K_n = {kn:.3g}", t.mu, t.alpha, t.alpha_err)
        ax.errorbar(t.mu, t.alpha, yerr=t.alpha_err.fillna(0), fmt=MARKERS[i % len(MARKERS)], mfc="none",
                    ms=4, capsize=2, color="0.5", label=rf"$K_n = {_sci(kn)}$ (yield force, Fig. 17)")
    ax.set(xlabel=MU_LABEL, ylabel=r"$\alpha_\mu$")
    ax.legend(fontsize=7)
    use, how = (alpha_drag, "averaged over speeds") if len(alpha_drag) else (alpha, "from the yield force")
    s = sum_rule(phi, use)
    if len(s):
        _by_kn(axes[1], s, "sum", "sum_err")
    axes[1].axhline(paper.SUM_RULE, color="k", ls="--", lw=0.8)
    axes[1].set_ylabel(rf"$\alpha_\mu + \phi_\mu$ ($\alpha_\mu$ {how})")
    for ax, tag in zip(axes, "ab"):
        ax.set_title(f"({tag})", loc="left")
    return _save(fig, outdir, "fig18_alpha_and_sum_rule")


def fig15_scaled_drag_D(df, outdir, phi=None, mus=(0.5, 0.0)):
    """Fig. 15: drag / (D*+1)^phi_mu vs Fr per D, (a) mu = 0.5, (b) mu = 0."""
    ref = _reference(df)
    phi = fit_phi(ref) if phi is None else phi
    kn, gn = reference_params(df)
    fig, axes = _subplots(1, len(mus), figsize=(5.2 * len(mus), 4), squeeze=False)
    drawn = 0
    for ax, mu, tag in zip(axes[0], mus, "ab"):
        rows = _moving(select(ref, mu=mu, system="I"), "D")
        t = phi[np.isclose(phi.mu, mu) & np.isclose(phi.kn, kn) & np.isclose(phi.gamman, gn)]
        ax.set_title(rf"({tag}) $\mu = {mu:g}$", loc="left")
        ax.set_xlabel(FR_LABEL)
        if rows.empty or t.empty:
            ax.text(0.5, 0.5, "no data", transform=ax.transAxes, ha="center")
            continue
        p = t.iloc[0].phi
        for i, (D, g) in enumerate(rows.groupby("D")):
            _errorbars(ax, g.Fr, g.drag, g.drag_err, i, f"$D = {D:g}d$", scale=(D + 1) ** p)
        ax.set_ylabel(rf"$F^*_{{\rm drag}}/(D^*+1)^{{\phi_\mu}}$, $\phi_\mu = {p:.2f}$")
        ax.legend(fontsize=7)
        drawn += 1
    if not drawn:
        plt.close(fig)
        raise NoData("no system I pulls with a fitted phi_mu")
    return _save(fig, outdir, "fig15_scaled_drag_vs_Fr_D")


def fig19_scaled_drag_h(df, outdir, alpha=None, mu=0.5, h_min=None):
    """Fig. 19: drag / h^alpha_mu vs Fr per depth (the paper shows h >= 45d)."""
    rows = _moving(select(_reference(df), mu=mu, system="II"), "h")
    if h_min is not None:
        rows = rows[paper.at_least(rows.h, h_min)]
    rows = _need(rows, f"system II at mu = {mu:g}")
    alpha = fit_alpha(_reference(df)) if alpha is None else alpha
    kn, gn = reference_params(df)
    t = alpha[np.isclose(alpha.mu, mu) & np.isclose(alpha.kn, kn) & np.isclose(alpha.gamman, gn)]
    if t.empty:
        raise NoData(f"no alpha_mu fitted for mu = {mu:g}")
    a = t.iloc[0].alpha
    fig, ax = _subplots(figsize=(5, 3.8))
    for i, (h, g) in enumerate(rows.groupby("h")):
        _errorbars(ax, g.Fr, g.drag, g.drag_err, i, f"$h = {h:.3g}d$", scale=h ** a)
    ax.set_xlabel(FR_LABEL)
    ax.set_ylabel(rf"$F^*_{{\rm drag}}/h^{{*\alpha_\mu}}$, $\alpha_\mu = {a:.2f}$")
    ax.legend(fontsize=7, title=rf"$\mu = {mu:g}$", title_fontsize=8)
    return _save(fig, outdir, "fig19_scaled_drag_vs_Fr_h")
