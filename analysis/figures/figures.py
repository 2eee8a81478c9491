"""One function per figure of the paper; each writes <name>.png, <name>.pdf and <name>.csv.

<name>.csv holds what the figure plots, one row per plotted point: figure, panel (a, b,
c in the order of the axes), series (its legend label, plain text), kind (points, curve,
line), x, y, y_err (NaN where none) and, for Fig. 9, the arrows u, v. The arrays are
recorded as they are handed to matplotlib (after any scaling or collapse), so the tests
check what is drawn.

Every function takes the pull table (or arrays) and an output directory and
returns the paths it wrote. Fits can be passed in (the report fits once and
draws many times); when they are not, the function fits what it draws
without bootstrap. Data of the study's reference contact law (the (K_n,
gamma_n) pair with most pulls) are drawn unless a figure is about varying
it (Figs. 14, 18, 20). A figure without the data it needs raises NoData.

The shared drawing (labels, the data record, saving, NoData, the "not drawn" placeholder) is in
analysis.figures.figures_drawing and the yield-force and scaling figures in analysis.figures.figures_yield; both
have their public names re-exported here, so analysis.figures.figures still offers every figure.
"""
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.patches import Circle

from ..core import paper
from ..core.physics import gamman_ratio
from ..core.result import format_pm
from ..core.table import reference_params, select, yield_rows
from ..fits.fits import THETA_DEFINITIONS, THETA_MIN_POINTS, fit_alpha, fit_kappa, fit_theta, series_labels
from .figures_drawing import (
    DATA_COLUMNS,
    DP1_LABEL,
    F_LABEL,
    FR_LABEL,
    FY_LABEL,
    H_LABEL,
    H_MATCH,
    MARKERS,
    MU_LABEL,
    NOT_DRAWN,
    NoData,
    _curve,
    _drag_panels,
    _errorbars,
    _fit_errors,
    _fit_note,
    _moving,
    _need,
    _record,
    _reference,
    _regime_fits,
    _save,
    _sci,
    _signed,
    _subplots,
    draw_not_drawn,
    not_drawn_reason,
)
from .figures_yield import (
    fig12_yield_vs_mu,
    fig13_yield_vs_D,
    fig14_phi_vs_mu,
    fig15_scaled_drag_D,
    fig17_yield_vs_h,
    fig18_alpha,
    fig19_scaled_drag_h,
)

__all__ = [
    "F_LABEL", "FY_LABEL", "FR_LABEL", "DP1_LABEL", "H_LABEL", "MU_LABEL", "MARKERS", "H_MATCH", "NoData",
    "DATA_COLUMNS", "NOT_DRAWN", "draw_not_drawn", "not_drawn_reason", "fit_alpha",
    "fig02_restitution", "fig04_force_trace", "fig05_drag_vs_Fr", "fig06_theta", "fig07_coordination",
    "fig08_kappa", "fig09_flow_field", "fig10_drag_vs_Fr_mu0", "fig11_quasistatic_mu", "fig12_yield_vs_mu",
    "fig13_yield_vs_D", "fig14_phi_vs_mu", "fig15_scaled_drag_D", "fig16_drag_vs_Fr_depth",
    "fig17_yield_vs_h", "fig18_alpha", "fig19_scaled_drag_h", "fig20_kn_gamman", "table1",
]


def fig02_restitution(v_n, e, theory_v, theory_e, outdir, sim_label="simulation"):
    """Fig. 2: restitution coefficient of a grain hitting the wall vs theory."""
    fig, ax = _subplots(figsize=(5, 3.8))
    ax.plot(v_n, e, "o", mfc="none", label=sim_label)
    ax.plot(theory_v, theory_e, "k-", label="Kuwabara-Kono / Brilliantov theory")
    _record(ax, "simulation", v_n, e)
    _record(ax, "theory", theory_v, theory_e, kind="curve")
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
    _record(ax, "instantaneous", t, force, kind="line")
    _record(ax, "cumulative average", t[keep], cum, kind="line")
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


def fig06_theta(df, outdir, mu=0.5, fit=None, fit_present=None):
    """Fig. 6: contact angle vs Fr per D with theta = U1 Fr^U2 + pi/U3; beside it, when the table
    has it, θ over the contacts present (time-weighted, column theta_present) with its own Eq. 7 fit
    (fit_present; fitted here only when neither fit is given, as a figure drawn without fits.json)."""
    ref = select(_reference(df), mu=mu, system="I")
    rows = _need(ref.dropna(subset=["theta"]), f"contact angles at mu = {mu:g}",
                 at_least=1 if fit else THETA_MIN_POINTS)
    present = ref.dropna(subset=["theta_present"]) if "theta_present" in ref else ref.iloc[:0]
    panels = [("theta", rows, fit)]
    if len(present) and (fit_present or (fit is None and len(present) >= THETA_MIN_POINTS)):
        panels.append(("theta_present", present, fit_present))
    fig, axes = _subplots(1, len(panels), figsize=(5 * len(panels), 3.8), squeeze=False, sharey=True)
    for ax, (col, g, f) in zip(axes[0], panels):
        _theta_panel(ax, col, g, f, len(panels) > 1)
    return _save(fig, outdir, "fig06_theta_vs_Fr")


