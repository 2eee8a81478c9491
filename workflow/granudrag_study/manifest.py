"""The plan's pulls as a file, an input of the table: a sweep that grows or shrinks remakes the
table by file time alone.

Snakemake notices a changed input list only from its metadata in .snakemake/ (the `input`
re-run trigger). A results directory copied or moved elsewhere, a fresh clone run beside old
results, or `--rerun-triggers mtime` have none: with a value added to a grid, Snakemake would
report nothing to be done and keep the old table, without the new pulls and without a word.
This file is rewritten when the list changes, and only then, so its time stamp says when.
"""

import os
from pathlib import Path


def plan_file(results):
    return f"{results}/plan/pulls.txt"


def write_plan(results, keys):
    """Write the pulls' keys, one a line, sorted, to plan_file(results) if the file does not
    hold them already (atomically: a concurrent reader sees the old list or the new one).
    Returns the file's path."""
    path = Path(plan_file(results))
    text = "".join(f"{k}\n" for k in sorted(keys))
    try:
        if path.read_text() == text:
            return str(path)
    except OSError:
        pass
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(text)
    tmp.replace(path)
    return str(path)
