"""The figure of claim (a) for each drag-vs-Fr series (analysis.regime_tests.regime_tests): the drag against Fr
under each averaging (a column each) with the line, the quadratic and the paper's shape (Fr₂ = 5 and
profiled) fitted on 1 ≤ Fr ≤ 15, and below, each point's residual in units of its error against
each, where a curvature the line misses shows as a U (fitted with the tests' covariance, so a bed's
shift can leave all residuals of one sign). Points outside the fitted range are drawn
open and grey. Files: regime_tests_<series>.png, .pdf and .csv (what is drawn, figures_drawing)."""
import numpy as np

from ..core.bed_shift import covariance
from ..figures.figures_drawing import FR_LABEL, _record, _save, _subplots
from .regime_fits import (
    PAPER_FR2,
    fit_line,
    fit_paper_shape,
    fit_quadratic,
    paper_curve,
    paper_tangent_design,
    profile_paper_shape,
    scale,
    wls,
)
from .regime_tests import RANGES, averagings, in_range, noise_scale, series

MODELS = (("line", "C0", "-"), ("quadratic", "C1", "-"), ("paper, Fr₂ = 5", "C2", "--"), ("paper, Fr₂ free", "C3", ":"))
PAPER_SIZED = "paper-sized: tangent at Fr₂ = 5"   # the alternative the power is against (regime_power)


def _curves(x, y, s):
    """Each model's curve as a function of Fr, fitted to (x, y, s)."""
    line, quad = fit_line(x, y, s), fit_quadratic(x, y, s)
    fixed, free = fit_paper_shape(x, y, s), profile_paper_shape(x, y, s)
    out = {"line": lambda f: line["a"] + line["b"] * f,
           "quadratic": lambda f: quad["a"] + quad["b"] * f + quad["c"] * f * f,
           "paper, Fr₂ = 5": lambda f: paper_curve(f, **fixed)}
    if free is not None:
        out["paper, Fr₂ free"] = lambda f: paper_curve(f, **free)
    return out


def _paper_sized(x, y, s):
    ab = wls(paper_tangent_design(x, [PAPER_FR2])[0], y, s)[0][0]
    return lambda f: paper_tangent_design(np.asarray(f, float), [PAPER_FR2])[0] @ ab


def _name(keys):
    h = "" if not np.isfinite(keys["h"]) else f"_h{keys['h']:g}"
    kn = f"{keys['kn']:.3g}".replace("e+0", "e").replace("e+", "e")
    return f"regime_tests_{keys['system']}_D{keys['D']:g}{h}_mu{keys['mu']:g}_kn{kn}"


def draw_series(keys, g, outdir, fr_range=RANGES[-1], averaging="both"):
    """One series' figure, a column per averaging (regime_tests.averagings' `which`); returns the paths written."""
    avgs = averagings(g, averaging)
    fig, axes = _subplots(2, len(avgs), figsize=(5.2 * len(avgs), 6), squeeze=False, sharex=True,
                          gridspec_kw={"height_ratios": [3, 1.3]})
    for j, (name, col, err) in enumerate(avgs):
        top, bottom = axes[0, j], axes[1, j]
        fr, F, e = g.Fr.to_numpy(float), g[col].to_numpy(float), g[err].to_numpy(float)
        x, y, C = in_range(fr, F, covariance(g, col, err), *fr_range)
        out = ~((fr >= fr_range[0] - 1e-9) & (fr <= fr_range[1] + 1e-9))
        top.errorbar(fr[out], F[out], yerr=e[out], fmt="o", mfc="none", color="0.6", ms=4, capsize=2)
        _record(top, f"{name}: outside the fit", fr[out], F[out], e[out])
        if len(np.unique(x)) < 5:
            top.set_title(f"{name}: too few speeds in {fr_range[0]:g}-{fr_range[1]:g}", fontsize=8)
            continue
        C = scale(C, noise_scale(x, y, C))   # the tests' errors, their bed shift included
        s = np.sqrt(np.diag(C))
        top.errorbar(x, y, yerr=s, fmt="o", color="k", ms=4, capsize=2, label=f"{name} drag")
        _record(top, f"{name}: points", x, y, s)
        grid = np.linspace(x.min(), x.max(), 200)
        for k, (model, curve) in enumerate(_curves(x, y, C).items()):
            color, ls = next((c, st) for m, c, st in MODELS if m == model)
            top.plot(grid, curve(grid), color=color, ls=ls, lw=1, label=model)
            _record(top, f"{name}: {model}", grid, curve(grid), kind="curve")
            r = (y - curve(x)) / s
            bottom.plot(x + (k - 1.5) * 0.06, r, marker="o", ls="none", ms=3, color=color)
            _record(bottom, f"{name}: {model} residual / error", x, r)
        sized = _paper_sized(x, y, C)
        top.plot(grid, sized(grid), color="0.5", lw=0.8, ls="-.", label=PAPER_SIZED)
        _record(top, f"{name}: {PAPER_SIZED}", grid, sized(grid), kind="curve")
        for level in (-2, -1, 1, 2):
            bottom.axhline(level, color="0.8", lw=0.6, ls=":")
        bottom.axhline(0, color="k", lw=0.6)
        for ax in (top, bottom):
            ax.axvline(5.0, color="0.7", lw=0.6, ls="--")
        top.set_title(f"{name} averaging, fitted on {fr_range[0]:g} ≤ Fr ≤ {fr_range[1]:g}", fontsize=9)
        top.set_ylabel(r"$F^*_{\rm drag}$")
        top.legend(fontsize=7)
        bottom.set_ylabel("residual / error")
        bottom.set_xlabel(FR_LABEL)
    where = f"h = {keys['h']:g}" if np.isfinite(keys["h"]) else f"D = {keys['D']:g}"
    fig.suptitle(f"claim (a), system {keys['system']}, {where}, μ = {keys['mu']:g}, K_n = {keys['kn']:g}", fontsize=10)
    return _save(fig, outdir, _name(keys))


def draw(table, outdir, averaging="both"):
    """Every series' figure; returns the paths written."""
    return [p for keys, g in series(table) for p in draw_series(keys, g, outdir, averaging=averaging)]
