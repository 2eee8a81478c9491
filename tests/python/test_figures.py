"""Every figure function writes a PNG and a PDF from a small synthetic table."""
import re

import numpy as np
import pytest
import synth

from analysis.figures import figures as F

TABLE_FIGURES = [
    (F.fig05_drag_vs_Fr, "fig05_drag_vs_Fr_mu0.5"),
    (F.fig06_theta, "fig06_theta_vs_Fr"),
    (F.fig08_kappa, "fig08_kappa_vs_Fr"),
    (F.fig10_drag_vs_Fr_mu0, "fig10_drag_vs_Fr_mu0"),
    (F.fig11_quasistatic_mu, "fig11_quasistatic_vs_mu"),
    (F.fig12_yield_vs_mu, "fig12_yield_vs_mu"),
    (F.fig13_yield_vs_D, "fig13_yield_vs_D"),
    (F.fig14_phi_vs_mu, "fig14_phi_vs_mu"),
    (F.fig15_scaled_drag_D, "fig15_scaled_drag_vs_Fr_D"),
    (F.fig16_drag_vs_Fr_depth, "fig16_drag_vs_Fr_depth"),
    (F.fig17_yield_vs_h, "fig17_yield_vs_h"),
    (F.fig18_alpha, "fig18_alpha_and_sum_rule"),
    (F.fig19_scaled_drag_h, "fig19_scaled_drag_vs_Fr_h"),
    (F.fig20_kn_gamman, "fig20_kn_gamman"),
    (F.table1, "table1_mu0_regime1"),
]


def check_written(paths, outdir, name):
    assert paths[0] == outdir / f"{name}.png" and paths[1] == outdir / f"{name}.pdf"
    assert paths[0].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert paths[1].read_bytes()[:5] == b"%PDF-"
    assert paths[0].stat().st_size > 5000      # something was drawn


@pytest.mark.parametrize("fn,name", TABLE_FIGURES, ids=[n for _, n in TABLE_FIGURES])
def test_table_figure_writes_png_and_pdf(table, tmp_path, fn, name):
    check_written(fn(table, tmp_path), tmp_path, name)


def test_table1_markdown_has_fitted_and_published(table, tmp_path):
    paths = F.table1(table, tmp_path)
    md = paths[2].read_text()
    assert "| 2 |" in md and "182.943" in md and "0.773" in md


def test_array_figures(tmp_path):
    v = np.geomspace(1e-3, 1.0, 12)
    e = 1 - 0.3 * v ** 0.2
    check_written(F.fig02_restitution(v, e, v, e + 0.001, tmp_path), tmp_path, "fig02_restitution")
    t = np.linspace(0, 40, 2000)
    force = 50 + 10 * np.sin(t * 7) + np.random.default_rng(0).normal(0, 5, t.size)
    check_written(F.fig04_force_trace(t, force, tmp_path, transient=5.0), tmp_path, "fig04_force_trace")


def test_missing_data_raise_nodata(table, tmp_path):
    only_I = table[table.system == "I"]
    with pytest.raises(F.NoData, match="system II"):
        F.fig16_drag_vs_Fr_depth(only_I, tmp_path)
    with pytest.raises(F.NoData, match="mu = 0.7"):
        F.fig05_drag_vs_Fr(table, tmp_path, mu=0.7)
    with pytest.raises(F.NoData, match="K_n or gamma_n"):
        F.fig20_kn_gamman(table[(table.kn == 2e5) & (table.gamman == 500.0)], tmp_path)
    # Fewer contact angles than Eq. 7's three parameters: not drawn (a study with a failed
    # pull left out of the table had two), not a crash of the figure rule.
    two = table[(table.system == "I") & (table.mu == 0.5)].dropna(subset=["theta"]).head(2)
    with pytest.raises(F.NoData, match="2 pulls for contact angles at mu = 0.5; the fit needs 3"):
        F.fig06_theta(two, tmp_path)
    assert not list(tmp_path.iterdir())


def test_fig07_coordination(table, tmp_path):
    pz = synth.pz_table(table)
    check_written(F.fig07_coordination(pz, tmp_path), tmp_path, "fig07_coordination_distribution")
    with pytest.raises(F.NoData):
        F.fig07_coordination(pz.iloc[:0], tmp_path)


def test_fig09_flow_field(tmp_path):
    panels = synth.flow_panels()
    check_written(F.fig09_flow_field(panels, tmp_path), tmp_path, "fig09_flow_field")
    with pytest.raises(F.NoData, match="snapshots"):
        F.fig09_flow_field([(2, 0.1, None)], tmp_path)


# --- the data behind each figure (<name>.csv): what is plotted, not just that a file exists


