"""A pour that needs two jobs: the bed rule's first job is killed (SIGKILL, as a cluster's time
limit does) right after the pour's first checkpoint, Snakemake retries it, the retry resumes
from the checkpoint, and the bed is bit for bit the one an uninterrupted pour gives.

The kill is event-driven (a wrapper around granudrag waits for the checkpoint file to appear),
never a wall-clock delay. The engine: $GRANUDRAG if set, else build/granudrag.
"""
import copy
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest
import yaml
from workflow_support import BINARY, ROOT, killing_wrapper

import granudrag_study as study

SNAKEMAKE = "/usr/bin/snakemake"

pytestmark = [
    pytest.mark.skipif(not Path(SNAKEMAKE).exists(), reason="Debian's snakemake is not installed"),
    pytest.mark.skipif(not BINARY.exists(), reason=f"no granudrag binary at {BINARY} (build it first)"),
]


def test_a_pour_killed_after_a_checkpoint_is_finished_by_the_retry_with_the_same_bed(tmp_path):
    # Killed as soon as its first checkpoint exists.
    wrapper, marks = killing_wrapper(tmp_path, "pour", until='-f "$out.checkpoint.h5"')
    with open(ROOT / "config" / "smoke.yaml") as fh:
        config = yaml.safe_load(fh)
    config = copy.deepcopy(config)
    config["granudrag"] = str(wrapper)
    # One bed that settles for its whole max_settle_time, estimated (at a low throughput) to
    # take longer than max_runtime / 4: the workflow gives it checkpoints and retries.
    config["systems"]["I"]["pour"] = {"ke_threshold": 1e-12, "max_settle_time": 10}
    config["sweeps"] = [{"name": "one", "system": "I", "D": 2, "depth": 4, "Fr": 1}]
    config.update(throughput=1.6e4, max_runtime=10)  # ~20 min estimated: 8 checkpoints
    plan = study.plan(config)
    (bed,) = plan.beds.values()
    args = study.pour_args(bed, config)
    assert "--checkpoint_interval" in args
    assert study.bed_retries(plan) >= 1
    configfile = tmp_path / "config.yaml"
    configfile.write_text(yaml.safe_dump(config, sort_keys=False))
    target = Path(config["results"]) / "beds" / bed.key / "bed.h5"
    cmd = [SNAKEMAKE, "--snakefile", str(ROOT / "workflow" / "Snakefile"), "--directory", str(tmp_path),
           "--configfile", str(configfile), "--cores", "1", str(target)]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, r.stderr[-4000:]
    assert (marks / "killed").exists(), "the first pour was not interrupted"
    bed_path = tmp_path / target
    assert bed_path.exists() and not Path(f"{bed_path}.checkpoint.h5").exists()
    log = (tmp_path / config["logs"] / "beds" / f"{bed.key}.log").read_text()
    assert "resuming from" in log

    direct = tmp_path / "direct.h5"
    subprocess.run([str(BINARY), "pour", "--output", str(direct), "--threads", str(config["threads"]), *args],
                   check=True, capture_output=True)
    with h5py.File(bed_path, "r") as a, h5py.File(direct, "r") as b:
        for name in ("particles/all/position/value", "particles/all/velocity/value",
                     "particles/all/angular_velocity/value", "contacts/shear", "bed/profile/packing_fraction"):
            assert np.array_equal(a[name][:], b[name][:]), name
