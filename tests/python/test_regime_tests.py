"""Claim (a)'s regime tests (analysis.regime_tests.regime_fits, regime_power, regime_tests, regime_figure): each fit
against an independent solver or an exact curve, the power calibration against curves whose answer
is known, and a test that fails when the test is made blind (a knee fitted without asking whether a
line fits as well has no power)."""
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy.optimize import lsq_linear
from scipy.stats import norm

from analysis.cli import main
from analysis.core.physics import froude, froude_speed
from analysis.regime_tests.regime_fits import (
    PaperShape,
    fit_line,
    fit_paper_shape,
    fit_quadratic,
    fr1_grid,
    fr2_grid,
    paper_curve,
    paper_design,
    paper_least_design,
    plateau_curve,
    profile_paper_shape,
    profile_plateau_line,
)
from analysis.regime_tests.regime_power import Calibration, verdict
from analysis.regime_tests.regime_tests import COLUMNS, averagings, regime_tests, series

ROOT = Path(__file__).resolve().parents[2]
# The crossover rung's 14 speeds on 1 <= Fr <= 10, and its errors there (about 2-6 % of the drag).
FR = np.array([1, 1.5, 2, 3, 3.5, 4, 4.5, 5, 5.5, 6, 6.5, 7, 8, 10.0])
ERR = np.array([23, 27, 27, 26, 45, 56, 70, 42, 54, 67, 79, 61, 105, 82.0])


def paper_shaped(fr, a=800.0, b=95.0, b2=30.0, fr2=5.0):
    return paper_curve(fr, a=a, b=b, b2=b2, Fr2=fr2)


def line(fr, a=800.0, b=95.0):
    return a + b * np.asarray(fr, float)


# --- the fits --------------------------------------------------------------------


def test_line_and_quadratic_are_numpys_weighted_polyfit():
    rng = np.random.default_rng(3)
    y = paper_shaped(FR) + ERR * rng.standard_normal(len(FR))
    for fit, deg in ((fit_line(FR, y, ERR), 1), (fit_quadratic(FR, y, ERR), 2)):
        coef, cov = np.polyfit(FR, y, deg, w=1 / ERR, cov="unscaled")
        names = ["c", "b", "a"][-deg - 1:]
        for name, value in zip(names, coef):
            assert fit[name] == pytest.approx(value, rel=1e-9)
        assert fit["chi2"] == pytest.approx(np.sum(((y - np.polyval(coef, FR)) / ERR) ** 2), rel=1e-9)
        assert fit["dof"] == len(FR) - deg - 1
        if deg == 2:
            assert fit["c_err"] == pytest.approx(math.sqrt(cov[0, 0]), rel=1e-9)
        else:
            assert fit["b_err"] == pytest.approx(math.sqrt(cov[0, 0]), rel=1e-9)


def test_quadratics_delta_chi2_is_minus_its_z_squared():
    rng = np.random.default_rng(4)
    y = line(FR) + ERR * rng.standard_normal(len(FR))
    q, lin = fit_quadratic(FR, y, ERR), fit_line(FR, y, ERR)
    assert q["chi2"] - lin["chi2"] == pytest.approx(-(q["c"] / q["c_err"]) ** 2, rel=1e-8)


def test_noiseless_curves_are_recovered_exactly():
    y = paper_shaped(FR)
    fixed = fit_paper_shape(FR, y, ERR)
    for k, v in (("a", 800.0), ("b", 95.0), ("b2", 30.0), ("a2", 800 + 95 * 5 - 30 * 25)):
        assert fixed[k] == pytest.approx(v, rel=1e-8)
    assert fixed["chi2"] < 1e-8 and not fixed["held"]
    X = paper_design(FR, [5.0])[0] / ERR[:, None]
    assert fixed["b2_err"] == pytest.approx(math.sqrt(np.linalg.inv(X.T @ X)[2, 2]), rel=1e-8)
    grid = fr2_grid(FR)
    true = grid[37]   # on the profiled grid, away from the paper's 5
    free = profile_paper_shape(FR, paper_shaped(FR, fr2=true), ERR)
    assert free["Fr2"] == true and free["b2"] == pytest.approx(30.0, rel=1e-8) and free["chi2"] < 1e-8
    assert free["Fr2_lo"] <= true <= free["Fr2_hi"]
    fr = np.array([0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 2.5, 3.0])
    plateau = profile_plateau_line(fr, plateau_curve(fr, a=840.0, b=110.0, Fr1=1.0), np.full(len(fr), 20.0))
    assert plateau["Fr1"] == 1.0 and plateau["chi2"] < 1e-8
    assert plateau["a"] == pytest.approx(840.0, rel=1e-8) and plateau["b"] == pytest.approx(110.0, rel=1e-8)


