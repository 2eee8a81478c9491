"""The predictor: drag with uncertainty from a saved fit file, range warnings."""
import json
import subprocess
import sys

import pytest
import synth

from analysis.core.table import froude
from analysis.fits.fit_file import load_fits
from analysis.predict import predict

ROOT = synth.__file__.rsplit("/tests/", 1)[0]


def run(*args):
    return subprocess.run([sys.executable, "-m", "analysis.predict", *args],
                          cwd=ROOT, capture_output=True, text=True, timeout=60)


@pytest.mark.slow
def test_cli_predicts_synthetic_truth(report_dir):
    r = run("--D", "4", "--h", "45", "--mu", "0.5", "--V", "2",
            "--fits", str(report_dir / "fits.json"), "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    truth = synth.drag_true(4.0, 45.0, 0.5, float(froude(2.0, 4.0)))
    assert abs(out["drag"] - truth) < 3 * out["err"], (out, truth)
    assert 0 < out["err"] < 0.1 * truth
    assert out["warnings"] == [] and "warning" not in r.stderr


@pytest.mark.slow
def test_cli_warns_outside_fitted_range(report_dir):
    r = run("--D", "20", "--h", "200", "--mu", "0.5", "--V", "2",
            "--fits", str(report_dir / "fits.json"))
    assert r.returncode == 0, r.stderr
    assert "F*_drag = " in r.stdout and " ± " in r.stdout
    assert "warning: D = 20 is outside the fitted range [1, 10]" in r.stderr
    assert "warning: h = 200 is outside the fitted range [10, 65]" in r.stderr


@pytest.mark.slow
def test_cli_rejects_bad_fit_file(tmp_path):
    bad = tmp_path / "fits.json"
    bad.write_text("[]")
    r = run("--D", "4", "--h", "45", "--mu", "0.5", "--V", "2", "--fits", str(bad))
    assert r.returncode == 2 and "error:" in r.stderr and "not a granudrag fit file" in r.stderr


@pytest.mark.slow
def test_mu_interpolation_and_extrapolation(report_dir):
    laws = load_fits(report_dir / "fits.json").laws
    assert sorted(law.mu for law in laws) == [0.0, 0.5]
    lo, hi = predict(laws, 4, 45, 0.0, 2.0), predict(laws, 4, 45, 0.5, 2.0)
    mid = predict(laws, 4, 45, 0.25, 2.0)
    assert mid.drag == pytest.approx(0.5 * (lo.drag + hi.drag))
    assert mid.notes and not mid.warnings
    far = predict(laws, 4, 45, 0.9, 2.0)
    assert far.drag == pytest.approx(hi.drag)
    assert any("mu = 0.9 is outside" in w for w in far.warnings)
    fast = predict(laws, 4, 45, 0.5, 40.0)
    assert any(w.startswith("Fr = ") for w in fast.warnings)
    with pytest.raises(ValueError, match="D > 0"):
        predict(laws, -1, 45, 0.5, 2.0)
