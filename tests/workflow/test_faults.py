"""Studies under faults (docs/reliability.md): a pull that the engine stops, and the whole study
killed with SIGKILL at random moments.

- A small study (one bed, four pulls) whose pull at Fr = 0.7 stops on the run guard (its sweep sets
  max_overlap = 0.025 d, which that pull's contacts exceed at t = 0.32): with --keep-going the
  other pulls finish; with table.allow_failed the table, the fits, the figures and the report are
  made without it and name it with the engine's reason; each re-run retries that pull and only it
  (and makes what follows from it again).
- The smoke study (table.csv and fits.json only) killed with SIGKILL, Snakemake and every one of
  its jobs at once, at three seeded random moments, and run again each time: its table.csv and
  fits.json are byte for byte those of the uninterrupted smoke study (the fixture `smoke`).

Under Snakemake 9 and 7.21 alike (GRANUDRAG_SNAKEMAKE, workflow_support.py).
"""
import os
import random
import signal
import subprocess
import time
from pathlib import Path

import pandas as pd
from workflow_support import (
    NEEDS_SNAKEMAKE_AND_ENGINE,
    command,
    job_counts,
    smoke_config,
    snakemake,
    write_config,
)

import granudrag_study as study
from granudrag_study import failures

pytestmark = NEEDS_SNAKEMAKE_AND_ENGINE

FRAGILE = "Fr~0.7"   # the pull that fails: its sweep's max_overlap is below what its contacts reach


def fragile_config(allow_failed, max_overlap=0.025):
    """One system I bed (D = 2, h = 4) pulled at Fr = 0.5, 1, 2 and, in a sweep of its own with a
    smaller max_overlap, at Fr = 0.7; Fig. 9's one panel is the Fr = 0.7 pull, Fig. 4 the Fr = 2."""
    config = smoke_config()
    del config["systems"]["II"]
    config["sweeps"] = [
        {"name": "drag", "system": "I", "D": 2, "depth": 4, "Fr": [0.5, 1, 2]},
        {"name": "fragile", "system": "I", "D": 2, "depth": 4, "Fr": 0.7, "pull": {"max_overlap": max_overlap}},
    ]
    config["restitution"] = {"points": 3}
    config["report"] = {"n_boot": 10, "trace": {"system": "I", "D": 2, "mu": 0.5, "V": 1.5},
                        "flow_field": [{"D": 2, "V": 0.5}]}
    config["table"] = {"allow_failed": allow_failed}
    return config


def dry_run(workdir, configfile):
    r = snakemake(workdir, configfile, "--dry-run", "--quiet", "rules")
    return r.stdout + r.stderr


def mtimes(paths):
    return {p: p.stat().st_mtime_ns for p in paths}


