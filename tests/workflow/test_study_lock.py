"""tools/study.sh's own lock (docs/reliability.md): one study at a time per working directory,
and a study killed outright is resumed by the same command, with no manual --unlock.

- Two runs at once: the second is refused, naming the first (its pid, start and command), and
  leaves Snakemake's lock of the live one alone; so is a run while a Snakemake started by hand
  works in the directory.
- A study killed with SIGKILL (tools/study.sh, which has become Snakemake, and every job at
  once) while a pull is in flight: the same command again clears Snakemake's stale lock, says
  so, and ends with the table of an uninterrupted run, byte for byte.

tools/study.sh runs here from a copy of it whose installer and build are stand-ins (the engine
under test is built already); the study is one bed and three short pulls. Under Snakemake 9 and
7.21 alike (GRANUDRAG_SNAKEMAKE, workflow_support.py).
"""
import os
import shutil
import signal
import subprocess
import time
from pathlib import Path

import pytest
from test_faults import alive, kill_everything
from workflow_support import (
    NEEDS_SNAKEMAKE_AND_ENGINE,
    ROOT,
    SNAKEFILE,
    SNAKEMAKE,
    command,
    smoke_config,
    snakemake,
    write_config,
)

import granudrag_study as study

pytestmark = NEEDS_SNAKEMAKE_AND_ENGINE


@pytest.fixture(scope="module")
def repo(tmp_path_factory):
    """A copy of tools/study.sh, its installer and cmake stand-ins, and the environment to run it."""
    repo = tmp_path_factory.mktemp("checkout")
    (repo / "tools").mkdir()
    shutil.copy2(ROOT / "tools" / "study.sh", repo / "tools" / "study.sh")
    stubs = repo / "bin"
    stubs.mkdir()
    for stub in (repo / "tools" / "install-deps.sh", stubs / "cmake"):
        stub.write_text("#!/bin/sh\nexit 0\n")
        stub.chmod(0o755)
    env = dict(os.environ, PATH=f"{stubs}:{os.environ['PATH']}", SNAKEMAKE=str(Path(SNAKEMAKE).absolute()))
    return repo, env


def small_config():
    """One system I bed (D = 2, h = 4) pulled at Fr = 0.5, 1, 2 (a checkpoint every tenth)."""
    config = smoke_config()
    del config["systems"]["II"]
    config["sweeps"] = [{"name": "drag", "system": "I", "D": 2, "depth": 4, "Fr": [0.5, 1, 2]}]
    return config


def study_command(repo, workdir):
    config = small_config()
    configfile = write_config(workdir / "small.yaml", config)
    return [str(repo / "tools" / "study.sh"), f"{config['results']}/table.csv", "--snakefile", str(SNAKEFILE),
            "--directory", str(workdir), "--configfile", str(configfile)]


def start(cmd, env, log):
    with open(log, "w") as out:
        return subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT, env=env, start_new_session=True)


def wait_for(proc, condition, what, timeout=600):
    deadline = time.monotonic() + timeout
    while not condition():
        assert proc.poll() is None, f"the study ended before {what}"
        assert time.monotonic() < deadline, f"no {what} after {timeout} s"
        time.sleep(0.05)


def snakemake_locked(workdir):
    locks = workdir / ".snakemake" / "locks"
    return locks.is_dir() and any(locks.iterdir())


def stop(proc):
    killed = kill_everything(proc)
    deadline = time.monotonic() + 10
    while any(alive(pid) for pid in killed) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not [name for pid, name in killed.items() if alive(pid)], "a job outlived the kill"


def test_two_runs_at_once_the_second_is_refused_naming_the_first(repo, tmp_path):
    repo, env = repo
    cmd = study_command(repo, tmp_path)
    first = start(cmd, env, tmp_path / "first.log")
    try:
        wait_for(first, lambda: snakemake_locked(tmp_path), "Snakemake's lock")
        second = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=120)
        assert second.returncode == 1
        said = second.stderr
        assert "refused: another study runs in" in said, said
        assert f"pid {first.pid} on " in said and ", started 20" in said and "tools/study.sh results/" in said, said
        assert "unlock" not in said.lower()
        assert first.poll() is None and snakemake_locked(tmp_path)     # the first run goes on
    finally:
        stop(first)

    # A Snakemake started by hand (no lock of tools/study.sh) in the directory: not unlocked either.
    snakemake(tmp_path, cmd[-1], "--unlock")
    by_hand = start(command(tmp_path, cmd[-1], "--cores", "1", targets=[cmd[1]]), env, tmp_path / "by_hand.log")
    try:
        wait_for(by_hand, lambda: snakemake_locked(tmp_path), "Snakemake's lock")
        third = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=120)
        assert third.returncode == 1
        assert "belongs to a run still at work there" in third.stderr and f"pid {by_hand.pid}: " in third.stderr, \
            third.stderr
        assert by_hand.poll() is None and snakemake_locked(tmp_path)
    finally:
        stop(by_hand)


def test_a_study_killed_with_sigkill_is_resumed_by_the_same_command(repo, tmp_path):
    repo, env = repo
    config = small_config()
    # An uninterrupted run, then the same study killed in a pull after its first checkpoint.
    reference = tmp_path / "uninterrupted"
    reference.mkdir()
    subprocess.run(study_command(repo, reference), check=True, capture_output=True, env=env, timeout=900)
    workdir = tmp_path / "killed"
    workdir.mkdir()
    cmd = study_command(repo, workdir)
    runs = [Path(study.run_file(str(workdir / config["results"]), k)) for k in study.plan(config).pulls]
    run = start(cmd, env, tmp_path / "killed.log")
    wait_for(run, lambda: any(Path(f"{p}.checkpoint.h5").exists() and not p.exists() for p in runs),
             "pull in flight after its checkpoint")
    stop(run)
    assert run.returncode == -signal.SIGKILL and snakemake_locked(workdir)

    again = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=900)
    assert again.returncode == 0, again.stderr[-3000:]
    assert "was left by a run that is no longer alive" in again.stderr and "unlocking it" in again.stderr
    logs = workdir / config["logs"] / "pulls"
    assert any("resuming from" in log.read_text() for log in logs.rglob("*.log")), "no pull resumed"
    table = (workdir / config["results"] / "table.csv").read_bytes()
    assert table == (reference / config["results"] / "table.csv").read_bytes()
