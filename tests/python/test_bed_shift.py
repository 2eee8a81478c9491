"""A bed's shift shared by every speed pulled through it (analysis.core.bed_shift) and the regime
tests' generalized least squares on it: the estimator against synthetic studies whose shift is
known, the covariance against its formula, the fits against an independent solver, and a test
that fails when the fits are made blind to the shift (their χ²/dof then falls to the independent
part's share, as the box40-deep rung's lines read 0.6)."""
import numpy as np
import pandas as pd
import pytest

from analysis.core.bed_shift import SHARED_CAP, covariance, shift_r2
from analysis.core.table import combine_beds
from analysis.regime_tests.regime_fits import fit_line, fit_quadratic, wls
from analysis.regime_tests.regime_power import Calibration

FR = np.array([0.5, 0.75, 1.0, 1.5, 2.0, 3.0])
SHIFT, OWN = 0.025, 0.02   # a bed's relative shift and a pull's own relative noise (the rung's size)


def study(rng, fr=FR, beds=3, shift=SHIFT, own=OWN, curve=lambda f: 1300 + 120 * f):
    """(points, drags) of one synthetic study: drags (speeds, beds) of a curve times (1 + the bed's
    shift) times (1 + each pull's own noise)."""
    beta = shift * rng.standard_normal(beds)
    y = curve(fr)[:, None] * (1 + beta[None, :]) * (1 + own * rng.standard_normal((len(fr), beds)))
    return y


def test_the_shift_estimate_is_unbiased_and_uses_no_pulls_error():
    # 400 studies of 13 speeds and 3 beds: the mean of σ_β² within 20 % of the truth (its estimate
    # rests on about two dof, so one study's scatters by about 100 %; the mean's by 5 %). Mutation
    # tried: dividing by k instead of k - 1 reads 0.67 of the truth.
    rng = np.random.default_rng(7)
    fr = np.linspace(1, 15, 13)
    est = [shift_r2(study(rng, fr)) for _ in range(400)]
    assert np.mean(est) == pytest.approx(SHIFT ** 2, rel=0.2)
    none = [shift_r2(study(rng, fr, shift=0.0)) for _ in range(400)]
    assert np.mean(none) < 0.15 * SHIFT ** 2     # no shift: near 0 (held at 0, so a little above)


def test_a_point_with_fewer_beds_shares_only_the_ones_it_has():
    Y = np.array([[1.0, np.nan, 1.1], [2.0, 2.4, 2.2], [3.0, 3.3, np.nan]])
    # pairs sharing two beds: (0, 1) over beds 0 and 2; (1, 2) over beds 0 and 1; (0, 2) share one
    r = lambda v: v / v.mean() - 1
    want = (np.sum(r(np.array([1.0, 1.1])) * r(np.array([2.0, 2.2])))
            + np.sum(r(np.array([2.0, 2.4])) * r(np.array([3.0, 3.3])))) / 2
    assert shift_r2(Y) == pytest.approx(max(0.0, want))
    assert np.isnan(shift_r2(np.array([[1.0, np.nan], [np.nan, 2.0]])))


def points(y, err, seeds, r2):
    return pd.DataFrame({"Fr": np.arange(len(y), dtype=float), "drag": y, "drag_err": err,
                         "seeds": seeds, "drag_shift_r2": r2})


def test_the_covariance_is_the_formula_and_held_below_each_points_variance():
    p = points([100.0, 200.0, 300.0], [5.0, 8.0, 30.0], ["1;3", "1;2;3", "2"], 1e-3)
    C = covariance(p, "drag", "drag_err")   # no split of the errors: each point's own on the diagonal
    assert np.diag(C) == pytest.approx([25.0, 64.0, 900.0])
    assert C[0, 1] == pytest.approx(1e-3 * 100 * 200 * 2 / (2 * 3))
    assert C[1, 2] == pytest.approx(1e-3 * 200 * 300 * 1 / (3 * 1))
    assert C[0, 2] == 0.0                         # no bed in common
    assert np.all(np.linalg.eigvalsh(C) > 0)
    big = covariance(p.assign(drag_shift_r2=1.0), "drag", "drag_err")   # a shift larger than the errors allow
    held = SHARED_CAP * min(2 * 25 / 100 ** 2, 3 * 64 / 200 ** 2, 1 * 900 / 300 ** 2)
    assert big[0, 1] == pytest.approx(held * 100 * 200 * 2 / 6)
    assert np.all(np.linalg.eigvalsh(big) > 0)
    # A table made before the shift, or a series without one: the errors alone
    assert np.array_equal(covariance(p.drop(columns="drag_shift_r2"), "drag", "drag_err"), np.diag([25.0, 64, 900]))
    assert np.array_equal(covariance(p.assign(drag_shift_r2=np.nan), "drag", "drag_err"), np.diag([25.0, 64, 900]))