def test_a_failed_pull_lets_the_others_finish_is_listed_with_its_reason_and_is_retried_alone(tmp_path):
    config = fragile_config(allow_failed=False)
    plan = study.plan(config)
    assert len(plan.beds) == 1 and len(plan.pulls) == 4
    runs = {Path(study.run_file(str(tmp_path / config["results"]), key)).parent.name:
            Path(study.run_file(str(tmp_path / config["results"]), key)) for key in plan.pulls}
    fragile, others = runs[FRAGILE], [p for name, p in runs.items() if name != FRAGILE]
    results = tmp_path / config["results"]

    # 1. Without table.allow_failed: the pull fails, the others finish (--keep-going), no table.
    strict = write_config(tmp_path / "strict.yaml", config)
    r = snakemake(tmp_path, strict, "--cores", "2", "--keep-going", targets=[f"{config['results']}/table.csv"],
                  check=False)
    assert r.returncode != 0
    assert all(p.is_file() for p in others) and not fragile.exists()
    assert not (results / "table.csv").exists()
    record = failures.read_failure(fragile)
    assert record["status"] == "1" and "exceeds max_overlap = 0.025" in record["reason"], record
    assert f"{FRAGILE}: the pull failed" in r.stdout + r.stderr
    done = mtimes(others + [Path(study.bed_file(str(results), k)) for k in plan.beds])

    # 2. With table.allow_failed: the re-run retries that pull alone, which stops again (same
    # options, resumed from the checkpoint the stop kept); the table, fits, figures and report are
    # made without it and name it with the engine's reason.
    config["table"]["allow_failed"] = True
    lenient = write_config(tmp_path / "lenient.yaml", config)
    counts = job_counts(dry_run(tmp_path, lenient))
    assert counts.get("pull") == 1 and "bed" not in counts, counts
    r = snakemake(tmp_path, lenient, "--cores", "2", "--keep-going")
    assert mtimes(done) == done                                   # nothing else simulated again
    log = (tmp_path / config["logs"] / "pulls" / f"{fragile.parent.relative_to(results / 'pulls')}.log").read_text()
    assert "resuming from" in log and "exceeds max_overlap = 0.025" in log
    table = pd.read_csv(results / "table.csv")
    assert sorted(table.Fr.round(6)) == [0.5, 1, 2]
    problems = (results / "table_problems.txt").read_text().splitlines()
    assert len(problems) == 1 and FRAGILE in problems[0] and "exceeds max_overlap = 0.025" in problems[0]
    for name in ("report.md", "report.html"):
        text = (results / "report" / name).read_text()
        assert "Pulls left out of the table" in text and FRAGILE in text and "exceeds max_overlap" in text, name
    assert "left out of Fig. 9" in (tmp_path / config["logs"] / "flow_field.log").read_text()
    assert "1 of 4 pulls failed" in r.stdout + r.stderr
    # The placeholder that stood for it is gone with failed_pulls.txt, its reason stays: the next
    # run makes the table again, retrying that pull and only it.
    assert not fragile.exists() and not (results / "failed_pulls.txt").exists()
    assert failures.read_failure(fragile)["status"] == "1"
    counts = job_counts(dry_run(tmp_path, lenient))
    assert counts.get("pull") == 1 and "bed" not in counts, counts

    # 3. The fault lifted (the sweep's max_overlap raised): the retry finishes and the table is whole.
    fixed = write_config(tmp_path / "fixed.yaml", fragile_config(allow_failed=True, max_overlap=0.1))
    snakemake(tmp_path, fixed, "--cores", "2", "--keep-going", targets=[f"{config['results']}/table.csv"])
    assert mtimes(done) == done
    assert fragile.is_file() and not failures.is_placeholder(fragile) and failures.read_failure(fragile) is None
    assert sorted(pd.read_csv(results / "table.csv").Fr.round(6)) == [0.5, 0.7, 1, 2]
    assert (results / "table_problems.txt").read_text() == ""


# --- the study killed with SIGKILL ---------------------------------------------------------

KILL_SEED = 32          # the kill moments are drawn from it: the same three every time
KILLS = 3


def process_tree(root):
    """root and every process descended from it (from /proc)."""
    parents = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                stat = (entry / "stat").read_text()
            except OSError:
                continue
            parents[int(entry.name)] = int(stat.rsplit(")", 1)[1].split()[1])
    tree, grew = {root}, True
    while grew:
        more = {pid for pid, ppid in parents.items() if ppid in tree} - tree
        tree |= more
        grew = bool(more)
    return tree


def signal_all(pids, sig):
    for pid in pids:
        try:
            os.kill(pid, sig)
        except ProcessLookupError:
            pass


def kill_everything(proc):
    """SIGKILL Snakemake and every process it started, at once: the process group is stopped
    first (SIGSTOP: nothing forks or finishes meanwhile), with any descendant outside it, then
    everything is killed. Returns {pid: command name} of the processes killed."""
    os.killpg(proc.pid, signal.SIGSTOP)
    tree, seen = process_tree(proc.pid), set()
    while tree - seen:
        signal_all(tree - seen, signal.SIGSTOP)
        seen |= tree
        tree = process_tree(proc.pid) | seen
    names = {}
    for pid in tree:
        try:
            names[pid] = Path(f"/proc/{pid}/comm").read_text().strip()
        except OSError:
            pass
    os.killpg(proc.pid, signal.SIGKILL)
    signal_all(tree, signal.SIGKILL)
    proc.wait(timeout=60)
    return names


