"""One answer on both supported Python stacks (issue 76): Debian's /usr/bin/python3 with Debian
12's NumPy, SciPy and pandas, and the project environment's .venv/bin/python with its pinned ones.

The same table once gave other Eq. 12 crossovers on each (Fr1 0.25 against 0.87 at mu = 0.5 on
results/reproduction/config): Debian's pandas 1.5 parsed about one float in ten an ulp off, the
regime fit counted Froude numbers an ulp apart as two, and SciPy's curve_fit stopped where each
release's tolerances said. Now the table is parsed exactly (analysis.core.table.EXACT_FLOATS), the
regimes count nominal Froude numbers (regimes.nominal_froude) and no fit calls an optimiser
(analysis/fits/least_squares.py). Both stacks must then write the same numbers to RTOL relative (ATOL
absolute near zero): a fitted parameter is fixed by its least squares only to about sqrt(machine
epsilon) times its own error over its value (each stack rounds differently; θ's Υ1, -4.63 ± 6.66
on that rung: 3.7e-7 apart, the largest measured). A fit whose errors have no precision at all
(least_squares.ill_posed: the smoke study's θ, 7e-5 apart) is written ill-posed on both, with no
error and the reason, and so compares equal; any other difference fails.

test_a_committed_rung_refits_alike: results/reproduction/config's table.csv refitted on each stack
with the options its fits.json records (n_boot cut to N_BOOT: the refits' machinery is what is
compared, and 200 of them cost 9 s of CPU a stack); also in test.sh's project-environment pass
only, as it starts both interpreters itself.
test_the_smoke_studys_table_and_fits_alike: the smoke study of this pass (its Snakemake's stack)
made its table.csv and fits.json; each stack makes them again, the table from the study's run
files, the fits from its table, and all three must agree.
"""
import csv
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest
from workflow_support import NEEDS_SNAKEMAKE_AND_ENGINE, ROOT

STACKS = {"debian": Path("/usr/bin/python3"), "venv": ROOT / ".venv" / "bin" / "python"}
RTOL, ATOL = 1e-5, 1e-9
RUNG = ROOT / "results" / "reproduction" / "config"
N_BOOT = 20

# The table rule's steps after the run files are found (workflow/scripts/make_table.py): argv
# runs.csv (whose `path` column lists the run files, in the study's order), the results folder
# (relative to the study's folder, as the rule's), yield speed, bed-scatter prior (JSON), output.
MAKE_TABLE = """
import json, sys
import pandas as pd
from analysis.runs.runs import load_runs
from analysis.core.table import combine_beds, mark_yield, save_csv
runs, root, speed, prior, out = sys.argv[1:]
df, problems = load_runs(list(pd.read_csv(runs).path), root=root, errors="collect")
assert not problems, problems
save_csv(combine_beds(mark_yield(df, float(speed)), prior=json.loads(prior)), out)
"""


def _usable(python):
    if not python.is_file():
        return f"no {python}"
    r = subprocess.run([str(python), "-c", "import numpy, pandas, scipy, h5py"], capture_output=True, text=True)
    return None if r.returncode == 0 else f"{python} lacks the analysis's packages: {r.stderr[-300:]}"


def _skip_without_both():
    for python in STACKS.values():
        reason = _usable(python)
        if reason:
            pytest.skip(reason)


