"""One function per figure of the paper; each writes <name>.png and <name>.pdf.

Every function takes the pull table (or arrays) and an output directory and
returns the paths it wrote. Fits can be passed in (the report fits once and
draws many times); when they are not, the function fits what it draws
without bootstrap. Data of the study's reference contact law (the (K_n,
gamma_n) pair with most pulls) are drawn unless a figure is about varying
it (Figs. 14, 18, 20). A figure without the data it needs raises NoData.
"""
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Circle
from matplotlib.ticker import FormatStrFormatter

from . import paper
from .fits import evaluate, fit_alpha, fit_kappa, fit_phi, fit_regimes, fit_saturation, fit_theta
from .physics import gamman_ratio
from .result import format_pm
from .table import YIELD_SPEED, reference_params, select, yield_rows

plt.switch_backend("Agg")  # files only, no display

F_LABEL = r"$F^*_{\rm drag} = F_{\rm drag}/(\rho d^3 g)$"
FY_LABEL = r"$F^*_Y = F_Y/(\rho d^3 g)$"
FR_LABEL = r"Fr $= 2V\sqrt{2D/g}\,/\,(D+d)$"
DP1_LABEL = r"$D^*+1 = D/d + 1$"
H_LABEL = r"$h^* = h/d$"
MU_LABEL = r"friction coefficient $\mu$"
MARKERS = "osD^v<>ph*"
H_MATCH = 1.0   # [d] depths closer than this count as the same depth (Fig. 20)


class NoData(ValueError):
    """The table lacks the pulls a figure needs."""


def _subplots(*args, **kw):
    # Constrained layout instead of bbox_inches="tight": one draw per format.
    return plt.subplots(*args, layout="constrained", **kw)


def _save(fig, outdir, name, png_metadata=None):
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    paths = [outdir / f"{name}.png", outdir / f"{name}.pdf"]
    fig.savefig(paths[0], dpi=150, metadata=png_metadata)
    fig.savefig(paths[1])
    plt.close(fig)
    return paths


# PNG text key of a figure drawn in place of one without data (the workflow's figure rules
# always write their files); its value says why.
NOT_DRAWN = "granudrag-not-drawn"


def draw_not_drawn(outdir, name, caption, reason):
    """<name>.png and .pdf saying that the figure was not drawn, and why (tagged NOT_DRAWN)."""
    fig, ax = _subplots(figsize=(5, 1.6))
    ax.axis("off")
    ax.text(0.5, 0.5, f"{caption}\nnot drawn: {reason}", ha="center", va="center", wrap=True, fontsize=9)
    return _save(fig, outdir, name, png_metadata={NOT_DRAWN: reason})


def not_drawn_reason(png):
    """Why the figure file png was not drawn (None if it is a real figure or is missing)."""
    from PIL import Image

    try:
        with Image.open(png) as im:
            return im.info.get(NOT_DRAWN)
    except FileNotFoundError:
        return None


def _reference(df):
    kn, gn = reference_params(df)
    return select(df, kn=kn, gamman=gn)


def _errorbars(ax, x, y, err, i, label, scale=1.0):
    """Markers with error bars (where known); returns their colour."""
    err = np.asarray(err, float) / scale
    c = ax.errorbar(x, np.asarray(y, float) / scale,
                    yerr=np.where(np.isfinite(err), err, 0.0) if np.isfinite(err).any() else None,
                    fmt=MARKERS[i % len(MARKERS)], ms=4, capsize=2, mfc="none", label=label)
    return c[0].get_color()


def _curve(ax, fit, lo, hi, log=False, **kw):
    x = np.geomspace(max(lo, 1e-4), hi, 200) if log else np.linspace(lo, hi, 200)
    return ax.plot(x, evaluate(fit, x), **({"color": "k", "lw": 1} | kw))[0]


def _sci(v):
    """Mathtext for a number: 2e+05 -> 2\\times10^{5}, 500 -> 500."""
    text = f"{v:.3g}"
    if "e" not in text:
        return text
    m, e = text.split("e")
    return rf"{m}\times10^{{{int(e)}}}"


