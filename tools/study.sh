#!/usr/bin/env bash
# Runs the study end to end: installs the missing Debian packages (sudo when not root) and
# the project environment .venv/ (Snakemake 9, pinned), builds the engine in build/, runs the
# Snakemake workflow with every core, and says where the report is. Arguments go to
# Snakemake, e.g.
#   tools/study.sh                                   # the default study (config/config.yaml)
#   tools/study.sh --configfile config/paper.yaml --profile workflow/profiles/slurm
#   tools/study.sh --dry-run                         # list the jobs, run nothing
# SNAKEMAKE=/usr/bin/snakemake tools/study.sh ...    runs Debian's Snakemake 7.21 instead (its
# SLURM profile: workflow/profiles/slurm-v7).
# Interrupted? Run it again: finished jobs are kept, a killed pull resumes from its checkpoint.
# A job that fails does not stop the others (--keep-going); with table.allow_failed a pull the
# engine stopped is listed in the table's problems and the report, and the next run retries it
# (docs/reliability.md).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh study
# Always an up-to-date engine (an incremental build is seconds); the workflow's own build rule
# only builds a missing binary, and does not make finished results out of date.
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)" --target granudrag >/dev/null
# The project environment's Snakemake (or $SNAKEMAKE), not whichever comes first on PATH.
"${SNAKEMAKE:-.venv/bin/snakemake}" --cores all --rerun-incomplete --keep-going "$@"
