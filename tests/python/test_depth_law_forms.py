"""tools/depth_law_forms.py: the paper's product form G_k h^alpha against a sum g h^a + c_k, on
synthetic system II tables drawn from each (the deep rung's depths, speeds, two beds)."""
import sys
from pathlib import Path

import numpy as np
from test_deep_law import runs

from analysis.core.table import combine_beds

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tools"))
from depth_law_forms import compare_forms, main  # noqa: E402


def summed(rng, g=60.0, a=1.0, excess=(0.0, 300.0, 350.0, 450.0, 700.0, 1000.0)):
    """A table whose drag is g h^a plus a depth-independent excess per speed (the yield pull's 0),
    with the runs' bed shifts and noise (test_deep_law.runs drew a product law: replaced here)."""
    t = runs(rng)
    speeds = sorted(t.V.unique())
    c = dict(zip(speeds, excess))
    noise = t.drag / (10.0 * t.h ** 0.9 * (1 + 0.1 * t.V))      # the product law's draw: shift x noise
    t["drag"] = (g * t.h ** a + t.V.map(c)) * noise
    t["drag_err"] = 0.02 * t.drag
    return t


def test_each_form_is_preferred_on_its_own_data():
    rng = np.random.default_rng(21)
    wins = {"product": 0, "sum": 0}
    n = 10
    for _ in range(n):
        forms, _ = compare_forms(combine_beds(runs(rng)))           # the product law, alpha 0.9
        wins["product"] += forms["product"][0] < forms["sum"][0]
        assert abs(forms["product"][3][-1] - 0.9) < 0.1
        forms, points = compare_forms(combine_beds(summed(rng)))
        wins["sum"] += forms["sum"][0] < forms["product"][0]
        assert abs(forms["sum"][3][1] - 1.0) < 0.15 and forms["sum"][1] == forms["product"][1] == points - 7
    assert wins["product"] >= 8 and wins["sum"] >= 8, wins


def test_the_command_prints_both_forms(tmp_path, capsys):
    from analysis.core.physics import froude
    from analysis.core.table import write_csv
    t = summed(np.random.default_rng(22))
    t["Fr"] = froude(t.V, t.D)
    write_csv(combine_beds(t), tmp_path / "table.csv")
    assert main([str(tmp_path / "table.csv"), "--h-min", "45"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("h >= 45 d, 18 points: product G_k h^alpha chi2") and "sum g h^a + c_k" in out