def _plain_log(ax, which="x"):
    """Log axis labelled 2, 3, 5, 10 rather than 2x10^0 (few decades here)."""
    axis = ax.xaxis if which == "x" else ax.yaxis
    (ax.set_xscale if which == "x" else ax.set_yscale)("log")
    axis.set_major_formatter(FormatStrFormatter("%g"))
    axis.set_minor_formatter(FormatStrFormatter("%g"))


def _moving(rows, by):
    """Groups that have pulls above the yield speed (drag-vs-Fr series)."""
    keep = rows.groupby(by).V.transform(lambda v: (~np.isclose(v, YIELD_SPEED)).any())
    return rows[keep.astype(bool)]


def _need(rows, what):
    if len(rows) == 0:
        raise NoData(f"no pulls for {what}")
    return rows


def _regime_fits(rows, by, mu, fits):
    """Regime fits per group, reusing those passed in; groups too small to fit get none."""
    fits = dict(fits or {})
    for key, g in rows.groupby(by):
        if key not in fits:
            g = g[~np.isclose(g.V, YIELD_SPEED)]      # fitted to the pulls at speed, as the report
            try:
                fits[key] = fit_regimes(g.Fr, g.drag, g.drag_err, n_boot=0,
                                        regime1="power" if mu == 0 else "constant")
            except ValueError:
                fits[key] = None
    return fits


def _drag_panels(rows, by, label, mu, fits, name, outdir, enlarge=True):
    fits = _regime_fits(rows, by, mu, fits)
    ncol = 2 if enlarge else 1
    fig, axes = _subplots(1, ncol, figsize=(5.2 * ncol, 4.0), squeeze=False)
    for ax, lim in zip(axes[0], [None, 1.2][:ncol]):
        for i, (key, g) in enumerate(rows.groupby(by)):
            g = g if lim is None else g[g.Fr <= lim]
            color = _errorbars(ax, g.Fr, g.drag, g.drag_err, i, label(key))
            fit = fits.get(key)
            if fit is not None and len(g):
                _curve(ax, fit, 0.0, g.Fr.max(), color=color, lw=0.8)
        ax.set_xlabel(FR_LABEL)
        ax.set_ylabel(F_LABEL)
    axes[0][0].legend(fontsize=7, title=rf"$\mu = {mu:g}$", title_fontsize=8)
    axes[0][0].set_title("(a)", loc="left")
    if enlarge:
        axes[0][1].set_title("(b) regime I, enlarged", loc="left")
    return _save(fig, outdir, name)


def fig02_restitution(v_n, e, theory_v, theory_e, outdir, sim_label="simulation"):
    """Fig. 2: restitution coefficient of a grain hitting the wall vs theory."""
    fig, ax = _subplots(figsize=(5, 3.8))
    ax.plot(v_n, e, "o", mfc="none", label=sim_label)
    ax.plot(theory_v, theory_e, "k-", label="Kuwabara-Kono / Brilliantov theory")
    ax.set_xscale("log")
    ax.set_xlabel(r"$v_n^* = v_n/\sqrt{gd}$")
    ax.set_ylabel("coefficient of restitution $e$")
    ax.legend(fontsize=8)
    return _save(fig, outdir, "fig02_restitution")


def fig04_force_trace(t, force, outdir, transient=0.0):
    """Fig. 4: instantaneous drag (thin) and its cumulative average (thick)."""
    t, force = np.asarray(t, float), np.asarray(force, float)
    keep = t >= transient
    cum = np.cumsum(force[keep]) / np.arange(1, keep.sum() + 1)
    fig, ax = _subplots(figsize=(6, 3.8))
    ax.plot(t, force, lw=0.4, color="0.6", label="instantaneous")
    ax.plot(t[keep], cum, lw=2, color="k", label="cumulative average")
    if transient > 0:
        ax.axvspan(t.min(), transient, color="0.9", label="discarded transient")
    ax.set_xlabel(r"$t^* = t\sqrt{g/d}$")
    ax.set_ylabel(F_LABEL)
    ax.legend(fontsize=8)
    return _save(fig, outdir, "fig04_force_trace")