def _run_on_both(args_of, cwd):
    """Each stack's command (args_of(name) -> argv after the interpreter), side by side; this
    tree's analysis package on both (PYTHONPATH), one thread each."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
    procs = {name: subprocess.Popen([str(py), *args_of(name)], cwd=cwd, env=env, text=True,
                                    stdout=subprocess.PIPE, stderr=subprocess.PIPE)
             for name, py in STACKS.items()}
    for name, p in procs.items():
        out, err = p.communicate(timeout=600)
        assert p.returncode == 0, f"{name}: {' '.join(p.args)} failed:\n{err[-3000:]}"


def _close(a, b):
    return a == b or (math.isnan(a) and math.isnan(b)) or abs(a - b) <= ATOL + RTOL * max(abs(a), abs(b))


def json_differences(a, b, where=""):
    """Every place two JSON documents differ beyond RTOL/ATOL, in words (empty: they agree)."""
    if isinstance(a, dict) and isinstance(b, dict):
        if set(a) != set(b):
            return [f"{where}: keys {sorted(set(a) ^ set(b))} in one only"]
        return [d for k in a for d in json_differences(a[k], b[k], f"{where}/{k}")]
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{where}: {len(a)} against {len(b)} items"]
        return [d for i, (u, v) in enumerate(zip(a, b)) for d in json_differences(u, v, f"{where}[{i}]")]
    numbers = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (a, b))
    if numbers and _close(float(a), float(b)) or not numbers and a == b:
        return []
    return [f"{where}: {a!r} against {b!r}"]


def _cell(text):
    try:
        return float(text) if text else text
    except ValueError:
        return text


def table_differences(a, b):
    """Every cell in which two CSV tables differ beyond RTOL/ATOL (as json_differences)."""
    rows = [[[_cell(c) for c in row] for row in csv.reader(Path(p).open())] for p in (a, b)]
    if rows[0][0] != rows[1][0]:
        return [f"columns {rows[0][0]} against {rows[1][0]}"]
    header = rows[0][0]
    return [d for i, (u, v) in enumerate(zip(rows[0][1:], rows[1][1:]))
            for k, (x, y) in enumerate(zip(u, v))
            for d in json_differences(x, y, f"row {i + 1} {header[k]}")] + (
        [f"{len(rows[0])} against {len(rows[1])} rows"] if len(rows[0]) != len(rows[1]) else [])


def _fit_args(table, options, out):
    return ["-m", "analysis", "fit", str(table), "--output", str(out), "--n-boot", str(options["n_boot"]),
            "--seed", str(options["seed"]), "--h-min", str(options["h_min"]),
            "--alpha-speeds", ",".join(str(v) for v in options["alpha_speeds"])]


def _load(path):
    return json.loads(Path(path).read_text())


def test_comparison_sees_a_moved_crossover_and_lets_rounding_pass():
    a = {"crossovers": [{"Fr1": 0.25029210463059737, "at_bounds": ["regime I held"]}], "p": 2.2e-33}
    b = {"crossovers": [{"Fr1": 0.8731493855906116, "at_bounds": []}], "p": 2.2e-33 * (1 + 1e-9)}
    assert len(json_differences(a, b)) == 2
    c = {"crossovers": [{"Fr1": 0.25029210463059737 * (1 + 3e-7), "at_bounds": ["regime I held"]}],
         "p": 2.2e-33}
    assert json_differences(a, c) == []


def test_a_committed_rung_refits_alike(tmp_path):
    _skip_without_both()
    options = {**_load(RUNG / "fits.json")["options"], "n_boot": N_BOOT}
    _run_on_both(lambda name: _fit_args(RUNG / "table.csv", options, tmp_path / f"{name}.json"), ROOT)
    debian, venv = _load(tmp_path / "debian.json"), _load(tmp_path / "venv.json")
    assert json_differences(debian, venv) == []
    collapse = [c for c in venv["crossovers"] if c["series"] == "Eq. 12 collapse"]
    assert len(collapse) == 2 and all(math.isfinite(c["Fr1"]) for c in collapse)


def _needs_the_study(test):
    for mark in NEEDS_SNAKEMAKE_AND_ENGINE:
        test = mark(test)
    return test


@_needs_the_study
def test_the_smoke_studys_table_and_fits_alike(smoke, tmp_path):
    _skip_without_both()
    workdir, _, config = smoke
    kept = workdir / "uninterrupted"
    speed = (config.get("report") or {}).get("yield_speed", 0.01)
    prior = json.dumps((config.get("table") or {}).get("bed_scatter"))
    script = tmp_path / "make_table.py"
    script.write_text(MAKE_TABLE)
    _run_on_both(lambda name: [str(script), str(kept / "runs.csv"), config["results"], str(speed),
                               prior, str(tmp_path / f"{name}.csv")], workdir)
    for name in STACKS:
        assert table_differences(kept / "table.csv", tmp_path / f"{name}.csv") == [], name
    study = _load(kept / "fits.json")
    _run_on_both(lambda name: _fit_args(kept / "table.csv", study["options"], tmp_path / f"{name}.json"), workdir)
    for name in STACKS:
        assert json_differences(study, _load(tmp_path / f"{name}.json")) == [], (name, sys.executable)