def data(paths):
    import pandas as pd
    csv = [p for p in paths if str(p).endswith(".csv")]
    assert len(csv) == 1, paths
    d = pd.read_csv(csv[0])
    assert len(d) > 0
    if csv[0].stem == "table1_mu0_regime1":     # the table as printed
        assert list(d.columns[:3]) == ["D/d", "a'' fit", "a'' paper"]
    else:
        assert list(d.columns[:7]) == F.DATA_COLUMNS
    return d


def points(d, panel="a"):
    return d[(d.panel == panel) & (d.kind == "points")]


@pytest.mark.parametrize("fn,name", TABLE_FIGURES, ids=[n for _, n in TABLE_FIGURES])
def test_every_figure_saves_its_data(table, tmp_path, fn, name):
    d = data(fn(table, tmp_path))
    assert (tmp_path / f"{name}.csv").is_file()
    if name != "table1_mu0_regime1":
        assert set(d.figure) == {name} and np.isfinite(d.x).all() and np.isfinite(d.y).all()


@pytest.mark.slow
def test_drag_vs_fr_plots_drag_against_fr(table, tmp_path):
    d = points(data(F.fig05_drag_vs_Fr(table, tmp_path)))
    rows = table[(table.system == "I") & (table.mu == 0.5) & (table.kn == synth.KN)]
    rows = rows[rows.D.isin([2.0, 4.0, 6.0])]          # the series with pulls at speed
    got = d.sort_values("y")[["x", "y"]].to_numpy()
    want = rows.sort_values("drag")[["Fr", "drag"]].to_numpy()
    assert np.allclose(got, want)
    curves = data(F.fig05_drag_vs_Fr(table, tmp_path))
    curves = curves[(curves.kind == "curve") & (curves.panel == "a")]
    assert sorted(curves.series.unique()) == ["fit, D = 2d", "fit, D = 4d", "fit, D = 6d"]
    assert len(curves) == 3 * 200


@pytest.mark.slow
def test_yield_collapse_plots_the_collapse_variable(table, tmp_path):
    # Fig. 13(b): F_Y / (f (D*+1)^phi) against D*+1 is 1 within the noise (2 %); with D
    # instead of D+1, or phi from another mu, it would not be. Fig. 17(b) the same in h.
    for fn, xcol in ((F.fig13_yield_vs_D, "D"), (F.fig17_yield_vs_h, "h")):
        d = data(fn(table, tmp_path))
        a, b = points(d, "a"), points(d, "b")
        assert np.allclose(np.sort(b.x), np.sort(a.x))
        assert abs(b.y.mean() - 1) < 0.02 and b.y.std() < 0.05, (xcol, b.y.describe())
        sys_ = "I" if xcol == "D" else "II"
        rows = table[(table.system == sys_) & (table.V == 0.01) & (table.kn == synth.KN)
                     & (table.gamman == synth.GAMMAN)]
        x = rows[xcol] + (1.0 if xcol == "D" else 0.0)
        assert np.allclose(np.sort(a.x), np.sort(x)) and np.allclose(np.sort(a.y), np.sort(rows.drag))


def test_scaled_drag_by_depth_collapses(table, tmp_path):
    # Fig. 19: F_drag / h^alpha_mu against Fr: at each Fr the depths fall together (2 % noise);
    # dividing by h^1 (or by (D+1)^phi) would leave them 3x apart between h = 25 and 65.
    d = points(data(F.fig19_scaled_drag_h(table, tmp_path)))
    alpha = F.fit_alpha(table)
    a = float(alpha[np.isclose(alpha.mu, 0.5) & np.isclose(alpha.kn, synth.KN)].alpha.iloc[0])
    rows = table[(table.system == "II") & (table.mu == 0.5) & (table.kn == synth.KN)
                 & (table.gamman == synth.GAMMAN) & table.h.isin([25.0, 45.0, 65.0])]   # depths pulled at speed
    assert np.allclose(np.sort(d.y), np.sort(rows.drag / rows.h ** a))
    spread = d.groupby(d.x.round(6)).y.agg(lambda v: v.std() / v.mean())
    assert spread.max() < 0.06, spread
    deep = points(data(F.fig19_scaled_drag_h(table, tmp_path, h_min=45)))
    assert sorted(deep.series.unique()) == ["h = 45d", "h = 65d"]


def test_scaled_drag_by_size_collapses(table, tmp_path):
    d = data(F.fig15_scaled_drag_D(table, tmp_path))
    for panel in "ab":
        p = points(d, panel)
        spread = p[p.x > 0.05].groupby(p.x.round(6)).y.agg(lambda v: v.std() / v.mean())
        assert spread.max() < 0.06, (panel, spread)


