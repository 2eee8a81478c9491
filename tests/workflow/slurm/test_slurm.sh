#!/usr/bin/env bash
# The SLURM path for real: starts a one-node SLURM cluster on this machine (cluster.sh), runs
# the smoke study through workflow/profiles/slurm, checks that the simulations ran as SLURM
# jobs and that the table of results equals a local run's, and shuts the cluster down.
#   test_slurm.sh [path/to/granudrag]
set -euo pipefail
root=$(cd "$(dirname "$0")/../../.." && pwd)
gd=$(realpath "${1:-$root/build/granudrag}")
if [ "$(id -u)" -ne 0 ] && ! sudo -n true 2>/dev/null; then
  echo "SKIPPED: the SLURM daemons need root (run as root or with passwordless sudo)"
  exit 0
fi
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo -E"
work=$(mktemp -d)
cluster="$work/cluster"
cleanup() { $sudo "$root/tests/workflow/slurm/cluster.sh" stop "$cluster" >/dev/null 2>&1 || true; rm -rf "$work"; }
trap cleanup EXIT
eval "$($sudo "$root/tests/workflow/slurm/cluster.sh" start "$cluster")"
echo "cluster up: $(sinfo -h -o '%P %D %t %c cpus')"

/usr/bin/python3 - "$root/config/smoke.yaml" "$work/smoke.yaml" "$gd" <<'PY'
import sys, yaml
config = yaml.safe_load(open(sys.argv[1]))
config["granudrag"] = sys.argv[3]
yaml.safe_dump(config, open(sys.argv[2], "w"), sort_keys=False)
PY
run() {  # run DIR extra-args...
  local dir=$1; shift
  mkdir -p "$dir"
  /usr/bin/snakemake --snakefile "$root/workflow/Snakefile" --directory "$dir" \
    --configfile "$work/smoke.yaml" "$@" > "$dir/snakemake.log" 2>&1 \
    || { echo "FAIL: snakemake $* failed:"; tail -30 "$dir/snakemake.log"; exit 1; }
}
t0=$(date +%s)
run "$work/slurm" --profile "$root/workflow/profiles/slurm" --jobs 4 --cores 2
echo "smoke study through SLURM: $(( $(date +%s) - t0 )) s"
run "$work/local" --cores 2

# The simulations ran as SLURM jobs: each has a SLURM log named after its rule and job id,
# and the controller (which keeps finished jobs for MinJobAge) knows the ids as COMPLETED.
logs=$(ls "$work/slurm/logs/slurm/" 2>/dev/null | grep -cE '^(bed|pull)-[0-9]+\.log$' || true)
[ "$logs" -gt 0 ] || { echo "FAIL: no SLURM job logs of the bed and pull rules"; exit 1; }
ids=$(ls "$work/slurm/logs/slurm/" | sed -nE 's/^(bed|pull)-([0-9]+)\.log$/\2/p')
completed=0
for id in $ids; do
  scontrol show job "$id" 2>/dev/null | grep -q "JobState=COMPLETED" && completed=$((completed + 1))
done
echo "SLURM jobs of the bed and pull rules: $logs logs, $completed known to the controller as COMPLETED"
[ "$completed" -gt 0 ] || { echo "FAIL: the controller knows none of the jobs as completed"; exit 1; }

# Same results as the local run (the smoke simulations use one thread each: bitwise).
/usr/bin/python3 - "$work/slurm" "$work/local" <<'PY'
import sys
from pathlib import Path
import pandas as pd
a, b = (next(Path(d).glob("results/**/table.csv")) for d in sys.argv[1:3])
ta, tb = pd.read_csv(a), pd.read_csv(b)
assert len(ta) == len(tb) > 0, f"{len(ta)} vs {len(tb)} rows"
cols = [c for c in ("D", "h", "mu", "V", "Fr", "drag", "drag_err", "n_contacts", "theta", "Z", "kappa") if c in ta]
key = [c for c in ("system", "D", "h", "mu", "kn", "V") if c in ta]
ta, tb = ta.sort_values(key).reset_index(drop=True), tb.sort_values(key).reset_index(drop=True)
pd.testing.assert_frame_equal(ta[cols], tb[cols], check_exact=True)
print(f"table: {len(ta)} pulls, identical to the local run in {', '.join(cols)}")
PY
echo "PASS: the smoke study ran through SLURM and matches the local run"