def _theta_panel(ax, col, rows, fit, titled):
    """One θ definition against Fr with its Eq. 7 fit (fitted here when not given)."""
    err = rows[f"{col}_err"] if f"{col}_err" in rows else None
    fit = fit or fit_theta(rows.Fr, rows[col], err, series_labels(rows))
    tag = "" if col == "theta" else f"{col}: "
    for i, (label, g) in enumerate(_series(rows)):     # with the errors the fit was weighted by
        _errorbars(ax, g.Fr, g[col], err[g.index] if err is not None else np.nan, i, label, series=tag + label)
    p = fit.values()
    note = _fit_note(fit)
    label = rf"${p['U1']:.2f}\,{{\rm Fr}}^{{{p['U2']:.2f}}} + \pi/{p['U3']:.2f}$"
    _curve(ax, fit, rows.Fr.min(), rows.Fr.max(), label=label + (f"\n({note})" if note else ""),
           series=f"{tag}theta = {p['U1']:.2f} Fr^{p['U2']:.2f} + pi/{p['U3']:.2f}")
    ax.set_xlabel(FR_LABEL)
    ax.set_ylabel(r"mean contact angle $\theta$ (rad)")
    if titled:
        ax.set_title(f"θ {THETA_DEFINITIONS[col]}", fontsize=8)
    ax.legend(fontsize=7)


def _series(rows):
    """(legend label, rows) of each series of a fit over several D (fits.series_labels: D, and
    the depth where one D was pulled at several, so two beds' points never share a series)."""
    labels = pd.Series(series_labels(rows), index=rows.index)
    for text, g in rows.groupby(labels, sort=False):
        yield "$" + text.replace(", h = ", "d$, $h = ") + "d$", g


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
        _record(ax, f"V* = {V:.3g}", g.Z, g.P, kind="line")
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
        _record(ax, f"D = {D:g}d, V = {V:.3g}", near.dx, near.dz, kind="arrows", u=near.vx + V, v=near.vz)
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
    err = rows["kappa_err"] if "kappa_err" in rows else None
    fig, ax = _subplots(figsize=(5, 3.8))
    for i, (label, g) in enumerate(_series(rows)):     # with the errors the fit was weighted by
        _errorbars(ax, g.Fr, g.kappa, err[g.index] if err is not None else np.nan, i, label)
    p = fit.values()
    formula = f"{p['k0']:.3f}{_signed(p['k1'])}"
    note = _fit_note(fit)
    _curve(ax, fit, rows.Fr.min(), rows.Fr.max(),
           label=rf"$\kappa = {formula}\,{{\rm Fr}}$" + (f"\n({note})" if note else ""),
           series=f"kappa = {formula} Fr")
    ax.set_xlabel(FR_LABEL)
    ax.set_ylabel(r"$\kappa = (Z/n)(D+d)^2/(2\sqrt{3}d^2)$")
    ax.legend(fontsize=7)
    return _save(fig, outdir, "fig08_kappa_vs_Fr")


def fig11_quasistatic_mu(df, outdir, D=2.0, mu_max=0.3, fit_mu0=None):
    """Fig. 11: drag for Fr <= 1 at D = 2d for small mu, with the mu = 0 fit."""
    rows = select(_reference(df), D=D, system="I")
    # Each friction's errors as its regime fit weights them (the μ = 0 fit is drawn).
    err = pd.concat([_fit_errors(g) for _, g in rows.groupby("mu")]) if len(rows) else None
    rows = _need(rows[(rows.Fr <= 1.0 + 1e-9) & (rows.mu <= mu_max + 1e-9)],
                 f"Fr <= 1 at D = {D:g}")
    fig, ax = _subplots(figsize=(5, 3.8))
    for i, (mu, g) in enumerate(rows.groupby("mu")):
        _errorbars(ax, g.Fr, g.drag, err[g.index], i, rf"$\mu = {mu:g}$")
    if fit_mu0 is None:
        fit_mu0 = _regime_fits(select(_reference(df), D=D, system="I", mu=0.0), "D", 0.0, None).get(D)
    if fit_mu0 is not None:
        _curve(ax, fit_mu0, 0.0, 1.0, label=r"fit for $\mu = 0$")
    ax.set_xlabel(FR_LABEL)
    ax.set_ylabel(F_LABEL)
    ax.legend(fontsize=7, title=f"$D = {D:g}d$", title_fontsize=8)
    return _save(fig, outdir, "fig11_quasistatic_vs_mu")



def fig16_drag_vs_Fr_depth(df, outdir, mu=0.5, fits=None):
    """Fig. 16: drag vs Fr per depth (system II), with three-regime fits (h -> Fit)."""
    rows = _need(_moving(select(_reference(df), mu=mu, system="II"), "h"),
                 f"system II pulls above the yield speed at mu = {mu:g}")
    return _drag_panels(rows, "h", lambda h: f"$h = {h:.3g}d$", mu, fits,
                        "fig16_drag_vs_Fr_depth", outdir, enlarge=False)


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
    paths = _save(fig, outdir, "table1_mu0_regime1", data=pd.DataFrame(body, columns=header))
    md = Path(outdir) / "table1_mu0_regime1.md"
    md.write_text("| " + " | ".join(header) + " |\n|" + "---|" * len(header) + "\n"
                  + "".join("| " + " | ".join(r) + " |\n" for r in body))
    return paths[:2] + [md] + paths[2:]
