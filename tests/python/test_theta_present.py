"""θ's second definition, over the contacts present at each sample (time-weighted; the engine's
/observables/theta_present): read into runs.csv, combined over beds into table.csv as θ is, fitted by
Eq. 7 beside θ per contact formation (fits.json `theta_present`), shown in the report and Fig. 6."""
import json
import math

import h5py
import numpy as np
import pandas as pd
import pytest
import synth
from test_runs import BED, write_run
from test_table import point_runs

from analysis.core.table import combine_beds
from analysis.figures.figures import fig06_theta
from analysis.fits.fit_file import VERSION
from analysis.fits.fits import THETA_DEFINITIONS
from analysis.fits.fitset import load_results, run_fits, save_results
from analysis.ladder.ladder_summary import _observable_figure, _theta_present
from analysis.report.report import comparisons
from analysis.runs.runs import EXTRA_COLUMNS, load_runs, read_run

# A time-weighted θ that is not the per-formation one: other Eq. 7 parameters, known.
TRUTH = {"U1": -0.10, "U2": 0.70, "U3": 2.30}
NOISE = 0.004


def with_theta_present(path, value=1.42, error=0.03):
    """The group as src/io/run_file.cpp writes it: value, error, error_dof; the sum and count series."""
    with h5py.File(path, "r+") as f:
        g = f.create_group("observables/theta_present")
        g.attrs.update({"value": value, "error": error, "error_dof": 7.5})
        g.create_dataset("sum", data=np.full(50, 2 * value))
        g.create_dataset("count", data=np.full(50, 2.0))
    return path


def test_runs_csv_reads_theta_present_and_nan_from_files_before_it(tmp_path):
    new = with_theta_present(write_run(tmp_path / "a" / "pulls" / BED / "Fr~1" / "run.h5"))
    old = write_run(tmp_path / "b" / "pulls" / BED / "Fr~1" / "run.h5")        # no group: an older file
    row = read_run(new)
    assert (row["theta_present"], row["theta_present_err"]) == (1.42, 0.03)
    assert row["theta"] == 1.55                                                 # the per-formation θ apart
    assert math.isnan(read_run(old)["theta_present"]) and math.isnan(read_run(old)["theta_present_err"])
    assert {"theta_present", "theta_present_err"} <= set(EXTRA_COLUMNS)
    df = load_runs([new, old])
    assert df.theta_present.iloc[0] == 1.42 and df.theta_present.isna().tolist() == [False, True]


def test_the_point_table_combines_theta_present_as_theta():
    df = point_runs(np.random.default_rng(5))
    rng = np.random.default_rng(6)
    df["theta_err"] = 0.01
    df["theta_present"] = 1.3 + 0.02 * rng.standard_normal(len(df))
    df["theta_present_err"] = [0.004, 0.030, 0.010, 0.008]
    pts = combine_beds(df)
    three, one = pts.iloc[0], pts.iloc[1]
    y, e = df.theta_present.to_numpy()[:3], df.theta_present_err.to_numpy()[:3]
    s2, W = np.var(y, ddof=1), np.mean(e ** 2)
    assert three.theta_present == pytest.approx(y.mean())
    assert three.theta_present_err == pytest.approx(math.sqrt(max(s2, W) / 3))
    assert three.theta_present_err_within == pytest.approx(math.sqrt(W / 3))
    assert three.theta_present_var_excess == pytest.approx((s2 - W) / 3)
    # One bed: its own value and error (θ's errors take no pooled scatter for a point poured once)
    assert (one.theta_present, one.theta_present_err) == (df.theta_present.iloc[3], 0.008)
    # A bed from before the engine recorded it leaves its point NaN, not the other beds' mean
    df.loc[1, ["theta_present", "theta_present_err"]] = np.nan
    assert np.isnan(combine_beds(df).theta_present.iloc[0])
    assert "theta_present" not in combine_beds(df.drop(columns=["theta_present", "theta_present_err"]))


