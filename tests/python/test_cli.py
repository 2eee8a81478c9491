"""`python -m analysis fit|report|predict` on a synthetic table with known exponents and
crossovers: the documented keys of fits.json, values within their error bars, bad input."""
import json
import subprocess
import sys

import numpy as np
import pytest
import synth

from analysis.core.table import save_csv

ROOT = synth.__file__.rsplit("/tests/", 1)[0]


def run(*args):
    return subprocess.run([sys.executable, "-m", "analysis", *map(str, args)], cwd=ROOT,
                          capture_output=True, text=True, timeout=300)


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    d = tmp_path_factory.mktemp("cli")
    save_csv(synth.make_table(seed=3), d / "table.csv")
    r = run("fit", d / "table.csv", "--output", d / "fits.json", "--n-boot", 40, "--seed", 1)
    assert r.returncode == 0, r.stderr
    return d, json.loads((d / "fits.json").read_text())


@pytest.mark.slow
def test_fit_writes_the_documented_keys(fitted):
    d, doc = fitted
    assert doc["format"] == "granudrag-fits"
    for key in ("phi", "alpha", "alpha_drag"):
        assert doc[key] and all({"mu", "value", "error"} <= set(e) for e in doc[key]), key
    assert doc["crossovers"]
    for c in doc["crossovers"]:
        assert {"series", "mu", "D", "h", "Fr1", "Fr1_error", "Fr2", "Fr2_error"} <= set(c)
    assert isinstance(doc["at_bounds"], list) and isinstance(doc["violations"], list)
    assert doc["options"]["n_boot"] == 40 and doc["options"]["alpha_speeds"] == [0.5, 1, 2, 4, 6]
    assert not list(d.glob("*.tmp"))


def test_fit_recovers_the_truth_within_error_bars(fitted):
    # Stated tolerance: 3 standard errors (and a sanity ceiling on each error).
    _, doc = fitted
    for e in doc["phi"]:
        assert abs(e["value"] - synth.phi_true(e["mu"])) < 3 * e["error"], e
        assert e["error"] < 0.05
    for e in doc["alpha"] + doc["alpha_drag"]:
        assert abs(e["value"] - synth.alpha_true(e["mu"])) < 3 * e["error"], e
        assert e["error"] < 0.1
    assert [e["mu"] for e in doc["alpha_drag"]] == [0.5]       # drag at speed over depth: mu = 0.5 only
    assert doc["alpha_drag"][0]["n_speeds"] == 4                # 0.5, 2, 4, 6 matched; 1 is not within 25 %
    series = {c["series"]: c for c in doc["crossovers"]}
    assert "Eq. 12 collapse" in series and "I: drag vs Fr at D = 4" in series
    # Crossovers: 22 numbers; their bootstrap errors run ~15 % small (tests/python/
    # calibrate_regimes.py), so: at least 80 % within 2 standard errors, none beyond 5.
    z = np.array([[(c["Fr1"] - 1.0) / c["Fr1_error"], (c["Fr2"] - 5.0) / c["Fr2_error"]]
                  for c in doc["crossovers"]])
    assert np.mean(np.abs(z) < 2) >= 0.8 and np.abs(z).max() < 5, z.round(1)


def test_shallow_pulls_left_out_of_eq12_with_h_min(tmp_path):
    save_csv(synth.make_table(seed=2, mus=(0.5,), kn_variants=False), tmp_path / "t.csv")
    r = run("fit", tmp_path / "t.csv", "--output", tmp_path / "f.json", "--n-boot", 0, "--h-min", 45)
    assert r.returncode == 0, r.stderr
    doc = json.loads((tmp_path / "f.json").read_text())
    law = doc["laws"][0]
    assert law["ranges"]["h"][0] == 45 and doc["options"]["h_min"] == 45
    # system I (h = 25) and the h = 25 series are out: 13 Fr values at h = 45 and 65 remain
    assert law["regimes"]["n_points"] == 2 * len(synth.FR_GRID)


@pytest.mark.slow
def test_report_and_predict_subcommands(fitted, tmp_path):
    d, _ = fitted
    r = run("report", d / "table.csv", "--fits", d / "fits.json", "--output-dir", tmp_path)
    assert r.returncode == 0, r.stderr
    md = (tmp_path / "report.md").read_text()
    assert "α_μ from the drag, averaged over speeds; μ = 0.5" in md and "(fig19_scaled_drag_vs_Fr_h.png)" in md
    # The report names its within-error test, and each verdict says which quantile it used.
    assert "Student-t quantile at the fit's degrees of freedom" in md
    assert "standard errors away, within" in md or "standard errors, beyond" in md
    p = run("predict", "--fits", d / "fits.json", "--D", 4, "--h", 45, "--mu", 0.5, "--V", 2, "--json")
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    truth = synth.drag_true(4.0, 45.0, 0.5, float(synth.froude(2.0, 4.0)))
    assert abs(out["drag"] - truth) < 3 * out["err"]


@pytest.mark.slow
def test_bad_input_is_named(tmp_path):
    (tmp_path / "bad.csv").write_text("a,b\n1,2\n")
    r = run("fit", tmp_path / "bad.csv", "--output", tmp_path / "f.json")
    assert r.returncode == 2 and "not a granudrag pull table: missing columns" in r.stderr
    assert not (tmp_path / "f.json").exists()
    r = run("fit", tmp_path / "none.csv", "--output", tmp_path / "f.json")
    assert r.returncode == 2 and "no such file" in r.stderr
    save_csv(synth.make_table(seed=0, mus=(0.5,), kn_variants=False), tmp_path / "t.csv")
    r = run("fit", tmp_path / "t.csv", "--output", tmp_path / "t.csv")
    assert r.returncode == 2 and "is the input table" in r.stderr
    r = run("fit", tmp_path / "t.csv", "--output", tmp_path / "f.json", "--alpha-speeds", "fast")
    assert r.returncode == 2 and "--alpha-speeds" in r.stderr
    r = run("fit", tmp_path / "t.csv", "--output", tmp_path / "f.json", "--h-min", "-1")
    assert r.returncode == 2 and "--h-min: must be >= 0" in r.stderr
    r = run("report", tmp_path / "t.csv", "--fits", tmp_path / "nofits.json", "--output-dir", tmp_path)
    assert r.returncode == 2 and "no such fit file" in r.stderr


@pytest.mark.slow
def test_fits_are_reproducible(fitted, tmp_path):
    d, doc = fitted
    r = run("fit", d / "table.csv", "--output", tmp_path / "again.json", "--n-boot", 40, "--seed", 1)
    assert r.returncode == 0
    again = json.loads((tmp_path / "again.json").read_text())
    assert again["crossovers"] == doc["crossovers"]
    assert np.allclose([e["value"] for e in again["alpha_drag"]], [e["value"] for e in doc["alpha_drag"]])