def test_the_constrained_paper_shape_is_scipys_bounded_least_squares():
    """Where the drag flattens past Fr₂ the paper's shape is held to its least rise, b' = b / (Fr₂ +
    Fr_end); an independent solver (b' = b / (Fr₂ + Fr_end) + t, t ≥ 0, scipy's lsq_linear) agrees."""
    rng = np.random.default_rng(5)
    for flat in (True, False):
        truth = np.where(FR < 5, line(FR), line(5.0)) if flat else paper_shaped(FR)
        y = truth + ERR * rng.standard_normal(len(FR)) * 0.3
        fit = fit_paper_shape(FR, y, ERR)
        tied = paper_least_design(FR, [5.0], FR.max())[0]
        A = np.column_stack([tied, paper_design(FR, [5.0])[0][:, 2]]) / ERR[:, None]
        res = lsq_linear(A, y / ERR, bounds=([-np.inf, -np.inf, 0.0], np.inf), tol=1e-14, method="bvls")
        a, b, t = res.x
        assert fit["chi2"] == pytest.approx(2 * res.cost, rel=1e-7, abs=1e-9)
        assert (fit["a"], fit["b"], fit["b2"]) == pytest.approx((a, b, b / (5 + FR.max()) + t), rel=1e-7)
        assert fit["held"] == flat


def test_the_fr2_profile_interval_is_where_chi2_is_within_one():
    rng = np.random.default_rng(6)
    y = paper_shaped(FR, b2=20.0) + ERR * rng.standard_normal(len(FR))
    free = profile_paper_shape(FR, y, ERR)
    grid, prof = free["grid"], free["profile"]
    fam = PaperShape(FR, ERR, grid)
    assert np.allclose(fam.fit_all(y)[1][:, 0], prof)
    inside = (grid >= free["Fr2_lo"]) & (grid <= free["Fr2_hi"])
    assert prof.min() == pytest.approx(free["chi2"]) and free["chi2"] == pytest.approx(min(prof))
    assert prof[grid == free["Fr2_lo"]][0] <= free["chi2"] + 1 and prof[grid == free["Fr2_hi"]][0] <= free["chi2"] + 1
    k_lo, k_hi = np.flatnonzero(inside)[[0, -1]]
    assert k_lo == 0 or prof[k_lo - 1] > free["chi2"] + 1
    assert k_hi == len(grid) - 1 or prof[k_hi + 1] > free["chi2"] + 1
    assert grid[0] == 1.5 and grid[-1] == 8.0 and 5.0 in grid   # 2 speeds on each side, the joint's counted
    assert fr1_grid(FR)[0] == 1.0


# --- power ----------------------------------------------------------------------------


SMALL = ERR / 4   # the rung's errors over 16 times the beds


def test_strong_curvature_small_noise_is_detected():
    y = paper_shaped(FR, b2=30.0)   # the mean curve: the calibration adds the noise
    for test in ("quadratic", "paper_fr2_5", "paper_fr2_free"):
        cal = Calibration(test, FR, y, SMALL, n_sim=1000, seed=1)
        assert cal.power > 0.9, test
        assert cal.power_best_fit > 0.9, test
        assert cal.p < 0.05, test   # the noiseless curve itself is far past the threshold
        assert verdict("X", "…", cal, "Y").startswith("X shown")


