#!/usr/bin/env bash
# Runs one rung of the reproduction ladder and records it under results/reproduction/:
#   tools/ladder.sh config/ladder/crossover-k2e6-box12.yaml [snakemake arguments]
# runs the study (tools/study.sh --configfile CONFIG, timed from start to end), then copies its
# small result files (table, fits, report, kappa shells) with the measured wall time, the
# core-hours of its jobs and the machine into results/reproduction/<rung>/, and regenerates the
# ladder table and figures (granudrag-analysis ladder table results/reproduction).
# Only a whole study run here is timed: if the rung's results directory holds beds or pulls (a
# finished or an interrupted study, whose resumed run would be timed from the resume), nothing is measured and
# the script stops (delete the directory to measure the rung again). The installation and the
# engine's build come first and are not timed.
set -euo pipefail
cd "$(dirname "$0")/.."
config=${1:?usage: tools/ladder.sh config/ladder/RUNG.yaml [snakemake arguments]}
shift
[ -f "$config" ] || { echo "tools/ladder.sh: no config '$config' (the rungs: config/ladder/*.yaml)" >&2; exit 2; }
results=$(/usr/bin/python3 -c 'import sys, yaml; print(yaml.safe_load(open(sys.argv[1])).get("results", "results"))' "$config")
# Beds or pulls, not the directory: a dry run leaves only the plan's list of pulls there.
if [ -e "$results/beds" ] || [ -e "$results/pulls" ]; then
  echo "tools/ladder.sh: $results holds beds or pulls, so the whole study's wall time cannot be measured here;" >&2
  echo "  delete $results to run the rung again, or record a measured run by hand with" >&2
  echo "  .venv/bin/granudrag-analysis ladder collect --config $config --results $results --wall-seconds S --cores N" >&2
  exit 2
fi
tools/study.sh --configfile "$config" --dry-run --quiet >/dev/null   # installs and builds, runs nothing
started=$(date -u +%Y-%m-%dT%H:%M:%SZ)
t0=$(date +%s)
tools/study.sh --configfile "$config" "$@"
wall=$(( $(date +%s) - t0 ))
.venv/bin/granudrag-analysis ladder collect --config "$config" --results "$results" \
  --wall-seconds "$wall" --cores "$(nproc)" --started "$started"
.venv/bin/granudrag-analysis ladder table results/reproduction
echo "tools/ladder.sh: $(basename "$config" .yaml) took ${wall} s on $(nproc) cores; results/reproduction/README.md"