def fig05_drag_vs_Fr(df, outdir, mu=0.5, fits=None):
    """Fig. 5 (mu = 0.5) / Fig. 10 (mu = 0): drag vs Fr per D, system I, with
    the three-regime fits; fits maps D -> Fit."""
    rows = _need(_moving(select(_reference(df), mu=mu, system="I"), "D"),
                 f"system I pulls above the yield speed at mu = {mu:g}")
    num = "10" if mu == 0 else "05"
    return _drag_panels(rows, "D", lambda D: f"$D = {D:g}d$", mu, fits,
                        f"fig{num}_drag_vs_Fr_mu{mu:g}", outdir)


def fig10_drag_vs_Fr_mu0(df, outdir, fits=None):
    """Fig. 10: frictionless drag vs Fr, regime I fitted by a + b Fr^c (Table I)."""
    return fig05_drag_vs_Fr(df, outdir, mu=0.0, fits=fits)


def fig06_theta(df, outdir, mu=0.5, fit=None):
    """Fig. 6: contact angle vs Fr per D with theta = U1 Fr^U2 + pi/U3."""
    rows = select(_reference(df), mu=mu, system="I").dropna(subset=["theta"])
    rows = _need(rows, f"contact angles at mu = {mu:g}")
    fit = fit or fit_theta(rows.Fr, rows.theta)
    fig, ax = _subplots(figsize=(5, 3.8))
    for i, (D, g) in enumerate(rows.groupby("D")):
        ax.plot(g.Fr, g.theta, MARKERS[i % len(MARKERS)], mfc="none", ms=4, label=f"$D = {D:g}d$")
    p = fit.values()
    _curve(ax, fit, rows.Fr.min(), rows.Fr.max(),
           label=rf"${p['U1']:.2f}\,{{\rm Fr}}^{{{p['U2']:.2f}}} + \pi/{p['U3']:.2f}$")
    ax.set_xlabel(FR_LABEL)
    ax.set_ylabel(r"mean contact angle $\theta$ (rad)")
    ax.legend(fontsize=7)
    return _save(fig, outdir, "fig06_theta_vs_Fr")


def _spread(values, k):
    """Up to k of the distinct values, evenly spread by rank (the grids are near-logarithmic)."""
    v = np.unique(np.asarray(values, float))
    if len(v) <= k:
        return v
    idx = np.unique(np.round(np.linspace(0, len(v) - 1, k)).astype(int))
    return v[idx]


def fig07_coordination(pz, outdir, D=4.0, mu=0.5, speeds=5):
    """Fig. 7: P(Z), the bulk coordination number of the grains around the intruder, for
    several speeds at one D (the one nearest D, system I, mu nearest mu, reference law).

    pz: long table with columns system, D, mu, kn, gamman, V, Fr, Z, P (one row per run and Z;
    the last Z bin holds Z and above)."""
    rows = _reference(_need(pz, "P(Z)"))
    rows = rows[rows.system == "I"] if (rows.system == "I").any() else rows
    mu_near = rows.mu.iloc[np.argmin(np.abs(rows.mu.to_numpy() - mu))]
    rows = rows[np.isclose(rows.mu, mu_near)]
    D_near = rows.D.iloc[np.argmin(np.abs(rows.D.to_numpy() - D))]
    rows = rows[np.isclose(rows.D, D_near)]
    fig, ax = _subplots(figsize=(5.2, 4.0))
    for i, V in enumerate(_spread(rows.V, speeds)):
        g = rows[np.isclose(rows.V, V)]
        g = g.groupby("Z", as_index=False).P.mean()     # several beds at one speed: their mean
        ax.plot(g.Z, g.P, marker=MARKERS[i % len(MARKERS)], ms=4, mfc="none", lw=0.8,
                label=rf"$V^* = {V:.3g}$")
    zmax = rows.Z.max()
    ax.set(xlabel=r"bulk coordination number $Z$", ylabel=r"$P(Z)$", xlim=(-0.5, zmax + 0.5))
    ax.set_xticks(range(0, int(zmax) + 1, 2))
    ax.legend(fontsize=7, title=rf"$D = {D_near:g}d$, $\mu = {mu_near:g}$", title_fontsize=8)
    return _save(fig, outdir, "fig07_coordination_distribution")