def test_alpha_figure_plots_both_alphas_near_the_truth(table, tmp_path):
    d = data(F.fig18_alpha(table, tmp_path))
    drag = d[d.series.str.startswith("drag, averaged")]
    fy = d[d.series.str.startswith("yield force")]
    assert list(drag.x) == [0.5] and abs(drag.y.iloc[0] - synth.alpha_true(0.5)) < 3 * drag.y_err.iloc[0]
    assert np.allclose(fy.y, synth.alpha_true(fy.x), atol=0.1)
    s = d[d.panel == "b"]
    assert abs(s.y.iloc[0] - 3.0) < 3 * s.y_err.iloc[0]


def test_contact_figures_plot_their_observables(table, tmp_path):
    rows = table[(table.system == "I") & (table.mu == 0.5) & (table.kn == synth.KN)]
    th = points(data(F.fig06_theta(table, tmp_path)))
    assert np.allclose(np.sort(th.y), np.sort(rows.theta)) and np.allclose(np.sort(th.x), np.sort(rows.Fr))
    ka = points(data(F.fig08_kappa(table, tmp_path)))
    assert np.allclose(np.sort(ka.y), np.sort(rows.kappa))


@pytest.mark.slow
def test_array_figures_save_their_data(tmp_path):
    v = np.geomspace(1e-3, 1.0, 12)
    d = data(F.fig02_restitution(v, 1 - v / 2, v, 1 - v / 3, tmp_path))
    assert np.allclose(d[d.series == "simulation"].y, 1 - v / 2)
    t = np.linspace(0, 40, 400)
    d = data(F.fig04_force_trace(t, 50 + np.sin(t), tmp_path, transient=5.0))
    cum = d[d.series == "cumulative average"]
    assert cum.x.min() >= 5.0 and abs(cum.y.iloc[-1] - np.mean(50 + np.sin(t[t >= 5]))) < 1e-6
    d = data(F.fig09_flow_field(synth.flow_panels(), tmp_path))
    assert {"u", "v"} <= set(d.columns) and sorted(d.panel.unique()) == ["a", "b", "c"]


def test_not_drawn_figure_has_an_empty_data_file(tmp_path):
    import pandas as pd
    F.draw_not_drawn(tmp_path, "fig19_scaled_drag_vs_Fr_h", "Fig. 19", "no data")
    d = pd.read_csv(tmp_path / "fig19_scaled_drag_vs_Fr_h.csv")
    assert list(d.columns) == F.DATA_COLUMNS and d.empty


# --- figures that show what was fitted: the errors the fit used, the formula as fitted ------

# Every figure that draws a fit (or fitted numbers), the errors drawn being those of the fit.
FITTED = ["fig05_drag_vs_Fr_mu0.5", "fig06_theta_vs_Fr", "fig08_kappa_vs_Fr", "fig10_drag_vs_Fr_mu0",
          "fig11_quasistatic_vs_mu", "fig12_yield_vs_mu", "fig13_yield_vs_D", "fig14_phi_vs_mu",
          "fig16_drag_vs_Fr_depth", "fig17_yield_vs_h", "fig18_alpha_and_sum_rule"]


def drawn(monkeypatch, fn, *args, **kw):
    """(paths, the figure as drawn): the figure is caught as _save closes it."""
    import matplotlib.pyplot as plt
    figs, close = [], plt.close
    monkeypatch.setattr(plt, "close", lambda fig=None: (figs.append(fig), close(fig)))
    return fn(*args, **kw), figs[-1]


def bars(ax):
    """[(x, y, half-length of each bar)] of every errorbar series drawn on ax."""
    from matplotlib.container import ErrorbarContainer
    out = []
    for c in ax.containers:
        if isinstance(c, ErrorbarContainer) and c.has_yerr:
            line, _, cols = c.lines
            seg = np.asarray(cols[0].get_segments())
            out.append((np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float),
                        (seg[:, 1, 1] - seg[:, 0, 1]) / 2))
    return out


def assert_errors_drawn(d, fig):
    """Every data series (points, or points joined by a line) of the figure's data file that has
    errors is drawn with those error bars on its panel's axes; returns how many."""
    checked = 0
    for (panel, series), p in d[d.kind.isin(["points", "line"])].groupby(["panel", "series"]):
        err = p.y_err.to_numpy(float)
        if not (np.isfinite(err) & (err > 0)).any():
            continue
        ax = fig.axes["abcdefgh".index(panel)]
        hits = [b for x, y, b in bars(ax) if len(x) == len(p) and np.allclose(x, p.x) and np.allclose(y, p.y)]
        assert hits, f"{series} (panel {panel}) has errors in the data file but none drawn"
        assert np.allclose(hits[0], np.nan_to_num(err)), series
        checked += 1
    return checked


@pytest.mark.parametrize("name", FITTED)
def test_fitted_figure_draws_the_errors(table, tmp_path, monkeypatch, name):
    fn = dict((n, f) for f, n in TABLE_FIGURES)[name]
    paths, fig = drawn(monkeypatch, fn, table, tmp_path)
    assert assert_errors_drawn(data(paths), fig) >= 1


