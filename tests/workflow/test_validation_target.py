"""The `validation` target: a validation config's runs, compared with the reference protocol."""
import h5py
import numpy as np
import pandas as pd
import pytest
import yaml
from test_smoke import BINARY, ROOT, job_counts, pytestmark, snakemake, write_config  # noqa: F401


def tiny(name):
    """config/validate/<name>.yaml on a tiny bed, short pulls: the whole DAG in seconds."""
    with open(ROOT / "config" / "validate" / f"{name}.yaml") as fh:
        config = yaml.safe_load(fh)
    config["granudrag"] = str(BINARY)
    return config


def test_every_validation_config_plans_its_comparison(tmp_path):
    for name in ("yield_speed", "box_size", "stiffness"):
        r = snakemake(tmp_path / name, write_config(tmp_path / f"{name}.yaml", tiny(name)), "-n", "validation")
        counts = job_counts(r.stdout)
        assert counts.get("validation") == 1 and counts.get("table") == 1, (name, counts)
        assert counts["pull"] == 24 and "report" not in counts, (name, counts)
    r = snakemake(tmp_path / "pl", write_config(tmp_path / "pl.yaml", tiny("pull_length")), "-n", "validation")
    counts = job_counts(r.stdout)
    assert counts.get("validation") == 1 and counts["pull"] == 16 and counts["bed"] == 4, counts


def test_yield_speed_validation_runs_end_to_end(tmp_path):
    config = tiny("yield_speed")
    config["systems"]["I"].update(lx=8, ly=8, grains=700, pour={"ke_threshold": 1e-5, "max_settle_time": 20})
    config["sweeps"][0].update(D=2, mu=0.5, depth=3, V=[0.05, 0.1], pull={"distance": 0.3, "transient": 0.1})
    r = snakemake(tmp_path, write_config(tmp_path / "c.yaml", config), "--cores", "2", "validation")
    out = tmp_path / config["results"]
    md = (out / "validate_yield_speed.md").read_text()
    assert "V = 0.1 against 0.05" in md and ("instead of 0.05" in md or "keep it" in md), md
    assert (out / "validate_yield_speed.png").stat().st_size > 5000
    assert len((out / "validate_yield_speed.csv").read_text().splitlines()) == 2   # one point, one variant
    assert r.returncode == 0


def test_time_step_validation_pulls_the_same_beds_at_coarser_steps(tmp_path):
    config = tiny("time_step_quick")
    config["defaults"].update(kn=2e4, seeds=[1, 2])
    config["systems"]["T64"].update(lx=8, ly=8, grains=700, pour={"ke_threshold": 1e-5, "max_settle_time": 20},
                                    pull={"distance": 0.4, "transient": 0.1, "max_overlap": 0.2, "snapshots": 1})
    config["sweeps"] = [dict(name=n, system=s, D=2, depth=3, Fr=1) for n, s in
                        (("reference", "T64"), ("t32", "T32"), ("t20", "T20"))]
    r = snakemake(tmp_path, write_config(tmp_path / "c.yaml", config), "--cores", "2", "validation")
    assert r.returncode == 0, r.stderr[-2000:]
    out = tmp_path / config["results"]
    runs = pd.read_csv(out / "runs.csv")
    # Two beds, poured once each, pulled at 64, 32 and 20 steps per collision time.
    assert sorted(runs.collision_steps.round()) == [20, 20, 32, 32, 64, 64]
    assert runs.groupby("seed").dt.agg(lambda dt: dt.max() / dt.min()).tolist() == pytest.approx([3.2, 3.2])
    md = (out / "validate_time_step.md").read_text()
    assert "collision_steps = 32 against 64" in md and "collision_steps = 20 against 64" in md, md
    assert "Fewest steps per collision time that agree with 64" in md, md


def test_pull_length_validation_runs_end_to_end(tmp_path):
    config = tiny("pull_length")
    config["systems"]["I"].update(lx=8, ly=8, grains=700, pour={"ke_threshold": 1e-5, "max_settle_time": 20})
    config["sweeps"] = [dict(name="pull_length", system="I", D=2, mu=0.5, depth=3, Fr=2, seeds=[1],
                             pull={"distance": 1.5, "transient": 0.2})]
    r = snakemake(tmp_path, write_config(tmp_path / "c.yaml", config), "--cores", "2", "validation")
    assert r.returncode == 0, r.stderr[-2000:]
    out = tmp_path / config["results"]
    md = (out / "validate_pull_length.md").read_text()
    assert "mu = 0.5, Fr = 2 (1 bed):" in md and "% error after" in md, md
    # The engine's convergence table: the first 8, 11, 16, 23, 32 samples after the transient and
    # all of them (1.5 d at V = 1.5, one sample per 0.02: 50 samples, about 7 in the transient).
    prefixes = pd.read_csv(out / "validate_pull_length.csv")
    assert list(prefixes.samples[:5]) == [8, 11, 16, 23, 32] and 40 <= prefixes.samples.iloc[-1] <= 45
    # Travel: samples x the sample interval (0.02 rounded to whole steps) x the speed.
    with h5py.File(tmp_path / prefixes.path.iloc[0]) as f:
        per_sample = float(np.diff(f["observables/intruder_force/time"][:2])[0] * f["run"].attrs["speed"])
    assert per_sample == pytest.approx(0.03, rel=0.02)
    assert np.allclose(prefixes.travel, prefixes.samples * per_sample, rtol=1e-9)
    assert (out / "validate_pull_length.png").stat().st_size > 5000


def test_placement_validation_compares_placed_beds_with_poured_ones(tmp_path):
    counts = job_counts(snakemake(tmp_path / "full", write_config(tmp_path / "full.yaml", tiny("placement")),
                                  "-n", "validation").stdout)
    assert (counts["column"], counts["placed_bed"], counts["bed"], counts["pull"]) == (6, 24, 24, 96), counts
    config = tiny("placement_quick")
    config["defaults"].update(kn=2e4, seeds=[1, 2])
    for name in ("poured", "placed"):
        config["systems"][name].update(lx=8, ly=8, grains=700, pour={"ke_threshold": 1e-5, "max_settle_time": 20},
                                       pull={"distance": 0.4, "transient": 0.1, "max_overlap": 0.2, "snapshots": 1})
    config["sweeps"] = [dict(name=n, system=n, D=2, depth=3, Fr=1) for n in ("poured", "placed")]
    r = snakemake(tmp_path, write_config(tmp_path / "c.yaml", config), "--cores", "2", "validation")
    assert r.returncode == 0, r.stderr[-2000:]
    out = tmp_path / config["results"]
    runs = pd.read_csv(out / "runs.csv")
    # Two beds poured with the intruder, two placed into two columns (one per seed).
    assert sorted(runs.placed) == [0, 0, 1, 1] and len(list((out / "columns").rglob("column.h5"))) == 2
    md = (out / "validate_placement.md").read_text()
    assert "placed = 1 against 0: agrees at" in md, md
    assert "as beds poured with the intruder in place" in md or "disagree with the paper's pour" in md, md
    cmp = pd.read_csv(out / "validate_placement.csv")
    assert len(cmp) == 1 and cmp.beds.iloc[0] == 2