def test_a_line_is_detected_at_the_level_not_more():
    rng = np.random.default_rng(7)
    y = line(FR) + ERR * rng.standard_normal(len(FR))
    for test in ("quadratic", "paper_fr2_5", "paper_fr2_free"):
        cal = Calibration(test, FR, y, ERR, n_sim=2000, seed=2)
        assert cal.false_positive_rate <= 0.08, test
        assert cal.false_positive_rate >= 0.02, test   # a threshold that rejects nothing fails too
    # Against the errors alone c / σ_c is a standard normal: its 95th percentile is 1.645.
    assert Calibration("quadratic", FR, y, ERR, n_sim=2000, seed=3).threshold == pytest.approx(1.645, abs=0.12)
    fr = np.array([0.5, 1, 1.5, 2, 2.5, 3.0])
    cal = Calibration("regime1", fr, line(fr) + 20 * rng.standard_normal(len(fr)), np.full(6, 20.0), n_sim=2000)
    assert cal.false_positive_rate <= 0.08


def test_a_blind_test_fails_where_the_real_one_sees():
    """A test made blind, one that fits the knee Fr₂ and asks only whether the paper's shape fits (χ²
    alone, never against the line), passes lines as often as curves: its power is its false-positive
    rate. The real test, the same fit's Δχ² against the line, sees the same curve almost always."""
    y = paper_shaped(FR, b2=30.0)
    real = Calibration("paper_fr2_free", FR, y, SMALL, n_sim=1000, seed=4)
    blind = Calibration("blind_fr2_only", FR, y, SMALL, n_sim=1000, seed=4)
    assert real.power > 0.9
    assert blind.power < 0.2 and abs(blind.power - blind.false_positive_rate) < 0.1
    assert real.power - blind.power > 0.7


def test_beds_for_80_percent_match_the_quadratics_closed_form():
    """c / σ_c is normal with unit variance about μ = c_alt / σ_c, μ growing as √beds: 80 % power
    at beds = ((z_0.95 + z_0.80) / μ)²."""
    cal = Calibration("quadratic", FR, line(FR), ERR, n_sim=2000, seed=5)
    quad = fit_quadratic(FR, cal.alt, ERR)
    mu = quad["c"] / quad["c_err"]
    assert cal.power == pytest.approx(norm.cdf(mu - norm.isf(0.05)), abs=0.04)
    k = cal.beds_for()
    assert k == pytest.approx(((norm.isf(0.05) + norm.isf(0.2)) / mu) ** 2, rel=0.15)
    assert cal.power_at(k) >= 0.8 and cal.power_at(k / 1.3) < 0.8


def test_verdicts_never_call_unseen_what_the_data_cannot_tell():
    rng = np.random.default_rng(8)
    noisy = line(FR) + 4 * ERR * rng.standard_normal(len(FR))
    cal = Calibration("paper_fr2_5", FR, noisy, 4 * ERR, n_sim=1000, seed=6)
    assert cal.power < 0.5
    text = verdict("a quadratic from Fr ≈ 5", "Δχ² = 0", cal, "a paper-sized quadratic", beds=3)
    assert text.startswith("these data cannot tell") and "as many beds would" in text
    assert 4 < cal.beds_for() < 40   # errors 4× the rung's: about 16× its beds
    exact = Calibration("paper_fr2_5", FR, line(FR), SMALL, n_sim=1000, seed=7)
    assert exact.power > 0.9 and exact.p > 0.16 and exact.excluded_sigma[0] > 3
    assert verdict("a quadratic", "Δχ² = 0", exact, "a paper-sized quadratic").startswith("a line preferred")


def test_a_shape_that_fits_worse_than_the_line_is_never_shown():
    """The paper's shape does not contain the line, so its Δχ² against the line can be positive and
    still lie in the lines' upper tail (their copies fit the shape worse still): the line is then
    strained, but the shape describes the data no better. Such a curve: one that bends over the
    whole range (a parabola about Fr 8), not from a knee at Fr 5; the quadratic test sees it."""
    fr, err = np.array([1.5, 2, 3, 4, 5, 6, 7, 8, 10, 12, 15.0]), np.full(11, 50.0)
    y = line(fr, a=1200.0, b=185.0) + 3 * (fr - 8) ** 2
    cal = Calibration("paper_fr2_5", fr, y, err, n_sim=1000, seed=11)
    worse = fit_paper_shape(fr, y, err)["chi2"] > fit_line(fr, y, err)["chi2"]
    assert worse and cal.p < 0.05
    text = verdict("a quadratic from Fr ≈ 5", "Δχ² = +3.3", cal, "a paper-sized quadratic", fits_worse=worse)
    assert text.startswith("not shown") and " shown (" not in text
    assert verdict("X", "…", cal, "Y").startswith("X shown")   # were the shape to fit better
    assert Calibration("quadratic", fr, y, err, n_sim=1000, seed=11).p < 0.05