def test_the_fits_are_generalized_least_squares():
    # Against numpy's solution of the whitened problem, and a covariance that is diagonal gives
    # the standard errors' fit.
    rng = np.random.default_rng(3)
    x = FR
    y = 1300 + 120 * x + 10 * rng.standard_normal(len(x))
    A = rng.standard_normal((len(x), len(x)))
    C = A @ A.T + np.eye(len(x)) * 50
    X = np.column_stack([np.ones_like(x), x, x * x])
    Ci = np.linalg.inv(C)
    beta = np.linalg.solve(X.T @ Ci @ X, X.T @ Ci @ y)
    r = y - X @ beta
    q = fit_quadratic(x, y, C)
    assert [q["a"], q["b"], q["c"]] == pytest.approx(beta, rel=1e-8)
    assert q["chi2"] == pytest.approx(r @ Ci @ r, rel=1e-8)
    assert q["c_err"] == pytest.approx(np.sqrt(np.linalg.inv(X.T @ Ci @ X)[2, 2]), rel=1e-8)
    s = 5 + rng.random(len(x))
    assert fit_line(x, y, np.diag(s ** 2))["chi2"] == pytest.approx(fit_line(x, y, s)["chi2"], rel=1e-10)
    assert wls(X, y, np.diag(s ** 2))[1] == pytest.approx(wls(X, y, s)[1], rel=1e-10)


def table_of(rng, fr=FR, curve=lambda f: 1300 + 120 * f, beds=3):
    """combine_beds's point table of one synthetic study in the workflow's layout (a pull's own
    error its true one, sqrt(shift² + own²) of its drag: the shift is in a pull's error too, as in
    a pull's time series)."""
    y = study(rng, fr, beds, curve=curve)
    rows = [{"system": "I", "D": 3.0, "mu": 0.5, "kn": 2e6, "gamman": 3154.8, "V": f, "Fr": f,
             "drag": y[i, b], "drag_err": np.hypot(SHIFT, OWN) * curve(f), "drag_dof": 10.0,
             "run": f"pulls/system~I/D~3/seed~{b + 1}/Fr~{f:g}", "seed": float(b + 1)}
            for i, f in enumerate(fr) for b in range(beds)]
    return combine_beds(pd.DataFrame(rows))


def test_the_tests_see_the_scatter_the_errors_promise_only_with_the_shift():
    # 300 studies of a line over the rung's 14 speeds with its shift: the line's χ²/dof averages
    # about 0.75 with the table's covariance (1 would need σ_β² exactly; estimated on three beds it
    # is often low, median 0.6 of the truth) and the independent part's share, OWN²/(SHIFT² + OWN²)
    # = 0.39, when the fit is blind to the shift (its errors alone): 0.34 measured.
    rng = np.random.default_rng(11)
    fr = np.array([0.5, 0.75, 1, 1.5, 2, 3, 4, 5, 6, 7, 8, 10, 12, 15.0])
    with_shift, blind = [], []
    for _ in range(300):
        t = table_of(rng, fr)
        x, y = t.Fr.to_numpy(float), t.drag.to_numpy(float)
        with_shift.append(fit_line(x, y, covariance(t, "drag", "drag_err"))["chi2"] / (len(x) - 2))
        blind.append(fit_line(x, y, t.drag_err.to_numpy(float))["chi2"] / (len(x) - 2))
    assert 0.62 < np.mean(with_shift) < 1.1
    assert np.mean(blind) < 0.45


