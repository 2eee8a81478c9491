"""Every figure function writes a PNG and a PDF from a small synthetic table."""
import numpy as np
import pytest
import synth

from analysis import figures as F

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
