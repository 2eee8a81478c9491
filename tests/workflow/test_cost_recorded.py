"""The cost estimate against the reproduction ladder's recorded rungs (granudrag_study.recorded).

Each rung's estimate is computed here from the config it ran (results/reproduction/<rung>/
config.yaml) and compared with the CPU its run.json recorded; nothing below is a stored result.
"""
import subprocess
from pathlib import Path

import pytest

import granudrag_study as study
from granudrag_study import cost, recorded

ROOT = Path(__file__).resolve().parents[2]
RECORDED = ROOT / "results" / "reproduction"
BOUND = 0.15     # the promise of docs (config/README.md, "How close the estimate comes")


def test_every_recorded_rung_and_the_default_study_is_within_15_percent():
    rows = {r["rung"]: r for r in recorded.check(RECORDED)}
    assert "config" in rows                                   # the default study, config/config.yaml
    assert len(rows) >= 15
    far = {name: round(r["ratio"], 3) for name, r in rows.items() if abs(r["ratio"] - 1) > BOUND}
    assert not far, f"measured / estimate beyond {BOUND:.0%}: {far}"
    for r in rows.values():
        assert r["jobs"] == r["recorded_jobs"]                # the plan is the jobs that ran


def test_the_benchmark_loses_what_a_job_used_after_its_last_sample():
    # Snakemake samples every 0.5 s for 15 s, then every 30 s, and keeps the last sample.
    assert recorded.lost_to_sampling(5.0) == 0.25
    assert recorded.lost_to_sampling(20.0) == pytest.approx(5.0)
    assert recorded.lost_to_sampling(45.0) == recorded.lost_to_sampling(3600.0) == 15.0


def test_a_rung_is_priced_at_the_machine_it_started_on():
    (first, rate1), (second, rate2) = cost.LADDER_MACHINES
    assert recorded.machine_throughput("2026-11-25T20:33:54Z") == rate1
    assert recorded.machine_throughput("2026-11-30T14:03:46Z") == rate2
    assert rate2 < rate1
    with pytest.raises(ValueError):
        recorded.machine_throughput("2026-11-01")


def test_a_pull_costs_its_steps_and_its_grains_start_and_time():
    config = {"threads": 1, "throughput": 1e7, "defaults": {"kn": 2e4, "mu": 0.5, "seed": 1},
              "systems": {"I": {"lx": 8, "ly": 8, "grains": 800, "pull": {"distance": 2}}},
              "sweeps": [{"name": "yield", "system": "I", "D": 2, "depth": 4, "V": 0.1}]}
    pull = next(iter(study.plan(config).pulls.values()))
    extra = 800 * (cost.PULL_START_STEPS + cost.PULL_TIME_STEPS * 2 / 0.1)
    assert study.pull_work(pull, config) == pytest.approx(study.pull_cost(pull, config) + extra)


def test_estimate_cost_prints_the_recorded_rungs_against_their_measurement():
    out = subprocess.run(["/usr/bin/python3", str(ROOT / "workflow/scripts/estimate_cost.py"),
                          "--check-recorded", str(RECORDED)], capture_output=True, text=True, check=True).stdout
    assert "crossover-k2e6-box40 " in out and "default-1bed" in out and "measured / estimate" in out