def test_the_shift_gives_regime_one_its_power():
    # A plateau to Fr 1 then a line, with the rung's shift: the calibrated power against a plateau
    # of the paper's size is higher with the covariance than with the errors alone, whose copies
    # carry noise the real curve does not have between its speeds.
    rng = np.random.default_rng(5)
    t = table_of(rng, curve=lambda f: 1400 + 150 * np.maximum(f - 1, 0)).assign(drag_shift_r2=SHIFT ** 2)
    x, y = t.Fr.to_numpy(float), t.drag.to_numpy(float)
    C = covariance(t, "drag", "drag_err")   # the shift known: its estimate is tested above
    cal = Calibration("regime1", x, y, C, n_sim=600)
    blind = Calibration("regime1", x, y, t.drag_err.to_numpy(float), n_sim=600)
    assert cal.power > blind.power + 0.1
    assert 0.02 < cal.false_positive_rate < 0.09


def test_the_regime_tests_take_the_tables_shift():
    # Wiring: regime_tests reads the table's covariance (Δχ² as the fit on it gives), and a table
    # made before the shift reads its errors alone. Mutation tried: regime_tests passing g[err]:
    # its regime I Δχ² is then the blind one.
    from analysis.regime_tests.regime_fits import profile_plateau_line
    from analysis.regime_tests.regime_tests import regime_tests
    rng = np.random.default_rng(2)
    t = table_of(rng, curve=lambda f: 1400 + 150 * np.maximum(f - 1, 0)).assign(h=np.nan)
    x, y = t.Fr.to_numpy(float), t.drag.to_numpy(float)
    steady = lambda tab: regime_tests(tab, n_sim=100, averaging="steady").set_index("test").loc["regime1"]
    C = covariance(t, "drag", "drag_err")
    want = profile_plateau_line(x, y, C)["chi2"] - fit_line(x, y, C)["chi2"]
    assert steady(t).delta_chi2 == pytest.approx(want, rel=1e-6)
    s = t.drag_err.to_numpy(float)
    blind = profile_plateau_line(x, y, s)["chi2"] - fit_line(x, y, s)["chi2"]
    assert steady(t.drop(columns="drag_shift_r2")).delta_chi2 == pytest.approx(blind, rel=1e-6)
    assert abs(want - blind) > 0.1


def test_the_three_regime_fit_takes_the_tables_shift():
    # Wiring: fitset.run_fits fits the drag curve on the table's covariance (its χ² is rᵀ C⁻¹ r of
    # the fitted curve), and a table made before the shift on the pooled errors, as before.
    # Mutation tried: run_fits passing pooled_drag_err again: the first assertion fails.
    from analysis.core.physics import froude_speed
    from analysis.core.point_errors import pooled_drag_err
    from analysis.fits.fitset import run_fits
    from analysis.fits.regimes import regime_curve
    fr = np.array([0.25, 0.5, 0.75, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0])
    t = table_of(np.random.default_rng(3), fr=fr, curve=lambda f: 1300 + 150 * np.maximum(f - 0.8, 0) + 4 * f ** 2)
    t = t.assign(h=14.0, yield_pull=False, n_contacts=np.nan, theta=np.nan, Z=np.nan, kappa=np.nan,
                 V=froude_speed(t.Fr, 3.0))
    t = t.sort_values("Fr").reset_index(drop=True)

    def chi2(tab, errors):
        fit = run_fits(tab, n_boot=0).regimes[("D", 0.5, 3.0)]
        r = tab.drag.to_numpy(float) - regime_curve(tab.Fr.to_numpy(float), **{k: fit[k].value for k in fit.params})
        C = np.asarray(errors, float)
        want = r @ np.linalg.solve(C, r) if C.ndim == 2 else np.sum((r / C) ** 2)
        return fit.meta["goodness"]["chi2"], want

    got, want = chi2(t, covariance(t, "drag", "drag_err"))
    assert got == pytest.approx(want, rel=1e-6)
    got, want = chi2(t.drop(columns="drag_shift_r2"), pooled_drag_err(t))
    assert got == pytest.approx(want, rel=1e-6)