def table_with_theta_present(seed=2):
    t = synth.make_table(seed=seed, kn_variants=False)
    rng = np.random.default_rng(seed)
    fr = t.Fr.to_numpy(float)
    t["theta_present"] = TRUTH["U1"] * fr ** TRUTH["U2"] + np.pi / TRUTH["U3"] + NOISE * rng.standard_normal(len(t))
    t["theta_present_err"] = NOISE
    return t


def test_eq7_fit_of_theta_present_recovers_its_truth_beside_theta(tmp_path):
    t = table_with_theta_present()
    r = run_fits(t, n_boot=0)
    fit = r.theta_present
    for k, v in TRUTH.items():          # within 3 standard errors of the truth
        assert abs(fit[k].value - v) < 3 * fit[k].err, (k, fit[k], v)
    assert fit["U2"].err < 0.1 and fit.meta["definition"] == THETA_DEFINITIONS["theta_present"]
    # The per-formation θ (synth: the paper's Eq. 7, Υ2 = 0.38) is fitted apart and told apart
    assert abs(r.theta["U2"].value - 0.38) < 3 * r.theta["U2"].err
    assert abs(r.theta["U2"].value - fit["U2"].value) > 3 * math.hypot(r.theta["U2"].err, fit["U2"].err)
    # fits.json: a key beside `theta`, the file's version unchanged (readers of version 1 skip it)
    save_results(tmp_path / "fits.json", r)
    doc = json.loads((tmp_path / "fits.json").read_text())
    assert doc["version"] == VERSION == 1 and {"theta", "theta_present"} <= set(doc["fits"])
    assert doc["fits"]["theta"]["meta"]["definition"] == "per contact formation"
    back = load_results(tmp_path / "fits.json")
    assert back.theta_present["U2"].value == fit["U2"].value and back.theta["U2"].value == r.theta["U2"].value
    # The report: Υ1-3 of each definition against the paper's
    quantities = [row.quantity for row in comparisons(back, t)]
    assert sum(q.startswith("θ(Fr) Υ") for q in quantities) == 3
    assert sum(q.startswith("θ_present(Fr) Υ") and "time-weighted" in q for q in quantities) == 3
    # ... both claim (b)'s, so the ladder's table by claim carries them
    from analysis.core.claims import claim_of
    assert {claim_of(q) for q in quantities if q.startswith(("θ(Fr)", "θ_present(Fr)"))} == {"b"}
    # Fig. 6: a panel for each, the time-weighted one with its own fit
    fig06_theta(t, tmp_path, fit=back.theta, fit_present=back.theta_present)
    drawn = pd.read_csv(tmp_path / "fig06_theta_vs_Fr.csv")
    assert set(drawn.panel) == {"a", "b"}
    curve = drawn[(drawn.panel == "b") & (drawn.kind == "curve")]
    assert len(curve) and curve.series.str.startswith("theta_present: ").all()
    x = curve.x.to_numpy()
    v = fit.values()
    assert np.allclose(curve.y, v["U1"] * x ** v["U2"] + np.pi / v["U3"])
    # Claim (b)'s evidence figure of the ladder: the time-weighted points and their fit beside θ's
    png = _observable_figure("theta", t, back, tmp_path, "synthetic")
    assert png.stat().st_size > 1000
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots()
    _theta_present(ax, t, back.theta_present, x)
    labels = ax.get_legend_handles_labels()[1]
    assert np.allclose(ax.lines[-1].get_ydata(), curve.y) and any("time-weighted" in s for s in labels)
    plt.close(fig)


def test_a_table_without_theta_present_fits_and_draws_as_before(tmp_path):
    t = synth.make_table(seed=3, kn_variants=False)
    r = run_fits(t, n_boot=0)
    assert r.theta is not None and r.theta_present is None
    assert not [n for n in r.notes if "theta_present" in n]       # nothing to fit is no failure
    t["theta_present"] = np.nan                                    # run files before the engine had it
    assert run_fits(t, n_boot=0).theta_present is None
    fig06_theta(t, tmp_path, fit=r.theta)
    assert set(pd.read_csv(tmp_path / "fig06_theta_vs_Fr.csv").panel) == {"a"}
