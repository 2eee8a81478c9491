"""Beds by placement: a system with `placement:` pours one column per seed (system, mu, K_n,
gamma_n, seed) without an intruder and places each bed's intruder (D, depth) into it with
`granudrag place`; the beds' paths, pulls and table are a poured system's.

The plan and cost without Snakemake; then the rules on a tiny column (700 grains, 8 d x 8 d,
K_n = 2e4): the jobs a dry run lists, a run to table.csv, a changed depth placed again into the
same column, which is not poured again, a failed placement that leaves no bed, and one killed
mid-run (SIGKILL, event-driven: once it has claimed its output) that the retry starts over,
giving the bed an uninterrupted placement gives.
"""
import copy
import subprocess

import h5py
import numpy as np
import pandas as pd
import pytest
import yaml
from workflow_support import BINARY, NEEDS_SNAKEMAKE_AND_ENGINE, job_counts, killing_wrapper, snakemake, write_config

import granudrag_study as study

pytestmark = NEEDS_SNAKEMAKE_AND_ENGINE
POUR = {"ke_threshold": 1e-5, "max_settle_time": 20}


def config(tmp_path=None, **placement):
    c = {
        "granudrag": str(BINARY),
        "results": "results/placed",
        "logs": "logs/placed",
        "threads": 1,
        "throughput": 5e6,
        "defaults": {"kn": 2e4, "mu": 0.5, "seeds": [1, 2]},
        "systems": {
            "P": {"lx": 8, "ly": 8, "grains": 700, "pour": dict(POUR), "placement": dict(placement),
                  "pull": {"distance": 0.4, "transient": 0.1, "snapshots": 1}},
        },
        "sweeps": [{"name": "drag", "system": "P", "D": [1.5, 2], "depth": [3, 4], "Fr": 1}],
    }
    study.validate_config(c)
    return c


def test_one_column_per_seed_serves_every_bed():
    plan = study.plan(config())
    assert len(plan.beds) == 8 and len(plan.columns) == 2
    assert sorted(plan.columns) == [f"system~P/mu~0.5/kn~2e4/gn~199.05359/seed~{s}" for s in (1, 2)]
    bed = plan.beds["system~P/D~2/h~3/mu~0.5/kn~2e4/gn~199.05359/seed~2"]
    assert bed.column_key in plan.columns
    assert study.column_bed(bed.column_key).seed == "2"
    column = study.column_args(plan.columns[bed.column_key], plan.config)
    assert column[column.index("--intruder_diameter") + 1] == "0" and "--depth" not in column
    assert column[column.index("--seed") + 1] in ("1", "2")
    assert study.place_args(bed, plan.config) == ["--intruder_diameter", "2", "--depth", "3"]
    damped = study.plan(config(settle_damping=1, max_settle_time=12))
    assert study.place_args(bed, damped.config)[4:] == ["--settle_damping", "1", "--max_settle_time", "12"]


def test_a_poured_system_has_no_columns_and_beds_from_pulls_through_the_placed_beds():
    c = config()
    c["systems"]["Q"] = {"beds_from": "P", "pull": {"snapshots": 0}}
    c["sweeps"].append({"name": "paired", "system": "Q", "D": 2, "depth": 3, "V": 0.5})
    plan = study.plan(c)
    assert len(plan.beds) == 8 and len(plan.columns) == 2       # Q's pulls go through P's beds
    pull = plan.pulls["system~Q/D~2/h~3/mu~0.5/kn~2e4/gn~199.05359/seed~1/V~0.5"]
    assert study.poured_bed(pull.bed, c).system == "P" and study.placed(c, "Q")
    c2 = config()
    del c2["systems"]["P"]["placement"]
    assert study.plan(c2).columns == {}


def test_placement_needs_depths_and_no_intruder_in_the_pour():
    c = config()
    c["sweeps"][0] = {"name": "z", "system": "P", "D": 2, "z": 3, "Fr": 1}
    with pytest.raises(study.ConfigError, match="give 'depth', not 'z'"):
        study.plan(c)
    c = config()
    c["systems"]["P"]["pour"]["intruder_x"] = 2
    with pytest.raises(study.ConfigError, match=r"systems\.P\.pour\.intruder_x.*under systems\.P\.placement"):
        study.plan(c)
    c = config()
    c["systems"]["P"]["placement"]["depth"] = 3
    with pytest.raises(study.ConfigError, match="placement"):
        study.validate_config(c)


def test_a_placed_study_costs_its_columns_once_and_each_placement():
    c = config()
    plan = study.plan(c)
    s = study.summary(plan)
    bed = next(iter(plan.beds.values()))
    column = study.column_bed(bed.column_key)
    dt = study.bed_dt(bed, c)
    assert s["columns"] == 2 and s["beds"] == 8
    place = 700 * study.expected_place_time(bed, c) / dt
    assert s["bed_particle_steps"] == pytest.approx(8 * place + 2 * study.expected_column_cost(column, c))
    assert study.bed_cost(bed, c) == pytest.approx(700 * 20 / dt)           # place's max_settle_time
    assert study.column_cost(column, c) == pytest.approx(700 * 20 / dt)     # the pour's
    assert study.expected_place_time(bed, c) == 9.0                          # to the column's 1e-5
    assert study.expected_place_time(bed, config(max_settle_time=5)) == 5
    deep = config(ke_threshold=1e-7)
    assert study.expected_place_time(bed, deep) == 20                          # undamped: runs out
    deep["systems"]["P"]["placement"]["settle_damping"] = 1
    assert study.expected_place_time(bed, deep) == 16.0
    poured = copy.deepcopy(c)
    del poured["systems"]["P"]["placement"]
    # Poured undamped to 1e-5: expected to settle in a time proportional to the column's height.
    settle = study.cost.UNDAMPED_SETTLE_PER_DENSITY * 700 / 64
    assert study.summary(study.plan(poured))["bed_particle_steps"] == pytest.approx(8 * 700 * settle / dt)
    assert study.summary(study.plan(poured))["bed_particle_steps_bound"] == pytest.approx(8 * 700 * 20 / dt)