def fig09_flow_field(panels, outdir):
    """Fig. 9: velocity of the grains near the intruder, in its frame, in the slab |y - Y| < d/2.

    panels: list of (D, V, snapshot), snapshot a DataFrame with dx, dz, vx, vz (grain relative
    to the intruder; velocity in the intruder's frame, as stored by `granudrag pull`)."""
    panels = [p for p in panels if p[2] is not None and len(p[2])]
    if not panels:
        raise NoData("no velocity-field snapshots (pull with snapshots > 0)")
    fig, axes = _subplots(1, len(panels), figsize=(4.0 * len(panels), 4.0), squeeze=False)
    for ax, (D, V, snap) in zip(axes[0], panels):
        half = D / 2 + 5.0
        near = snap[(snap.dx.abs() < half) & (snap.dz.abs() < half)]
        # Lab-frame speed relative to the intruder's: grains dragged along show up bright.
        lab = np.hypot(near.vx + V, near.vz) / V
        ax.scatter(near.dx, near.dz, s=6, c="0.85", zorder=0)   # where the grains are
        q = ax.quiver(near.dx, near.dz, near.vx + V, near.vz, np.clip(lab, 0, 1.5), cmap="viridis",
                      clim=(0, 1.5), angles="xy", scale_units="xy", scale=2.0 * V, width=0.004)
        ax.add_patch(Circle((0, 0), D / 2, color="0.6", zorder=0))
        ax.set(xlim=(-half, half), ylim=(-half, half), aspect="equal",
               xlabel=r"$(x - X)/d$", ylabel=r"$(z - Z)/d$")
        ax.set_title(rf"$D = {D:g}d$, $V = {V:.3g}\sqrt{{gd}}$", fontsize=9)
    fig.colorbar(q, ax=axes[0].tolist(), label=r"grain speed / $V$ (lab frame)", shrink=0.8)
    return _save(fig, outdir, "fig09_flow_field")


def fig08_kappa(df, outdir, mu=0.5, fit=None):
    """Fig. 8: normalised coordination number kappa (Eq. 8) vs Fr, linear fit."""
    rows = select(_reference(df), mu=mu, system="I").dropna(subset=["kappa"])
    rows = _need(rows, f"kappa at mu = {mu:g}")
    fit = fit or fit_kappa(rows)
    fig, ax = _subplots(figsize=(5, 3.8))
    for i, (D, g) in enumerate(rows.groupby("D")):
        ax.plot(g.Fr, g.kappa, MARKERS[i % len(MARKERS)], mfc="none", ms=4, label=f"$D = {D:g}d$")
    p = fit.values()
    _curve(ax, fit, rows.Fr.min(), rows.Fr.max(),
           label=rf"$\kappa = {p['k0']:.3f} + {p['k1']:.3f}\,{{\rm Fr}}$")
    ax.set_xlabel(FR_LABEL)
    ax.set_ylabel(r"$\kappa = (Z/n)(D+d)^2/(2\sqrt{3}d^2)$")
    ax.legend(fontsize=7)
    return _save(fig, outdir, "fig08_kappa_vs_Fr")


def fig11_quasistatic_mu(df, outdir, D=2.0, mu_max=0.3, fit_mu0=None):
    """Fig. 11: drag for Fr <= 1 at D = 2d for small mu, with the mu = 0 fit."""
    rows = select(_reference(df), D=D, system="I")
    rows = _need(rows[(rows.Fr <= 1.0 + 1e-9) & (rows.mu <= mu_max + 1e-9)],
                 f"Fr <= 1 at D = {D:g}")
    fig, ax = _subplots(figsize=(5, 3.8))
    for i, (mu, g) in enumerate(rows.groupby("mu")):
        _errorbars(ax, g.Fr, g.drag, g.drag_err, i, rf"$\mu = {mu:g}$")
    if fit_mu0 is None:
        fit_mu0 = _regime_fits(select(_reference(df), D=D, system="I", mu=0.0), "D", 0.0, None).get(D)
    if fit_mu0 is not None:
        _curve(ax, fit_mu0, 0.0, 1.0, label=r"fit for $\mu = 0$")
    ax.set_xlabel(FR_LABEL)
    ax.set_ylabel(F_LABEL)
    ax.legend(fontsize=7, title=f"$D = {D:g}d$", title_fontsize=8)
    return _save(fig, outdir, "fig11_quasistatic_vs_mu")


