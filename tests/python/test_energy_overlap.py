"""tools/energy_overlap.py: the energy balance's residual and the largest overlaps read from the
/sanity report of each run, against values worked out by hand for synthetic run files."""
import subprocess
import sys
from pathlib import Path

import h5py
import pytest

TOOL = Path(__file__).resolve().parents[2] / "tools" / "energy_overlap.py"


def write_run(path, e0, e1, work, dissipated, overlap):
    path.parent.mkdir(parents=True)
    with h5py.File(path, "w") as f:
        s = f.create_group("sanity")
        s.attrs["report"] = (f"sanity: grains lost 0 of 10; largest overlap {overlap} d; energy of the grains {e0} "
                             f"-> {e1}, work by the intruder {work}, dissipated {dissipated} (rho g d^4)\n").encode()
        s.attrs["max_overlap"] = overlap


def run_tool(*args):
    return subprocess.run([sys.executable, str(TOOL), *map(str, args)], capture_output=True, text=True)


def test_residual_and_overlap_ratio_per_system(tmp_path):
    bed = "D~2/h~7/mu~0/kn~2e6/gn~1/seed~1"
    # reference: residual (110 - 100 - 50 + 40) / 50 = 0; variant: (110 - 100 - 50 + 41) / 50 = 0.02
    write_run(tmp_path / f"pulls/system~T64/{bed}/Fr~1/run.h5", 100, 110, 50, 40, 0.010)
    write_run(tmp_path / f"pulls/system~T64/{bed}/Fr~5/run.h5", 100, 110, 50, 40, 0.020)
    write_run(tmp_path / f"pulls/system~T32/{bed}/Fr~1/run.h5", 100, 110, 50, 41, 0.012)
    write_run(tmp_path / f"pulls/system~T32/{bed}/Fr~5/run.h5", 100, 110, 50, 39.5, 0.030)
    r = run_tool(tmp_path)
    assert r.returncode == 0, r.stderr
    t32 = next(line for line in r.stdout.splitlines() if line.startswith("kn~2e6 system~T32:"))
    assert "|residual| at most 2.00e-02" in t32
    assert "greatest 0.0300 d" in t32
    # overlap ratios 1.2 and 1.5: median 1.35
    assert "median 1.350 (1.200-1.500, 2 pairs)" in t32
    t64 = next(line for line in r.stdout.splitlines() if line.startswith("kn~2e6 system~T64:"))
    assert "|residual| at most 0.00e+00" in t64 and "pairs" not in t64


@pytest.mark.parametrize("layout", ["no pulls", "no reference"])
def test_bad_input_names_the_problem(tmp_path, layout):
    if layout == "no reference":
        write_run(tmp_path / "pulls/system~T32/D~2/kn~2e6/seed~1/Fr~1/run.h5", 1, 2, 1, 0, 0.01)
    r = run_tool(tmp_path)
    assert r.returncode != 0
    assert ("no run.h5" in r.stderr) if layout == "no pulls" else ("--reference" in r.stderr)
