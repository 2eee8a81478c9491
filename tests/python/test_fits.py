"""Fits of theta, kappa, the yield-force exponents and the scaling law."""
import json
from pathlib import Path

import numpy as np
import pytest
import synth

from analysis.core import paper
from analysis.core.table import select, yield_rows
from analysis.fits.fit_file import FitFileError, load_fits, save_fits
from analysis.fits.fits import (
    ScalingLaw,
    evaluate,
    fit_alpha,
    fit_kappa,
    fit_phi,
    fit_power_law,
    fit_saturation,
    fit_scaling_law,
    fit_theta,
    sum_rule,
)

ROOT = Path(__file__).resolve().parents[2]


def within(p, truth, n_err=3.0):
    return abs(p.value - truth) < n_err * p.err


def test_theta_fit_recovers_eq7():
    rng = np.random.default_rng(7)
    Fr = np.linspace(0.05, 10, 40)
    theta = -0.15 * Fr ** 0.38 + np.pi / 2.45 + 0.004 * rng.standard_normal(40)
    fit = fit_theta(Fr, theta)
    for k in ("U1", "U2", "U3"):
        assert within(fit[k], paper.THETA[k]), (k, fit[k])
        assert 0 < fit[k].err < 0.1 * abs(paper.THETA[k])
    assert np.allclose(evaluate(fit, Fr), -0.15 * Fr ** 0.38 + np.pi / 2.45, atol=0.01)


def test_kappa_fit_recovers_fig8_line(table):
    fit = fit_kappa(table)
    assert within(fit["k0"], 0.887) and within(fit["k1"], 0.185)
    assert fit["k1"].err < 0.005
    # A wrong line is excluded by the error bars.
    assert not within(fit["k1"], 0.2)


def test_error_never_below_what_the_measurements_carry():
    # Three points exactly on a line with 5 % errors: the slope's error must be the analytic
    # weighted-least-squares one, 1 / sqrt(sum w (x - xw)^2), not the ~0 that scaling by the
    # (vanishing) residuals gives. With residuals larger than the errors it scales up.
    x = np.log(np.array([2.0, 3.0, 4.0]))
    rel = np.full(3, 0.05)
    w = 1 / rel ** 2
    analytic = 1 / np.sqrt(np.sum(w * (x - np.sum(w * x) / np.sum(w)) ** 2))
    exact = fit_power_law(np.exp(x), 3.0 * np.exp(x) ** 1.4, 3.0 * np.exp(x) ** 1.4 * rel)
    assert exact["p"].value == pytest.approx(1.4)
    assert exact["p"].err == pytest.approx(analytic, rel=1e-6)
    y = 3.0 * np.exp(x) ** 1.4 * np.array([1.0, 1.3, 0.8])      # scatter >> 5 %
    noisy = fit_power_law(np.exp(x), y, y * rel)
    assert noisy["p"].err > 3 * analytic


def test_power_law_exponent_and_errors():
    rng = np.random.default_rng(3)
    x = np.arange(2.0, 12.0)
    y = 0.7 * x ** 1.6 * (1 + 0.03 * rng.standard_normal(len(x)))
    fit = fit_power_law(x, y, 0.03 * y)
    assert within(fit["p"], 1.6) and within(fit["A"], 0.7)
    assert fit["p"].err < 0.05
    with pytest.raises(ValueError, match="positive"):
        fit_power_law([1, 2, -3], [1, 2, 3])


def test_phi_alpha_and_sum_rule(table):
    phi, alpha = fit_phi(table), fit_alpha(table)
    assert sorted(phi.mu) == [0.0, 0.1, 0.3, 0.5, 0.9]
    # Stated tolerance: 3 standard errors and 0.05 absolute on every exponent.
    for _, r in phi.iterrows():
        assert abs(r.phi - synth.phi_true(r.mu)) < min(3 * r.phi_err, 0.05), r
        if r.mu > 0:    # G = 1 at the yield speed only with friction
            assert abs(r.f / synth.prefactor(r.mu) / synth.H_SYSTEM_I ** synth.alpha_true(r.mu) - 1) < 0.1
    for _, r in alpha.iterrows():
        assert abs(r.alpha - synth.alpha_true(r.mu)) < min(3 * r.alpha_err, 0.1), r
    s = sum_rule(phi, alpha)
    assert len(s) == 5
    assert np.all(np.abs(s["sum"] - 3.0) < 3 * s.sum_err)
    assert np.allclose(s.sum_err, np.hypot(s.phi_err, s.alpha_err))


def test_yield_force_saturation_fit(table):
    g = select(yield_rows(table), D=4.0, system="I")
    fit = fit_saturation(g.mu, g.drag)
    # Synthetic F_Y reaches 95 % of its rise by mu ~ 0.4 < 0.9 sampled.
    assert 3 * (fit["mu_c"].value + 2 * fit["mu_c"].err) < g.mu.max()
    # A force rising linearly over the whole range does not look saturated.
    lin = fit_saturation(g.mu, 10 + 20 * g.mu)
    assert 3 * lin["mu_c"].value > g.mu.max()


