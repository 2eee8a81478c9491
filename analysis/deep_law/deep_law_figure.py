"""The figure of the depth law for each system II series (analysis.deep_law.deep_law): the yield force and
the drag at each of the paper's speeds against h, log-log, with the law fitted on the deep depths
(h >= h_min, solid) carried down to the shallow ones (dashed), one alpha for all speeds (the
collapse) and one for the yield force; below, each point's departure from that law in units of
its error. Files: deep_law_<series>.png, .pdf and .csv (what is drawn, figures_drawing)."""
import numpy as np
from matplotlib.ticker import NullFormatter, ScalarFormatter

from ..core import paper
from ..core.table import is_yield
from ..figures.figures_drawing import _record, _save, _subplots
from .deep_law import SERIES, _law, log_covariance, speed_groups


def _kinds(g, speeds):
    """(label, rows, group keys) for the yield pulls and the pulls at the speeds."""
    yld, moving = g[is_yield(g)], g[~is_yield(g)]
    groups = speed_groups(moving, speeds)
    keep = np.isfinite(groups)
    return [("F_Y", yld, np.zeros(len(yld))), ("drag", moving[keep], groups[keep])]


def draw(df, out_dir, h_min=paper.DEEP_H, speeds=(0.5, 1.0, 2.0, 4.0, 6.0), system="II"):
    """One figure per series; returns the paths written."""
    paths = []
    for key, g in df[df.system == system].groupby(SERIES):
        fig, (ax, res) = _subplots(2, 1, figsize=(6.4, 6.4), sharex=True, height_ratios=[3, 1.3])
        colours = iter(["k"] + [f"C{i}" for i in range(10)])
        for label, t, group in _kinds(g, speeds):
            if t.empty:
                continue
            h = t.h.to_numpy(float)
            y, C, _, _ = log_covariance(t)
            fit = _law(t, t, group, h_min)
            for k in sorted(set(group.tolist())):
                c = next(colours)
                at = group == k
                name = "F_Y (yield)" if label == "F_Y" else f"V = {k:g}"
                err = np.sqrt(np.diag(C))[at] * np.exp(y[at])
                ax.errorbar(h[at], np.exp(y[at]), err, fmt="o", color=c, ms=4, capsize=2, label=name)
                _record(ax, name, h[at], np.exp(y[at]), err)
                if fit is None or k not in fit.keys:
                    continue
                hh = np.geomspace(h.min(), h.max(), 50)
                line = np.exp(fit.design(np.full(50, k), hh) @ fit.beta)
                ax.plot(hh[hh >= h_min], line[hh >= h_min], "-", color=c, lw=1)
                ax.plot(hh[hh <= h_min], line[hh <= h_min], "--", color=c, lw=1)
                _record(ax, name + " deep law", hh, line, kind="curve")
                r = (y[at] - fit.design(group[at], h[at]) @ fit.beta) / np.sqrt(np.diag(C)[at])
                res.plot(h[at], r, "o", color=c, ms=4)
                _record(res, name, h[at], r)
            if fit is not None:
                ax.plot([], [], " ", label=f"{'α (yield)' if label == 'F_Y' else 'α (one for all V)'} = {fit.alpha}")
        for a in (ax, res):
            a.axvline(h_min, color="0.6", ls=":", lw=1)
        ax.set_xscale("log")
        ax.set_yscale("log")
        for axis in (ax.xaxis, ax.yaxis):
            axis.set_major_formatter(ScalarFormatter())
            axis.set_minor_formatter(NullFormatter())
        ax.set_ylabel(r"$F^*$")
        ax.legend(fontsize=7, ncol=2)
        res.axhline(0, color="k", lw=0.8)
        res.set_xlabel(r"$h/d$")
        res.set_ylabel("departure / error")
        D, mu, kn, _ = key
        ax.set_title(f"system {system}, D = {D:g}, μ = {mu:g}, K_n = {kn:.3g}: fitted on h ≥ {h_min:g} d", fontsize=9)
        paths += _save(fig, out_dir, f"deep_law_D{D:g}_mu{mu:g}_kn{kn:.3g}")
    return paths
