"""The common start of the workflow's scripts (workflow/scripts/*.py)."""

import logging


def start(snakemake):
    """Log to the rule's log file (standard error if it has none); returns the logger."""
    log = snakemake.log[0] if len(snakemake.log) else None
    logging.basicConfig(filename=log, level=logging.INFO, format="%(message)s", force=True)
    return logging.getLogger(snakemake.rule)
