"""What the workflow tests share: the engine, the Snakemake under test and how to call it.

The engine: $GRANUDRAG if set, else build/granudrag (tools/test.sh builds it). The Snakemake:
$GRANUDRAG_SNAKEMAKE if set (tools/test.sh runs the workflow tests with the project environment's
Snakemake 9, .venv/bin/snakemake, and with Debian's 7.21), else Debian's /usr/bin/snakemake.
"""
import os
import re
import subprocess
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
SNAKEFILE = ROOT / "workflow" / "Snakefile"
SNAKEMAKE = os.environ.get("GRANUDRAG_SNAKEMAKE", "/usr/bin/snakemake")
BINARY = Path(os.environ.get("GRANUDRAG", ROOT / "build" / "granudrag")).resolve()

NEEDS_SNAKEMAKE_AND_ENGINE = [
    pytest.mark.skipif(not Path(SNAKEMAKE).exists(), reason=f"no Snakemake at {SNAKEMAKE}"),
    pytest.mark.skipif(not BINARY.exists(), reason=f"no granudrag binary at {BINARY} (build it first)"),
]


def snakemake_major():
    """The major version of SNAKEMAKE (7 for Debian's 7.21, 9 for the project environment's)."""
    r = subprocess.run([SNAKEMAKE, "--version"], capture_output=True, text=True, timeout=120)
    return int(r.stdout.strip().split(".")[0])


def command(workdir, configfile, *args, targets=()):
    """The Snakemake command line: targets first (--configfile takes every word after it)."""
    return [SNAKEMAKE, *targets, "--snakefile", str(SNAKEFILE), "--directory", str(workdir),
            "--configfile", str(configfile), *args]


def snakemake(workdir, configfile, *args, check=True, targets=()):
    cmd = command(workdir, configfile, *args, targets=targets)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
    if check and r.returncode != 0:
        pytest.fail(f"{' '.join(cmd)} failed ({r.returncode}):\n{r.stderr[-4000:]}")
    return r


def smoke_config():
    """config/smoke.yaml with the engine under test."""
    with open(ROOT / "config" / "smoke.yaml") as fh:
        config = yaml.safe_load(fh)
    config["granudrag"] = str(BINARY)
    return config


def write_config(path, config):
    path.write_text(yaml.safe_dump(config, sort_keys=False))
    return path


def job_counts(output):
    """{rule: count} from the 'Job stats' table of a (dry) run."""
    counts, in_table = {}, False
    for line in output.splitlines():
        if line.startswith("job ") and "count" in line:
            in_table = True
            continue
        m = re.match(r"^(\w+)\s+(\d+)(\s+\d+\s+\d+)?\s*$", line)
        if in_table and m and m.group(1) != "total":
            counts[m.group(1)] = int(m.group(2))
    return counts


# The first `granudrag <command>` is killed (SIGKILL, as a cluster's time limit does) as soon as
# `until` holds, a bash test on its --output path $out; the file `killed` in `marks` then says
# so. Every other call runs granudrag itself. The kill waits on an event, never on the clock.
KILLING_WRAPPER = """#!/usr/bin/env bash
real={binary}
marks={marks}
if [ "$1" = {command} ] && [ ! -e "$marks/started" ]; then
  touch "$marks/started"
  out="" prev=""
  for a in "$@"; do [ "$prev" = --output ] && out=$a; prev=$a; done
  "$real" "$@" &
  pid=$!
  while kill -0 "$pid" 2>/dev/null && ! [ {until} ]; do sleep 0.02; done
  if kill -9 "$pid" 2>/dev/null; then
    wait "$pid" 2>/dev/null
    touch "$marks/killed"
    exit 137
  fi
  wait "$pid"
  exit $?
fi
exec "$real" "$@"
"""


def killing_wrapper(tmp_path, command, until):
    """(wrapper, marks): an executable standing in for granudrag that kills the first `command`
    once `until` holds (KILLING_WRAPPER)."""
    marks = tmp_path / "marks"
    marks.mkdir()
    wrapper = tmp_path / "granudrag"
    wrapper.write_text(KILLING_WRAPPER.format(binary=BINARY, marks=marks, command=command, until=until))
    wrapper.chmod(0o755)
    return wrapper, marks