# --- a table, the rung, the command --------------------------------------------------


def _table(with_cumulative=True, Ds=(3.0,)):
    rng = np.random.default_rng(9)
    rows = []
    for D in Ds:
        for fr in [0.02, 0.5, 1, 1.5, 2, 3, 4, 5, 6, 7, 8, 10, 12, 15]:
            drag = 300 * D + (95 * D / 3) * fr + 3 * max(fr - 5, 0) ** 2
            err = 0.04 * drag
            rows.append({"system": "I", "D": D, "h": 14.0, "mu": 0.5, "kn": 2e6, "gamman": 3154.8,
                         "V": froude_speed(fr, D), "Fr": float(froude(froude_speed(fr, D), D)),
                         "drag": drag + err * rng.standard_normal(), "drag_err": err, "n_contacts": 10.0,
                         "theta": 1.4, "Z": 2.5, "kappa": 0.7, "run": f"D{D}/Fr{fr}", "yield_pull": fr == 0.02,
                         "n_beds": 2, "drag_cumulative_box": drag * 1.02, "drag_cumulative_box_err": err})
    df = pd.DataFrame(rows)
    return df if with_cumulative else df.drop(columns=["drag_cumulative_box", "drag_cumulative_box_err"])


def test_series_are_split_by_diameter_and_leave_the_yield_pulls_out():
    table = _table(Ds=(2.0, 3.0))
    found = list(series(table))
    assert [keys["D"] for keys, _ in found] == [2.0, 3.0]
    assert all(len(g) == 13 and g.Fr.min() == pytest.approx(0.5) for _, g in found)
    assert [a[0] for a in averagings(table)] == ["steady", "cumulative"]
    assert [a[0] for a in averagings(_table(with_cumulative=False))] == ["steady"]


def test_the_command_writes_one_row_per_averaging_range_and_test_and_a_figure(tmp_path, capsys):
    table = tmp_path / "table.csv"
    _table().to_csv(table, index=False)
    assert main(["regime-tests", str(table), "--out", str(tmp_path / "out"), "--n-sim", "200"]) == 0
    out = pd.read_csv(tmp_path / "out" / "regime_tests.csv")
    assert list(out.columns) == COLUMNS
    assert len(out) == 2 * (2 * 4 + 1)   # averaging, (2 ranges x 4 tests + regime I)
    assert set(out.averaging) == {"steady", "cumulative"}
    assert (out[out.test == "regime1"].n_points == 5).all()   # Fr 0.5-3: the yield pull at 0.02 left out
    assert (out[(out.test == "line") & (out.fr_high == 10)].n_points == 10).all()
    tested = out[out.test != "line"]
    assert tested.verdict.notna().all() and tested.p.between(0, 1).all() and tested.power.between(0, 1).all()
    stem = tmp_path / "out" / "regime_tests_I_D3_mu0.5_kn2e6"
    assert Path(f"{stem}.png").stat().st_size > 1000
    drawn = pd.read_csv(f"{stem}.csv")
    assert {"steady: points", "cumulative: quadratic residual / error"} <= set(drawn.series)
    assert "paper_fr2_5" in capsys.readouterr().out
    assert not list((tmp_path / "out").glob("*.tmp"))
    assert main(["regime-tests", str(tmp_path / "missing.csv"), "--out", str(tmp_path / "out")]) == 2