def _yield_I(df):
    return _need(yield_rows(_reference(df)).query("system == 'I'"), "yield pulls of system I")


def fig12_yield_vs_mu(df, outdir, saturation=None):
    """Fig. 12: yield force vs mu per D; dashed: saturating fits (D -> Fit)."""
    rows = _yield_I(df)
    fig, ax = _subplots(figsize=(5, 3.8))
    for i, (D, g) in enumerate(rows.groupby("D")):
        color = _errorbars(ax, g.mu, g.drag, g.drag_err, i, f"$D = {D:g}d$")
        fit = (saturation or {}).get(D)
        if fit is None and g.mu.nunique() >= 4:
            try:
                fit = fit_saturation(g.mu, g.drag)
            except (ValueError, RuntimeError):
                fit = None
        if fit is not None:
            _curve(ax, fit, 0.0, g.mu.max(), color=color, ls="--", lw=0.8)
    ax.set_xlabel(MU_LABEL)
    ax.set_ylabel(FY_LABEL)
    ax.legend(fontsize=7)
    return _save(fig, outdir, "fig12_yield_vs_mu")


def _scaling_panels(rows, xcol, xlabel, table, expo, pref, name, outdir, logx_b):
    """Figs. 13 and 17: (a) log-log F_Y vs x per mu, (b) collapse, (c) prefactor vs mu."""
    fig, axes = _subplots(1, 3, figsize=(14, 4))
    for i, (mu, g) in enumerate(rows.groupby("mu")):
        t = table[np.isclose(table.mu, mu)]
        x = g[xcol] + (1.0 if xcol == "D" else 0.0)
        color = _errorbars(axes[0], x, g.drag, g.drag_err, i, rf"$\mu = {mu:g}$")
        if len(t):
            r = t.iloc[0]
            xs = np.geomspace(x.min(), x.max(), 50)
            axes[0].plot(xs, r[pref] * xs ** r[expo], color=color, lw=0.8)
            _errorbars(axes[1], x, g.drag, g.drag_err, i, None, scale=r[pref] * x ** r[expo])
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


def fig18_alpha(df, outdir, phi=None, alpha=None):
    """Fig. 18: (a) alpha_mu vs mu per K_n, (b) sum rule alpha_mu + phi_mu ~ 3."""
    from .fits import sum_rule
    phi = fit_phi(df) if phi is None else phi
    alpha = fit_alpha(df) if alpha is None else alpha
    if alpha.empty:
        raise NoData("no alpha_mu fitted (system II yield pulls at two or more h)")
    fig, axes = _subplots(1, 2, figsize=(10, 3.8))
    _by_kn(axes[0], alpha, "alpha", "alpha_err")
    axes[0].set_ylabel(r"$\alpha_\mu$")
    s = sum_rule(phi, alpha)
    if len(s):
        _by_kn(axes[1], s, "sum", "sum_err")
    axes[1].axhline(paper.SUM_RULE, color="k", ls="--", lw=0.8)
    axes[1].set_ylabel(r"$\alpha_\mu + \phi_\mu$")
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


def fig16_drag_vs_Fr_depth(df, outdir, mu=0.5, fits=None):
    """Fig. 16: drag vs Fr per depth (system II), with three-regime fits (h -> Fit)."""
    rows = _need(_moving(select(_reference(df), mu=mu, system="II"), "h"),
                 f"system II pulls above the yield speed at mu = {mu:g}")
    return _drag_panels(rows, "h", lambda h: f"$h = {h:.3g}d$", mu, fits,
                        "fig16_drag_vs_Fr_depth", outdir, enlarge=False)


def fig19_scaled_drag_h(df, outdir, alpha=None, mu=0.5, h_min=None):
    """Fig. 19: drag / h^alpha_mu vs Fr per depth (the paper shows h >= 45d)."""
    rows = _moving(select(_reference(df), mu=mu, system="II"), "h")
    if h_min is not None:
        rows = rows[rows.h >= h_min]
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