def alive(pid):
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def test_a_study_killed_three_times_at_random_moments_ends_as_an_uninterrupted_one(smoke, tmp_path):
    """Each kill comes once a seeded random number of the study's beds and pulls exist (and,
    among the pulls, once a pull has checkpointed), after a seeded random delay of up to half a
    second: during Snakemake's start, a pour, a pull after its checkpoint.
    Each re-run: `--unlock` (a killed Snakemake leaves its lock), then the same command with
    --rerun-incomplete; killed pulls resume from their checkpoints."""
    reference = smoke[0] / "uninterrupted"
    config = smoke_config()
    configfile = write_config(tmp_path / "smoke.yaml", config)
    results = tmp_path / config["results"]
    plan = study.plan(config)
    simulations = [Path(study.bed_file(str(results), k)) for k in plan.beds] + \
                  [Path(study.run_file(str(results), k)) for k in plan.pulls]
    targets = [f"{config['results']}/table.csv", f"{config['results']}/report/fits.json"]
    cmd = command(tmp_path, configfile, "--cores", "2", "--rerun-incomplete", targets=targets)
    rng = random.Random(KILL_SEED)
    # One kill in each third of the simulations: among the pours, among the pulls, near the end
    # (at most once every simulation but the last exists: the table and the fits follow).
    thirds = [round(len(simulations) * i / KILLS) for i in range(KILLS + 1)]
    thresholds = [rng.randrange(a, b) for a, b in zip(thirds, thirds[1:])]
    delays = [rng.uniform(0, 0.5) for _ in range(KILLS)]
    pulls = simulations[len(plan.beds):]

    def in_a_pull():
        """A pull has checkpointed and not finished (so that the kill tests a resume)."""
        return any(Path(f"{p}.checkpoint.h5").exists() and not p.exists() for p in pulls)
    landed = []
    for k, (threshold, delay) in enumerate(zip(thresholds, delays)):
        if k:
            snakemake(tmp_path, configfile, "--unlock")
        with open(tmp_path / f"run{k}.log", "w") as out:
            proc = subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT, start_new_session=True)
        start = time.monotonic()
        while proc.poll() is None and (sum(p.exists() for p in simulations) < threshold
                                       or threshold >= len(plan.beds) and not in_a_pull()):
            time.sleep(0.02)
        time.sleep(delay)
        # The checkpointed pull may have finished within the delay: wait for one in flight again,
        # or the kill lands before any checkpoint and no resume is tested.
        while proc.poll() is None and threshold >= len(plan.beds) and not in_a_pull():
            time.sleep(0.02)
        assert proc.poll() is None, f"kill {k + 1}: the study finished before it ({threshold} simulations, " \
                                    f"{delay:.2f} s); see {tmp_path}/run{k}.log"
        killed = kill_everything(proc)
        assert proc.returncode == -signal.SIGKILL
        deadline = time.monotonic() + 10
        while any(alive(pid) for pid in killed) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert not [name for pid, name in killed.items() if alive(pid)], "a job outlived the kill"
        landed.append(f"{time.monotonic() - start:.1f} s into run {k + 1}, {threshold} of {len(simulations)} "
                      f"simulations done: killed {sorted(killed.values())}")
    print("\n".join(landed))
    snakemake(tmp_path, configfile, "--unlock")
    r = snakemake(tmp_path, configfile, "--cores", "2", "--rerun-incomplete", targets=targets)
    assert "Nothing to be done" not in r.stdout + r.stderr   # the kills left work to do
    logs = tmp_path / config["logs"] / "pulls"
    assert any("resuming from" in log.read_text() for log in logs.rglob("*.log")), "no pull resumed"
    assert (results / "table.csv").read_bytes() == (reference / "table.csv").read_bytes()
    assert (results / "report" / "fits.json").read_bytes() == (reference / "fits.json").read_bytes()
