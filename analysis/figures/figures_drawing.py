"""What every figure shares: the axis labels, NoData, the record of what is drawn (<name>.csv)
and the saving of a figure's files, the "not drawn" placeholder, and the plotting helpers of
the drag-vs-Fr figures (reference contact law, error bars, fitted curves, regime fits)."""
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.ticker import FormatStrFormatter

from ..core.bed_shift import curve_errors
from ..core.table import is_yield, pooled_drag_err, reference_params, select, write_csv
from ..fits.fits import evaluate, fit_regimes
from ..fits.goodness import chi2_far_out

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


DATA_COLUMNS = ["figure", "panel", "series", "kind", "x", "y", "y_err"]


def _record(ax, series, x, y, err=None, kind="points", **extra):
    """Keep what is drawn on ax for the figure's CSV (see the docstring of analysis.figures.figures)."""
    fig = ax.figure
    x, y = np.asarray(x, float).ravel(), np.asarray(y, float).ravel()
    err = np.full(len(x), np.nan) if err is None else np.broadcast_to(np.asarray(err, float), x.shape)
    panel = "abcdefgh"[fig.axes.index(ax)] if ax in fig.axes else "a"
    label = str(series).replace("$", "").replace("\\", "") if series is not None else ""
    frame = pd.DataFrame({"panel": panel, "series": label, "kind": kind, "x": x, "y": y, "y_err": err,
                          **{k: np.asarray(v, float).ravel() for k, v in extra.items()}})
    if not hasattr(fig, "_granudrag_data"):
        fig._granudrag_data = []
    fig._granudrag_data.append(frame)


def _save(fig, outdir, name, png_metadata=None, data=None):
    """<name>.png and .pdf, and <name>.csv with the recorded data (or `data`, a DataFrame)."""
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    paths = [outdir / f"{name}.png", outdir / f"{name}.pdf"]
    fig.savefig(paths[0], dpi=150, metadata=png_metadata)
    fig.savefig(paths[1])
    parts = getattr(fig, "_granudrag_data", [])
    plt.close(fig)
    if data is None and parts:
        data = pd.concat(parts, ignore_index=True)
        data.insert(0, "figure", name)
    if data is not None:
        write_csv(data, outdir / f"{name}.csv")
        paths.append(outdir / f"{name}.csv")
    return paths


# PNG text key of a figure drawn in place of one without data (the workflow's figure rules
# always write their files); its value says why.
NOT_DRAWN = "granudrag-not-drawn"


def draw_not_drawn(outdir, name, caption, reason):
    """<name>.png and .pdf saying that the figure was not drawn, and why (tagged NOT_DRAWN)."""
    fig, ax = _subplots(figsize=(5, 1.6))
    ax.axis("off")
    ax.text(0.5, 0.5, f"{caption}\nnot drawn: {reason}", ha="center", va="center", wrap=True, fontsize=9)
    # Its data file has the columns and no rows (nothing was plotted).
    return _save(fig, outdir, name, png_metadata={NOT_DRAWN: reason}, data=pd.DataFrame(columns=DATA_COLUMNS))


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


def _errorbars(ax, x, y, err, i, label, scale=1.0, series=None):
    """Markers with error bars (where known); returns their colour."""
    err = np.asarray(err, float) / scale
    _record(ax, series if series is not None else label, x, np.asarray(y, float) / scale, err)
    c = ax.errorbar(x, np.asarray(y, float) / scale,
                    yerr=np.where(np.isfinite(err), err, 0.0) if np.isfinite(err).any() else None,
                    fmt=MARKERS[i % len(MARKERS)], ms=4, capsize=2, mfc="none", label=label)
    return c[0].get_color()


def _fit_errors(series):
    """The drag errors a regime fit of this series (one D or h) was weighted by, per row: the
    pulls at speed pooled as fitset.run_fits pools them (table.pooled_drag_err), the yield pull
    (not in the fit) its own drag_err. Taken over the whole series, then subset by index."""
    err = pd.Series(series.drag_err.to_numpy(float), index=series.index)
    moving = series[~is_yield(series)]
    if len(moving):
        err.loc[moving.index] = np.asarray(pooled_drag_err(moving), float)
    return err


def _signed(value, fmt=".3f"):
    """' + 0.185' or ' − 0.021': a term of a legend's formula with its sign written once."""
    return f" {'−' if value < 0 else '+'} {abs(value):{fmt}}"


def _fit_note(fit):
    """The goodness of a fit for its legend entry: 'χ²/dof = 0.62' and, when the data reject the
    model, 'model rejected: residuals trend' or 'model rejected: χ² far out' (goodness.py)."""
    g = fit.meta.get("goodness") if fit is not None else None
    if not g:
        return ""
    text = f"χ²/dof = {g['chi2_dof']:.2f}" if g.get("chi2_dof") is not None else ""
    if g.get("rejected"):
        why = ": residuals trend" if g.get("trend") else ": χ² far out" if chi2_far_out(g) else ""
        text += ("; " if text else "") + f"model rejected{why}"
    return text


def _curve(ax, fit, lo, hi, log=False, series=None, **kw):
    x = np.geomspace(max(lo, 1e-4), hi, 200) if log else np.linspace(lo, hi, 200)
    _record(ax, series or kw.get("label", "fit"), x, evaluate(fit, x), kind="curve")
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
    keys = [rows[b] for b in by] if isinstance(by, (list, tuple)) else rows[by]
    keep = pd.Series(~is_yield(rows), index=rows.index).groupby(keys).transform("any")
    return rows[keep.astype(bool)]


def _need(rows, what, at_least=1):
    """rows, or NoData when there are fewer than at_least (a fitted figure: the fit's minimum)."""
    if len(rows) == 0:
        raise NoData(f"no pulls for {what}")
    if len(rows) < at_least:
        raise NoData(f"{len(rows)} pulls for {what}; the fit needs {at_least}")
    return rows


def _regime_fits(rows, by, mu, fits):
    """Regime fits per group, reusing those passed in; groups too small to fit get none."""
    fits = dict(fits or {})
    for key, g in rows.groupby(by):
        if key not in fits:
            g = g[~is_yield(g)]      # fitted to the pulls at speed, weighted as the report's
            try:
                fits[key] = fit_regimes(g.Fr, g.drag, curve_errors(g), n_boot=0,
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
            err = _fit_errors(g)          # the errors the series' fit was weighted by
            g = g if lim is None else g[g.Fr <= lim]
            color = _errorbars(ax, g.Fr, g.drag, err[g.index], i, label(key))
            fit = fits.get(key)
            if fit is not None and len(g):
                _curve(ax, fit, 0.0, g.Fr.max(), color=color, lw=0.8, series=f"fit, {label(key)}")
        ax.set_xlabel(FR_LABEL)
        ax.set_ylabel(F_LABEL)
    axes[0][0].legend(fontsize=7, title=rf"$\mu = {mu:g}$", title_fontsize=8)
    axes[0][0].set_title("(a)", loc="left")
    if enlarge:
        axes[0][1].set_title("(b) regime I, enlarged", loc="left")
    return _save(fig, outdir, name)
