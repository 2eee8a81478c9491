"""Failed pulls of a study, as workflow/scripts/resumable.sh leaves them.

A pull whose attempt failed leaves `run.h5.failed` beside where its run file belongs (not a
Snakemake output): `key: value` lines, its exit status, attempt, host, time and reason (the
engine's last error line). The next attempt that finishes removes it. Under `table.allow_failed`,
a pull the engine stopped itself (exit status 1) also leaves a placeholder at `run.h5`, a few
lines of text starting with PLACEHOLDER, so that the job succeeds and the table and the report are
made without the pull and name it (the table also lists it in failed_pulls.txt). At the end of the
run the workflow (its onsuccess/onerror hooks) removes the placeholders and that list: the next run
then makes the table again, which asks for the missing pulls, so it retries them. (A missing run
file alone would not do: Snakemake does not make a missing input again while the files made from
it are up to date.)
"""

from pathlib import Path

PLACEHOLDER = b"granudrag: failed pull placeholder"


def record_path(run):
    """The failure record of the pull whose run file is `run`."""
    return Path(f"{run}.failed")


def is_placeholder(run):
    """True when `run` is a failed pull's placeholder, not a run file."""
    try:
        with open(run, "rb") as fh:
            return fh.read(len(PLACEHOLDER)) == PLACEHOLDER
    except OSError:
        return False


def read_failure(run):
    """The failure record of `run` as a dict (status, attempt, host, at, reason), or None."""
    try:
        text = record_path(run).read_text(errors="replace")
    except OSError:
        return None
    out = {}
    for line in text.splitlines():
        key, sep, value = line.partition(": ")
        if sep:
            out[key.strip()] = value.strip()
    return out


def describe(run, root=None):
    """One line naming a failed pull (its directory relative to `root`) and why it failed."""
    name = Path(run).parent
    if root is not None:
        try:
            name = name.resolve().relative_to(Path(root).resolve())
        except ValueError:
            pass
    rec = read_failure(run) or {}
    when = ", ".join(x for x in (f"exit status {rec['status']}" if "status" in rec else "",
                                 f"attempt {rec['attempt']}" if "attempt" in rec else "",
                                 rec.get("at", "")) if x)
    reason = rec.get("reason", "no failure record (run.h5.failed) beside it")
    return f"{name}: the pull failed ({when or 'no record'}): {reason}"


def remove_placeholders(runs):
    """Remove the placeholders among `runs`; returns their paths."""
    removed = []
    for run in runs:
        if is_placeholder(run):
            Path(run).unlink(missing_ok=True)
            removed.append(run)
    return removed