def fig20_kn_gamman(df, outdir, mu=0.5):
    """Fig. 20: drag vs Fr (a) for several K_n at fixed gamma_n/K_n^0.6 (same
    restitution curve), (b) for several gamma_n at the reference K_n."""
    kn0, gn0 = reference_params(df)
    rows = select(df, mu=mu)
    rows = rows[rows.system == "II"] if (rows.system == "II").any() else rows
    ratio = gamman_ratio(rows.kn, rows.gamman)
    same_e = rows[np.isclose(ratio, gamman_ratio(kn0, gn0), rtol=1e-6)]
    same_k = rows[np.isclose(rows.kn, kn0, rtol=1e-9)]
    varied = rows[(~np.isclose(rows.kn, kn0)) | (~np.isclose(rows.gamman, gn0))]
    if same_e.kn.nunique() < 2 and same_k.gamman.nunique() < 2:
        raise NoData(f"no K_n or gamma_n variations at mu = {mu:g}")
    # Compare at one depth: the one where the variations were run. Depths are
    # measured after settling, so beds poured for the same depth differ by a few
    # tenths of d: rows within H_MATCH of it count as at that depth.
    h = (varied if len(varied) else rows).h.round(6).mode().iloc[0]
    fig, axes = _subplots(1, 2, figsize=(10, 3.8))
    for ax, sel, col, sym in ((axes[0], same_e, "kn", "K_n"), (axes[1], same_k, "gamman", r"\gamma_n")):
        sel = sel[np.isclose(sel.h, h, rtol=0, atol=H_MATCH)]
        for i, (v, g) in enumerate(sel.groupby(col)):
            _errorbars(ax, g.Fr, g.drag, g.drag_err, i, rf"${sym} = {_sci(v)}$")
        ax.set(xlabel=FR_LABEL, ylabel=F_LABEL)
        if len(sel):
            ax.legend(fontsize=7)
    axes[0].set_title(r"(a) fixed $\gamma_n/K_n^{0.6}$", loc="left")
    axes[1].set_title(rf"(b) $K_n = {_sci(kn0)}$, $h \approx {h:.3g}d$", loc="left")
    return _save(fig, outdir, "fig20_kn_gamman")


def table1(df, outdir, fits=None):
    """Table I: mu = 0 regime-I coefficients a'' + b'' Fr^c'' per D, fitted
    beside published. Written as PNG/PDF and as Markdown (<name>.md)."""
    rows = _need(select(_reference(df), mu=0.0, system="I"), "system I at mu = 0")
    fits = _regime_fits(rows, "D", 0.0, fits)
    header = ["D/d", "a'' fit", "a'' paper", "b'' fit", "b'' paper", "c'' fit", "c'' paper",
              "F_Y (yield pull, not fitted)"]
    body = []
    for D, fit in sorted(fits.items()):
        if fit is None:
            continue
        pub = paper.TABLE1.get(int(round(D)), (np.nan,) * 3) if float(D).is_integer() else (np.nan,) * 3
        y = yield_rows(rows[np.isclose(rows.D, D)])
        fy = format_pm(float(y.drag.mean()), float(y.drag_err.mean())) if len(y) else "-"
        body.append([f"{D:g}"] + [s for k, v in zip(("a0", "b0", "c0"), pub)
                                  for s in (str(fit[k]), f"{v:g}" if np.isfinite(v) else "-")] + [fy])
    if not body:
        raise NoData("no mu = 0 regime fit succeeded")
    fig, ax = _subplots(figsize=(10.5, 0.4 * len(body) + 0.8))
    ax.axis("off")
    ax.table(cellText=body, colLabels=header, loc="center", cellLoc="center")
    paths = _save(fig, outdir, "table1_mu0_regime1")
    md = Path(outdir) / "table1_mu0_regime1.md"
    md.write_text("| " + " | ".join(header) + " |\n|" + "---|" * len(header) + "\n"
                  + "".join("| " + " | ".join(r) + " |\n" for r in body))
    return paths + [md]