def test_drag_figures_draw_the_errors_the_regime_fits_weighted_by(table, tmp_path, monkeypatch):
    # With replicate beds the regime fits weigh a point by the between-bed scatter pooled over
    # its series (table.pooled_drag_err), not by its own drag_err: the figure draws those.
    from analysis.core.table import pooled_drag_err
    t = table.copy()
    rng = np.random.default_rng(3)
    t["n_beds"] = 2
    t["drag_err_within"] = 0.5 * t.drag_err
    t["drag_err_between"] = t.drag_err * rng.uniform(0.2, 1.5, len(t))
    paths, fig = drawn(monkeypatch, F.fig05_drag_vs_Fr, t, tmp_path)
    d = points(data(paths))
    assert_errors_drawn(data(paths), fig)
    for D in (2.0, 4.0, 6.0):
        g = t[(t.system == "I") & (t.mu == 0.5) & (t.D == D) & (t.V > 0.01) & (t.kn == synth.KN)]
        g = g.assign(pooled=np.asarray(pooled_drag_err(g), float)).sort_values("Fr")
        got = d[d.series == f"D = {D:g}d"].sort_values("x").iloc[1:]     # the yield pull, not fitted, aside
        assert np.allclose(got.x, g.Fr) and np.allclose(got.y_err, g.pooled)
        assert not np.allclose(got.y_err, g.drag_err)


def kappa_table(k1, depths=(14.0,)):
    """System I kappa at D = 2 and 3 over one Fr grid, kappa = 0.95 + k1 Fr, per depth."""
    import pandas as pd
    rows = []
    for h in depths:
        for D in (2.0, 3.0):
            for i, Fr in enumerate([0.5, 1, 2, 3, 5, 7, 10, 15]):
                rows.append(dict(system="I", D=D, h=h, mu=0.5, kn=2e5, gamman=800.0, V=Fr, Fr=Fr,
                                 kappa=0.95 + k1 * Fr + 0.01 * np.sin(7 * i + D + h), kappa_err=0.02 + 0.01 * Fr))
    return pd.DataFrame(rows)


def test_kappa_figure_writes_the_fitted_line_with_its_sign(tmp_path, monkeypatch):
    for k1, sign in ((-0.021, "−"), (0.185, "+")):
        paths, fig = drawn(monkeypatch, F.fig08_kappa, kappa_table(k1), tmp_path)
        d = data(paths)
        line = d[d.kind == "curve"].series.unique()
        assert len(line) == 1 and re.fullmatch(rf"kappa = 0\.9\d\d {re.escape(sign)} 0\.\d\d\d Fr", line[0]), line
        legend = " ".join(t.get_text() for t in fig.axes[0].get_legend().get_texts())
        assert "+ -" not in legend and "+-" not in legend and sign in legend, legend
        assert "χ²/dof" in legend                      # the fit's goodness beside it


def test_kappa_figure_lists_each_point_once(tmp_path):
    # One D pulled at two depths (two beds' series: say two sweeps at the same D): each point
    # is drawn once, in its own series, never twice in one.
    d = points(data(F.fig08_kappa(kappa_table(-0.02, depths=(14.0, 28.0)), tmp_path)))
    assert not d.duplicated(["series", "x"]).any(), d[d.duplicated(["series", "x"], keep=False)]
    assert sorted(d.series.unique()) == ["D = 2d, h = 14d", "D = 2d, h = 28d", "D = 3d, h = 14d", "D = 3d, h = 28d"]
    one = points(data(F.fig08_kappa(kappa_table(-0.02), tmp_path)))
    assert sorted(one.series.unique()) == ["D = 2d", "D = 3d"] and not one.duplicated(["series", "x"]).any()


def test_kappa_error_of_a_point_combines_its_beds():
    # The point table's kappa_err, which the kappa fit and Fig. 8 use: both beds' errors and
    # their scatter (as drag_err), not the first bed's error alone.
    import pandas as pd

    from analysis.core.table import combine_beds
    runs = pd.DataFrame([dict(system="I", D=2.0, h=14.0, mu=0.5, kn=2e5, gamman=800.0, V=1.0, Fr=1.0,
                              drag=100.0 + s, drag_err=2.0, n_contacts=9.0, theta=1.5, theta_err=0.01, Z=3.0,
                              kappa=k, kappa_err=e, seed=s, run=f"pulls/D~2/seed~{s}/Fr~1")
                         for s, k, e in ((1, 0.98, 0.019), (2, 0.97, 0.067))])
    p = combine_beds(runs)
    w = (0.019 ** 2 + 0.067 ** 2) / 2
    assert len(p) == 1 and np.isclose(p.kappa_err.iloc[0], np.sqrt(max(np.var([0.98, 0.97], ddof=1), w) / 2))