def test_the_rules_pour_a_column_per_seed_and_place_each_bed(tmp_path):
    configfile = write_config(tmp_path / "c.yaml", config())
    counts = job_counts(snakemake(tmp_path, configfile, "-n", "table").stdout)
    assert counts.get("column") == 2 and counts.get("placed_bed") == 8 and "bed" not in counts, counts
    assert counts.get("pull") == 8 and counts.get("table") == 1, counts


def test_a_placed_study_runs_to_its_table_and_a_new_depth_reuses_the_column(tmp_path):
    c = config()
    c["defaults"]["seeds"] = [1]
    c["sweeps"] = [{"name": "drag", "system": "P", "D": 2, "depth": 3, "Fr": 1}]
    snakemake(tmp_path, write_config(tmp_path / "c.yaml", c), "--cores", "2", "table")
    results = tmp_path / c["results"]
    table = pd.read_csv(results / "table.csv")
    assert len(table) == 1 and table.D.iloc[0] == 2
    column = results / "columns/system~P/mu~0.5/kn~2e4/gn~199.05359/seed~1/column.h5"
    poured = column.stat().st_mtime_ns
    assert (results / "beds/system~P/D~2/h~3/mu~0.5/kn~2e4/gn~199.05359/seed~1/bed.h5").is_file()
    assert (tmp_path / c["logs"] / "columns/system~P/mu~0.5/kn~2e4/gn~199.05359/seed~1.log").is_file()
    c["sweeps"][0]["depth"] = 4
    configfile = write_config(tmp_path / "deeper.yaml", c)
    counts = job_counts(snakemake(tmp_path, configfile, "-n", "table").stdout)
    assert counts.get("placed_bed") == 1 and "column" not in counts, counts
    snakemake(tmp_path, configfile, "--cores", "2", "table")
    assert column.stat().st_mtime_ns == poured
    table = pd.read_csv(results / "table.csv")
    assert len(table) == 1 and table.h.iloc[0] == pytest.approx(4, abs=0.5)
    with open(results / "beds/system~P/D~2/h~4/mu~0.5/kn~2e4/gn~199.05359/seed~1/bed.h5", "rb") as fh:
        assert fh.read(8) == b"\x89HDF\r\n\x1a\n"
    assert yaml.safe_load(configfile.read_text())["systems"]["P"]["placement"] == {}


def test_a_failed_placement_leaves_no_bed_and_says_why(tmp_path):
    c = config()
    c["defaults"]["seeds"] = [1]
    c["sweeps"] = [{"name": "too_deep", "system": "P", "D": 2, "depth": 30, "Fr": 1}]
    r = snakemake(tmp_path, write_config(tmp_path / "c.yaml", c), "--cores", "1", "table", check=False)
    assert r.returncode != 0
    results = tmp_path / c["results"]
    bed = results / "beds/system~P/D~2/h~30/mu~0.5/kn~2e4/gn~199.05359/seed~1/bed.h5"
    assert not bed.exists() and not list(bed.parent.glob("*.tmp*"))
    assert "deeper than the bed" in (bed.parent / "bed.h5.failed").read_text()
    assert (results / "columns/system~P/mu~0.5/kn~2e4/gn~199.05359/seed~1/column.h5").is_file()   # kept


def test_a_placement_killed_mid_run_starts_over_cleanly(tmp_path):
    # Killed once it has claimed its output.
    wrapper, marks = killing_wrapper(tmp_path, "place", until='-e "$out.lock"')
    c = config()
    c.update(granudrag=str(wrapper), max_runtime=10)           # max_runtime: the bed rules retry
    c["defaults"]["seeds"] = [1]
    c["sweeps"] = [{"name": "one", "system": "P", "D": 2, "depth": 3, "Fr": 1}]
    assert study.bed_retries(study.plan(c)) >= 1
    key = "system~P/D~2/h~3/mu~0.5/kn~2e4/gn~199.05359/seed~1"
    snakemake(tmp_path, write_config(tmp_path / "c.yaml", c), "--cores", "1", f"{c['results']}/beds/{key}/bed.h5")
    assert (marks / "killed").exists(), "the first placement was not interrupted"
    bed = tmp_path / c["results"] / "beds" / key / "bed.h5"
    assert not (bed.parent / "bed.h5.failed").exists() and not (bed.parent / "bed.h5.lock").exists()
    log = (tmp_path / c["logs"] / "beds" / f"{key}.log").read_text()
    assert "attempt 1" in log and "attempt 2" in log
    direct = tmp_path / "direct.h5"
    column = tmp_path / c["results"] / "columns" / "system~P/mu~0.5/kn~2e4/gn~199.05359/seed~1/column.h5"
    subprocess.run([str(BINARY), "place", "--bed", str(column), "--output", str(direct), "--threads", "1",
                    *study.place_args(study.Bed.parse(key), c)], check=True, capture_output=True)
    with h5py.File(bed) as a, h5py.File(direct) as b:
        for name in ("particles/all/position/value", "particles/all/velocity/value", "contacts/shear"):
            assert np.array_equal(a[name][:], b[name][:]), name