def test_scaling_law_lambdas_and_prediction(table):
    phi, alpha = fit_phi(table), fit_alpha(table)
    law = fit_scaling_law(table, phi, alpha, mu=0.5, n_boot=40, seed=0)
    G = synth.G_params(0.5)
    lam = law.lambdas()
    # lambda^I is the prefactor C(mu) times G's plateau, etc. (3 standard errors)
    C = synth.prefactor(0.5)
    assert within(lam["lambda^I"], C * G["a0"])
    assert within(lam["lambda_1^II"], C * G["b1"])
    assert within(lam["lambda_1^III"], C * G["b2"])
    assert within(law.regimes["Fr1"], 1.0) and within(law.regimes["Fr2"], 5.0)
    F, err = law.predict(D=4.0, h=45.0, V=2.0)
    truth = synth.drag_true(4.0, 45.0, 0.5, float(synth.froude(2.0, 4.0)))
    assert abs(F - truth) < 3 * err and err < 0.2 * truth
    with pytest.raises(ValueError, match="8 or more Froude numbers"):
        fit_scaling_law(table, phi, alpha, mu=0.9)


def test_fit_file_round_trip(table, tmp_path):
    phi, alpha = fit_phi(table), fit_alpha(table)
    law = fit_scaling_law(table, phi, alpha, mu=0.5, n_boot=20)
    theta = fit_theta(table.Fr, table.theta)
    path = tmp_path / "fits.json"
    save_fits(path, laws=[law], fits={"theta": theta}, tables={"phi": phi})
    back = load_fits(path)
    assert isinstance(back.laws[0], ScalingLaw)
    assert back.laws[0].predict(4.0, 45.0, 2.0) == pytest.approx(law.predict(4.0, 45.0, 2.0))
    assert back.fits["theta"]["U2"] == theta["U2"]
    assert np.allclose(back.tables["phi"].phi, phi.phi)
    doc = json.loads(path.read_text())
    assert doc["format"] == "granudrag-fits" and doc["version"] == 1
    # The release that wrote it, as the engine's files record theirs (/granudrag code_version).
    assert doc["written_by"] == f"granudrag-analysis {(ROOT / 'VERSION').read_text().strip()}"
    assert "written_by" not in back.summary


def test_fit_file_errors(tmp_path):
    with pytest.raises(FitFileError, match="no such fit file"):
        load_fits(tmp_path / "none.json")
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    with pytest.raises(FitFileError, match="not a JSON fit file"):
        load_fits(bad)
    bad.write_text(json.dumps({"format": "something-else"}))
    with pytest.raises(FitFileError, match="not a granudrag fit file"):
        load_fits(bad)
    bad.write_text(json.dumps({"format": "granudrag-fits", "version": 99}))
    with pytest.raises(FitFileError, match="version 99"):
        load_fits(bad)
    bad.write_text(json.dumps({"format": "granudrag-fits", "version": 1, "laws": [{"mu": 0.5}]}))
    with pytest.raises(FitFileError, match="damaged fit file"):
        load_fits(bad)


def test_config_h_min_and_alpha_speeds_reach_the_fits():
    # paper.yaml cuts Eq. 12 / Fig. 19 at h >= 45 as the paper; the default keeps every depth
    # (its beds are all shallower), and both average alpha over the paper's five speeds.
    import yaml

    from granudrag_study import fit_options, validate_config
    root = synth.__file__.rsplit("/tests/", 1)[0]
    opts = {}
    for name in ("paper.yaml", "config.yaml", "smoke.yaml"):
        with open(f"{root}/config/{name}") as fh:
            cfg = yaml.safe_load(fh)
        validate_config(cfg)
        opts[name] = fit_options(cfg)
    assert opts["paper.yaml"].h_min == 45 and opts["config.yaml"].h_min == 0
    assert opts["smoke.yaml"].h_min == 0                       # schema default
    assert opts["paper.yaml"].alpha_speeds == (0.5, 1.0, 2.0, 4.0, 6.0)
    # the paper's Fig. 18a K_n sweep pulls at those speeds, not at the yield speed
    with open(f"{root}/config/paper.yaml") as fh:
        sweeps = {s["name"]: s for s in yaml.safe_load(fh)["sweeps"]}
    assert sweeps["alpha_kn"]["V"] == [0.5, 1, 2, 4, 6] == sweeps["alpha_speeds"]["V"]


