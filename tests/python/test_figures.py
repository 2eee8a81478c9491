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
