"""The plan's pulls as a file, an input of the table: a sweep that grows or shrinks remakes the
table by file time alone.

Snakemake notices a changed input list only from its metadata in .snakemake/ (the `input`
re-run trigger). A results directory copied or moved elsewhere, a fresh clone run beside old
results, or `--rerun-triggers mtime` have none: with a value added to a grid, Snakemake would
report nothing to be done and keep the old table, without the new pulls and without a word.
This file is rewritten when the list changes, and only then, so its time stamp says when.
"""

import os
import tempfile
from pathlib import Path


def plan_file(results):
    return f"{results}/plan/pulls.txt"


def _holds(path, text):
    try:
        return path.read_text() == text
    except (OSError, ValueError):   # missing, unreadable, or not text: rewrite it
        return False


def write_plan(results, keys):
    """Write the pulls' keys, one a line, sorted, to plan_file(results) unless the file holds
    them already; atomically (a reader sees the old list or the new one), and safe when several
    processes parse the same config at once (cluster jobs on a shared file system). Returns the
    file's path."""
    path = Path(plan_file(results))
    text = "".join(f"{k}\n" for k in sorted(keys))
    if _holds(path, text):
        return str(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    except OSError:
        if not _holds(path, text):   # another process wrote the same list first: fine
            raise
    finally:
        Path(tmp).unlink(missing_ok=True)
    return str(path)