def test_the_rung_gives_the_issues_numbers():
    """The numbers issue 72 quoted for crossover-k2e6-box40-full (D = 3, μ = 0.5, steady drag):
    one line on 1 ≤ Fr ≤ 10 χ² = 5.3 for 12 dof, c = 0.7 ± 2.0, the paper's shape 4.3 for 11;
    on Fr ≤ 15 c = 2.3 ± 1.4 and the paper's shape Δχ² = -4.5. The issue weighed each point by its
    error alone: the table without the beds' shift (analysis.core.bed_shift) is read that way."""
    df = pd.read_csv(ROOT / "results/reproduction/crossover-k2e6-box40-full/table.csv")
    df = df.drop(columns=[c for c in df.columns if c.endswith("_shift_r2")])
    out = regime_tests(df, n_sim=200).set_index(["fr_high", "test"])
    assert (out.loc[(10, "line"), "chi2"], out.loc[(10, "line"), "dof"]) == (pytest.approx(5.31, abs=0.01), 12)
    assert (out.loc[(10, "quadratic"), "coef_value"], out.loc[(10, "quadratic"), "coef_err"]) == \
        (pytest.approx(0.73, abs=0.01), pytest.approx(2.02, abs=0.01))
    assert (out.loc[(10, "paper_fr2_5"), "chi2"], out.loc[(10, "paper_fr2_5"), "dof"]) == \
        (pytest.approx(4.29, abs=0.01), 11)
    assert (out.loc[(15, "quadratic"), "coef_value"], out.loc[(15, "quadratic"), "coef_err"]) == \
        (pytest.approx(2.31, abs=0.01), pytest.approx(1.40, abs=0.01))
    assert out.loc[(15, "paper_fr2_5"), "delta_chi2"] == pytest.approx(-4.48, abs=0.01)


def test_each_averaging_is_tested_on_its_own_drag_and_labelled(tmp_path, capsys):
    """A table whose steady drag is a line and whose cumulative average is the paper's shape (a
    quadratic from Fr 5): each averaging's tests see its own curve, and every output says which."""
    fr = np.array([0.5, 1, 1.5, 2, 3, 4, 5, 6, 7, 8, 10, 12, 15])
    df = _table().iloc[1:].reset_index(drop=True)          # Fr as listed, no yield pull
    assert np.allclose(df.Fr, fr)
    df["drag"], df["drag_err"] = line(fr, a=900.0), 10.0
    df["drag_cumulative_box"], df["drag_cumulative_box_err"] = paper_shaped(fr, a=900.0, b2=8.0), 10.0
    table = tmp_path / "table.csv"
    df.to_csv(table, index=False)
    assert main(["regime-tests", str(table), "--out", str(tmp_path / "both"), "--n-sim", "200"]) == 0
    out = pd.read_csv(tmp_path / "both" / "regime_tests.csv").set_index(["averaging", "fr_high", "test"])
    for test in ("quadratic", "paper_fr2_5"):
        assert out.loc[("cumulative", 15, test), "verdict"].startswith("a quadratic"), test
        assert " shown (" in out.loc[("cumulative", 15, test), "verdict"]
        assert out.loc[("steady", 15, test), "verdict"].startswith("a line preferred"), test
    quad = out.loc[("cumulative", 15, "quadratic")]
    assert quad.coef_value > 3 * quad.coef_err
    assert abs(out.loc[("steady", 15, "quadratic"), "coef_value"]) < 1e-6
    md = (tmp_path / "both" / "regime_tests.md").read_text()
    steady, cumulative = md.split("## steady averaging")[1].split("## cumulative averaging")
    assert "drag_cumulative_box" in cumulative and "Fig. 4" in cumulative
    assert "a quadratic rise shown" in cumulative and "a quadratic rise shown" not in steady
    assert "a line preferred" in steady
    # One averaging alone: only its rows and its column of the figure
    assert main(["regime-tests", str(table), "--out", str(tmp_path / "cum"), "--n-sim", "200",
                 "--averaging", "cumulative"]) == 0
    assert set(pd.read_csv(tmp_path / "cum" / "regime_tests.csv").averaging) == {"cumulative"}
    drawn = pd.read_csv(tmp_path / "cum" / "regime_tests_I_D3_mu0.5_kn2e6.csv")
    assert drawn.series.str.startswith("cumulative: ").all()
    assert "## steady averaging" not in (tmp_path / "cum" / "regime_tests.md").read_text()
    # Asked of a table made before the cumulative average: refused, naming its columns
    df.drop(columns=["drag_cumulative_box", "drag_cumulative_box_err"]).to_csv(table, index=False)
    capsys.readouterr()
    assert main(["regime-tests", str(table), "--out", str(tmp_path / "old"), "--averaging", "cumulative"]) == 2
    assert "drag_cumulative_box" in capsys.readouterr().err
