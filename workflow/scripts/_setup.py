"""Shared start of the workflow's Python scripts: import path and logging to the rule's log."""
import logging
import sys


def start(snakemake):
    """Put the repository on sys.path (for `analysis`) and log to the rule's log file."""
    repo = snakemake.params.repo
    if repo not in sys.path:
        sys.path.insert(0, repo)
    log = snakemake.log[0] if len(snakemake.log) else None
    logging.basicConfig(filename=log, level=logging.INFO, format="%(message)s", force=True)
    return logging.getLogger(snakemake.rule)
