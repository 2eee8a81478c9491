"""The report's figures in the paper's order: each one's file name, caption (figure_names) and drawing.

A figure is drawn from the study's data (`Inputs`: the pull table, the restitution and
force-trace series, P(Z), the velocity fields) and the report's fits (`fitset.Results`,
read from fits.json), so that drawing it never refits with bootstrap. `draw` always writes
<name>.png and .pdf: a figure whose data are missing is drawn as a note saying why, which
the report lists as "not drawn" (figures.not_drawn_reason).

The workflow draws them by families (workflow/rules/figures.smk) with
`draw_files(inputs, outputs)`; `build_report` draws all of them.
"""

from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import pandas as pd

from ..core.table import load_csv
from ..fits.fitset import load_results
from . import figure_names
from . import figures as F


@dataclass
class Inputs:
    """The data figures are drawn from; None where not given."""

    table: pd.DataFrame = None
    restitution: tuple = None  # (v_n, e, theory v_n, theory e[, label of e]), Fig. 2
    trace: tuple = None  # (t, drag[, transient]), Fig. 4
    coordination: pd.DataFrame = None  # P(Z) per run, long format, Fig. 7
    flow: list = None  # [(D, V, snapshot)], Fig. 9


@dataclass(frozen=True)
class Figure:
    name: str  # file name without extension (stable: the report and the rules use it)
    caption: str
    draw: Callable  # (Inputs, Results, outdir) -> paths written
    markdown: bool = False  # also <name>.md (Table I)


def _need(data, what):
    if data is None:
        raise F.NoData(f"no {what} given")
    return data


def _restitution(inp, r, out):
    v, e, tv, te, *label = _need(inp.restitution, "restitution data")
    return F.fig02_restitution(v, e, tv, te, out, *label)


def _trace(inp, r, out):
    t, force, *transient = _need(inp.trace, "force trace")
    return F.fig04_force_trace(t, force, out, *transient)


def _table(fn, **kw):
    """A figure of the pull table; kw maps fn's keyword to a function of the Results."""
    return lambda inp, r, out: fn(_need(inp.table, "pull table"), out, **{k: g(r) for k, g in kw.items()})


# Each figure's drawing, by its name in figure_names (which declares the names, captions and order).
_DRAW = {
    "fig02_restitution": _restitution,
    "fig04_force_trace": _trace,
    "fig05_drag_vs_Fr_mu0.5": _table(F.fig05_drag_vs_Fr, fits=lambda r: r.by("D", 0.5)),
    "fig06_theta_vs_Fr": _table(F.fig06_theta, fit=lambda r: r.theta, fit_present=lambda r: r.theta_present),
    "fig07_coordination_distribution":
        lambda inp, r, out: F.fig07_coordination(_need(inp.coordination, "P(Z) data"), out),
    "fig08_kappa_vs_Fr": _table(F.fig08_kappa, fit=lambda r: r.kappa),
    "fig09_flow_field": lambda inp, r, out: F.fig09_flow_field(_need(inp.flow, "velocity-field snapshots"), out),
    "fig10_drag_vs_Fr_mu0": _table(F.fig10_drag_vs_Fr_mu0, fits=lambda r: r.by("D", 0.0)),
    "table1_mu0_regime1": _table(F.table1, fits=lambda r: r.by("D", 0.0)),
    "fig11_quasistatic_vs_mu": _table(F.fig11_quasistatic_mu, fit_mu0=lambda r: r.by("D", 0.0).get(2.0)),
    "fig12_yield_vs_mu": _table(F.fig12_yield_vs_mu, saturation=lambda r: r.saturation),
    "fig13_yield_vs_D": _table(F.fig13_yield_vs_D, phi=lambda r: r.phi),
    "fig14_phi_vs_mu": _table(F.fig14_phi_vs_mu, phi=lambda r: r.phi),
    "fig15_scaled_drag_vs_Fr_D": _table(F.fig15_scaled_drag_D, phi=lambda r: r.phi),
    "fig16_drag_vs_Fr_depth": _table(F.fig16_drag_vs_Fr_depth, fits=lambda r: r.by("h", 0.5)),
    "fig17_yield_vs_h": _table(F.fig17_yield_vs_h, alpha=lambda r: r.alpha),
    "fig18_alpha_and_sum_rule":
        _table(F.fig18_alpha, phi=lambda r: r.phi, alpha=lambda r: r.alpha, alpha_drag=lambda r: r.alpha_drag),
    "fig19_scaled_drag_vs_Fr_h":
        _table(F.fig19_scaled_drag_h, alpha=lambda r: r.alpha, h_min=lambda r: r.options.h_min),
    "fig20_kn_gamman": _table(F.fig20_kn_gamman),
}
if set(_DRAW) != set(figure_names.NAMES):
    raise ImportError(f"figure_list draws {sorted(set(_DRAW) ^ set(figure_names.NAMES))} that figure_names does "
                      "not name, or names what it does not draw: a figure is declared in both")
FIGURES = [Figure(f.name, f.caption, _DRAW[f.name], f.markdown) for f in figure_names.FIGURES]
BY_NAME = {f.name: f for f in FIGURES}
NAMES = [f.name for f in FIGURES]


def draw(name, inputs, results, outdir):
    """Draw one figure into outdir; (paths written, None or why it was not drawn)."""
    figure = BY_NAME[name]
    try:
        return figure.draw(inputs, results, outdir), None
    except F.NoData as exc:
        paths = F.draw_not_drawn(outdir, name, figure.caption, str(exc))
        if figure.markdown:
            paths.append(Path(outdir) / f"{name}.md")
            paths[-1].write_text(f"{figure.caption}: not drawn — {exc}.\n")
        return paths, str(exc)


def read_inputs(table=None, restitution=None, theory=None, trace=None, coordination=None, flow=None):
    """Inputs from the workflow's files (paths; any may be None): table.csv, the engine's and
    the theory's restitution CSVs, trace.csv, coordination.csv, flow_field.csv."""
    inp = Inputs()
    if table:
        inp.table = load_csv(table)
    if restitution and theory:
        engine, th = pd.read_csv(restitution), pd.read_csv(theory)
        label = f"granudrag drop test ($K_n = {th.kn.iloc[0]:.3g}$, $\\gamma_n = {th.gamman.iloc[0]:.4g}$)"
        inp.restitution = (engine.v_n, engine.e_dem, th.v_n, th.e, label)
    if trace:
        t = pd.read_csv(trace)
        inp.trace = (t.t, t.drag, float(t.transient.iloc[0]))
    if coordination:
        inp.coordination = pd.read_csv(coordination, dtype={"system": str})
    if flow:
        f = pd.read_csv(flow)
        inp.flow = [(g.D.iloc[0], g.V.iloc[0], g) for _, g in f.groupby("panel")]
    return inp


def draw_files(inputs, outputs):
    """The workflow's figure rules: draw every figure that outputs name (<name>.png) from the
    files inputs names (keys: fits and those of read_inputs). Returns lines for the log."""
    inputs = dict(inputs)
    fits = inputs.pop("fits", None)
    results = load_results(fits) if fits else None
    data = read_inputs(**inputs)
    lines = []
    for png in (Path(p) for p in outputs if str(p).endswith(".png")):
        paths, why = draw(png.stem, data, results, png.parent)
        lines.append(f"{png.stem}: " + (f"not drawn ({why})" if why else ", ".join(p.name for p in paths)))
    return lines