def test_scaling_law_h_min_drops_shallow_pulls(table):
    phi, alpha = fit_phi(table), fit_alpha(table)
    deep = fit_scaling_law(table, phi, alpha, mu=0.5, n_boot=0, h_min=45)
    every = fit_scaling_law(table, phi, alpha, mu=0.5, n_boot=0)
    moving = table[(table.mu == 0.5) & (table.kn == synth.KN) & (table.gamman == synth.GAMMAN)
                   & (table.V > 0.02)]
    assert every.regimes.n_points == len(moving)
    assert deep.regimes.n_points == len(moving[moving.h >= 45])
    assert deep.ranges["h"][0] == 45 and deep.regimes.meta["h_min"] == 45
    with pytest.raises(ValueError, match="h >= 100"):
        fit_scaling_law(table, phi, alpha, mu=0.5, n_boot=0, h_min=100)


def test_theta_fit_from_data_not_from_the_paper():
    # A theta(Fr) far from Eq. 7's numbers (rising, steeper, another static angle), with
    # per-point errors that differ 10-fold: the fit must find it by its own profile over U2, and
    # weight the points (half of them carry 10x the noise and 10x the error).
    rng = np.random.default_rng(11)
    Fr = np.geomspace(0.1, 10, 40)
    truth = dict(U1=0.04, U2=1.3, U3=4.0)
    sigma = np.where(np.arange(40) % 2, 0.002, 0.02)
    theta = 0.04 * Fr ** 1.3 + np.pi / 4.0 + sigma * rng.standard_normal(40)
    fit = fit_theta(Fr, theta, sigma)
    for k, v in truth.items():
        assert within(fit[k], v), (k, fit[k])
    assert fit.meta["weighted"] and fit.meta["at_bounds"] == []
    unweighted = fit_theta(Fr, theta)
    assert fit["U2"].err < unweighted["U2"].err               # the weights are used


def test_kappa_fit_weighted_by_its_errors(table):
    # Outliers that carry large errors must not pull the weighted line.
    t = table.dropna(subset=["kappa"]).copy()
    bad = t.index[::7]
    t.loc[bad, "kappa"] += 0.5
    t.loc[bad, "kappa_err"] = 5.0
    fit = fit_kappa(t)
    assert fit.meta["weighted"] and within(fit["k1"], 0.185) and within(fit["k0"], 0.887)
    assert not within(fit_kappa(t.drop(columns="kappa_err"))["k0"], 0.887)


def test_regime_fits_leave_the_yield_pull_out():
    # At mu = 0 the yield pull alone would fix a'' of a'' + b'' Fr^c''. Tripling it changes
    # no regime fit; it is reported beside the fit instead.
    from analysis.fits.fitset import run_fits
    df = synth.make_table(seed=5, mus=(0.0, 0.5), kn_variants=False)
    moved = df.copy()
    y = (moved.system == "I") & (moved.V == 0.01) & (moved.D == 2.0) & (moved.mu == 0.0)
    moved.loc[y, "drag"] *= 3
    a, b = run_fits(df, n_boot=0), run_fits(moved, n_boot=0)
    fa, fb = a.regimes[("D", 0.0, 2.0)], b.regimes[("D", 0.0, 2.0)]
    assert fa.values() == fb.values()
    assert fa.n_points == len(synth.FR_GRID)
    assert fb.meta["yield_pull"]["drag"] == pytest.approx(float(moved.loc[y, "drag"].iloc[0]))


def test_yield_pulls_at_a_validated_faster_speed_are_found_by_their_mark(table):
    # A study whose yield pulls ran at V = 0.03 (report.yield_speed): the table marks them,
    # and phi and alpha are the same as from the same forces at 0.01; unmarked, those pulls
    # would be taken for pulls at speed and no yield force would be found.
    import pandas as pd

    from analysis.core.table import YIELD_SPEED, is_yield, mark_yield

    faster = table.assign(V=np.where(np.isclose(table.V, YIELD_SPEED), 0.03, table.V))
    assert not is_yield(faster).any()
    assert fit_phi(faster).empty
    marked = mark_yield(faster, 0.03)
    assert is_yield(marked).sum() == np.isclose(table.V, YIELD_SPEED).sum() > 0
    pd.testing.assert_frame_equal(fit_phi(marked), fit_phi(table))
    pd.testing.assert_frame_equal(fit_alpha(marked), fit_alpha(table))
    # Per friction: 0.03 below mu = 0.5, 0.1 from it on (report.yield_speed as steps).
    steps = [{"mu": 0, "V": 0.03}, {"mu": 0.5, "V": 0.1}]
    fastest = faster.assign(V=np.where(np.isclose(faster.V, 0.03) & (faster.mu >= 0.5), 0.1, faster.V))
    assert (fastest.V == 0.1).any() and (fastest.V == 0.03).any()
    per_mu = mark_yield(fastest, steps)
    assert (per_mu.yield_pull == marked.yield_pull).all()
    pd.testing.assert_frame_equal(fit_phi(per_mu), fit_phi(table))
    assert not mark_yield(fastest, 0.03).yield_pull[fastest.mu >= 0.5].any()   # one speed misses them


def test_yield_speeds_per_friction_are_steps_from_mu_zero():
    from analysis.core.table import yield_speeds

    steps = [{"mu": 0.5, "V": 0.1}, {"mu": 0, "V": 0.03}]          # any order
    assert list(yield_speeds(steps, [0, 0.3, 0.5, 0.9])) == [0.03, 0.03, 0.1, 0.1]
    assert list(yield_speeds(0.01, [0, 0.9])) == [0.01, 0.01]
    with pytest.raises(ValueError, match="first step must start at mu = 0"):
        yield_speeds([{"mu": 0.5, "V": 0.1}], [0.5])


def test_eq12_on_shallow_and_deep_pulls_is_flagged(capsys):
    # The paper's Eq. 12 collapse holds for h >~ 45 d (Sec. III H). A table with pulls on both
    # sides of it, fitted with h_min = 0, gets a note (and a warning on stderr) naming the
    # shallow pulls and the key that leaves them out; with h_min = 45 there is none.
    from analysis.fits.fitset import Options, run_fits
    df = synth.make_table(seed=5, mus=(0.0, 0.5), kn_variants=False)
    assert (df.h < 45).any() and (df.h >= 45).any()
    shallow = int(((df.h >= 0) & (df.h < 45)).sum())
    notes = run_fits(df, n_boot=0).notes
    flagged = [n for n in notes if "Sec. III H" in n]
    assert len(flagged) == 1 and f"include {shallow} pull(s)" in flagged[0] and "report.h_min: 45" in flagged[0]
    assert "warning: Eq. 12" in capsys.readouterr().err
    deep_only = run_fits(df, n_boot=0, options=Options(n_boot=0, h_min=45.0)).notes
    assert not [n for n in deep_only if "Sec. III H" in n]


def test_every_fit_records_its_goodness_in_the_fit_file(table, tmp_path):
    # chi^2/dof and the residual-trend test beside every fitted quantity (additive keys).
    import json

    from analysis.fits.fitset import load_results, run_fits, save_results
    r = run_fits(table, n_boot=5, seed=0)
    save_results(tmp_path / "fits.json", r)
    doc = json.loads((tmp_path / "fits.json").read_text())
    assert {"regimes_mu0.5_D2", "theta", "kappa", "saturation_D2"} <= set(doc["fits"])
    for name, f in doc["fits"].items():
        g = f["meta"]["goodness"]
        assert {"chi2", "dof", "chi2_dof", "chi2_p", "runs", "runs_expected", "trend_p", "trend",
                "rejected"} <= set(g), name
        assert g["dof"] == f["n_points"] - len(f["params"]) or f["model"] == "regimes", name
        assert g["chi2_dof"] is not None and g["rejected"] is False, (name, g)   # the synthetic laws hold
    for law in doc["laws"]:
        assert "goodness" in law["regimes"]["meta"]
    for row in doc["phi"] + doc["alpha"] + doc["tables"]["phi"] + doc["tables"]["alpha_speeds"]:
        assert {"chi2_dof", "trend_p", "rejected"} <= set(row) and row["chi2_dof"] is not None
        assert row["rejected"] in (False, 0.0)
    assert doc["rejected"] == []
    back = load_results(tmp_path / "fits.json")
    assert back.kappa.meta["goodness"] == r.kappa.meta["goodness"] and "chi2_dof" in back.phi.columns


def test_a_fit_whose_errors_have_no_precision_is_ill_posed():
    # θ of the smoke study, two series at three speeds, U3 on its bound: its covariance's condition
    # number is 1.3e10, and its errors came out 7e-5 apart on Debian's and the pinned stack
    # (issue 76). No error is written, and the report calls it inconclusive, saying why.
    from analysis.report.verdicts import verdict
    Fr = [0.5, 1.0, 2.0, 0.5, 1.0, 2.0]
    theta = [1.50221792, 1.44030581, 1.47991295, 2.07670736, 1.36842091, 0.94867351]
    sigma = [0.27907778, 0.14722054, 0.12530438, 0.16229614, 0.17911098, 0.24557468]
    fit = fit_theta(Fr, theta, sigma)
    assert "ill-posed" in fit.meta["ill_posed"] and fit.covariance is None
    assert all(np.isnan(p.err) for p in fit.params.values())
    assert verdict(fit["U2"], 0.38, ill_posed=fit.meta["ill_posed"]) == ("inconclusive", fit.meta["ill_posed"])
    assert "ill_posed" not in fit_theta(Fr[:3] + [4.0, 8.0], theta[:3] + [1.2, 0.9], sigma[:5]).meta
