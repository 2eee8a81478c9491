#!/usr/bin/env bash
# The SLURM paths for real: starts a one-node SLURM cluster with accounting on this machine
# (cluster.sh: slurmctld, slurmd, slurmdbd on a MariaDB server), then
#   1. runs two of the smoke study's sweeps (below) to their table and fits (targets `table
#      fits`: the beds, the pulls, the table and the fits) through workflow/profiles/slurm with Snakemake 9 (the project environment's, .venv/bin/snakemake,
#      and its SLURM executor plugin, which follows the jobs through sacct), and through
#      workflow/profiles/slurm-v7 with Debian's Snakemake 7.21; checks that the beds, pulls,
#      table and fits ran as SLURM jobs that accounting (sacct) knows as COMPLETED, under the
#      account and partition given by SBATCH_ACCOUNT/SBATCH_PARTITION, and that each table of
#      results equals a local run's. The figures and the report are left out: they are rules
#      like the table (a Python script, one thread), submitted the same way, and each is a
#      SLURM job of 6-10 s under Snakemake 9 (its plugin starts Snakemake twice per job);
#      the workflow tests draw them under both Snakemake generations;
#   2. with a 1-minute time limit on the pull rule (--set-resources pull:runtime=1, as
#      max_runtime gives on a cluster; the config's max_runtime is 10 minutes at least), runs one
#      pull that needs longer, through each profile: SLURM kills the first job at its time limit
#      (sacct: TIMEOUT), Snakemake submits the next attempt, which resumes from the checkpoint
#      and completes;
# and shuts the cluster down. Prints how long each path took.
#   test_slurm.sh [path/to/granudrag]      (GRANUDRAG_SNAKEMAKE9: another Snakemake >= 8)
set -euo pipefail
root=$(cd "$(dirname "$0")/../../.." && pwd)
gd=$(realpath "${1:-$root/build/granudrag}")
sm9=${GRANUDRAG_SNAKEMAKE9:-$root/.venv/bin/snakemake}
sm7=/usr/bin/snakemake
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
t0=$SECONDS
eval "$($sudo "$root/tests/workflow/slurm/cluster.sh" start "$cluster")"
# The SLURM executor plugin's job step drops every SLURM_* variable but the job's ids before
# it calls srun inside the job, SLURM_CONF too: srun then looks for the machine's
# /etc/slurm/slurm.conf, which a real cluster has and this test cluster leaves alone. An srun
# first on PATH (sbatch passes PATH to the job) gives it the test cluster's config back.
mkdir -p "$work/bin"
printf '#!/bin/sh\nSLURM_CONF=%s exec %s "$@"\n' "$SLURM_CONF" "$(command -v srun)" > "$work/bin/srun"
chmod +x "$work/bin/srun"
export PATH="$work/bin:$PATH"
echo "cluster up in $((SECONDS - t0)) s: $(sinfo -h -o '%P %D %t %c cpus'); accounting: $(sacctmgr -n -P list cluster format=cluster)"

# The smoke config on this binary, cut to two of its sweeps: system I's drag at D = 2 (one bed,
# three speeds: the bed the time-limit pull below goes through) and system II's replicate beds
# (two seeds of one point, which the table combines). Both systems, both kinds of bed, every
# rule up to the fits, in 10 SLURM jobs per generation instead of the whole smoke study's 21;
# the workflow tests run all of it. (The time-limit config is written below, once a pull has
# been timed on this machine.)
/usr/bin/python3 - "$root/config/smoke.yaml" "$work" "$gd" <<'PY'
import sys, yaml
src, work, gd = sys.argv[1:4]
config = yaml.safe_load(open(src))
config["granudrag"] = gd
sweeps = {s["name"]: s for s in config["sweeps"]}
config["sweeps"] = [dict(sweeps["drag"], D=2), sweeps["kn"]]
yaml.safe_dump(config, open(f"{work}/smoke.yaml", "w"), sort_keys=False)
PY
run() {  # run DIR SNAKEMAKE CONFIG extra-args...: a run, its log in DIR/snakemake.log
  local dir=$1 sm=$2 cfg=$3; shift 3
  mkdir -p "$dir"
  "$sm" --snakefile "$root/workflow/Snakefile" --directory "$dir" --configfile "$cfg" "$@" \
    > "$dir/snakemake.log" 2>&1 || { echo "FAIL: $sm $* failed:"; tail -30 "$dir/snakemake.log"; exit 1; }
}
# `sacct` of the jobs run from DIR: id|name|state|account|partition, one line per job (the runs
# below go side by side, so their jobs are told apart by their working directory).
jobs_in() { sacct -n -X -P -S now-2hours -o JobID,JobName,State,Account,Partition,WorkDir \
  | grep -F "|$1" | cut -d'|' -f1-5 || true; }

export SBATCH_ACCOUNT=granudrag SBATCH_PARTITION=debug
# The plugin asks sacct 40 s after a submission, then every 40 s or more: right for a cluster,
# slow for jobs of seconds; 3 s here.
fast=(--slurm-init-seconds-before-status-checks 3)
# The two generations and the local reference at once: the SLURM runs spend most of their time
# waiting on the scheduler and accounting (193 and 131 s one after the other, for jobs of seconds).
t=$SECONDS
run "$work/slurm9" "$sm9" "$work/smoke.yaml" --profile "$root/workflow/profiles/slurm" --jobs 4 "${fast[@]}" table fits &
pid9=$!
run "$work/slurm7" "$sm7" "$work/smoke.yaml" --profile "$root/workflow/profiles/slurm-v7" --jobs 4 --cores 2 table fits &
pid7=$!
run "$work/local" "$sm7" "$work/smoke.yaml" --cores 2 table &
pidlocal=$!
wait $pid9 || exit 1
wait $pid7 || exit 1
wait $pidlocal || exit 1
echo "two of the smoke study's sweeps, to the table and the fits, through Snakemake 9 + slurm, 7.21 + slurm-v7 and locally, side by side: $((SECONDS - t)) s"
sleep 2   # slurmctld sends the last job's end to slurmdbd asynchronously
for gen in 9 7; do
  # Accounting: the run's jobs (beds, pulls, the table and the fits) as COMPLETED under the
  # account and partition asked for. Snakemake 9 names its jobs after the run's id, 7's profile
  # after the rule.
  new=$(jobs_in "$work/slurm$gen")
  n=$(grep -c . <<<"$new" || true)
  done_ok=$(grep -cE '\|COMPLETED\|granudrag\|debug$' <<<"$new" || true)
  echo "Snakemake $gen through SLURM: $n jobs in accounting, $done_ok COMPLETED under account granudrag, partition debug"
  # every bed and pull the run made, the table and the fits at least
  sims=$(find "$work/slurm$gen/results" \( -name bed.h5 -o -name run.h5 \) | wc -l)
  { [ "$sims" -ge 7 ] && [ "$done_ok" -ge $((sims + 2)) ] && [ "$done_ok" -eq "$n" ]; } \
    || { echo "FAIL: $sims beds and pulls made; sacct:"; echo "$new"; exit 1; }
done

# Same results as the local run (the smoke simulations use one thread each: bitwise).
/usr/bin/python3 - "$work/slurm9" "$work/slurm7" "$work/local" <<'PY'
import sys
from pathlib import Path
import pandas as pd
def table(d):
    t = pd.read_csv(next(Path(d).glob("results/**/table.csv")))
    key = [c for c in ("system", "D", "h", "mu", "kn", "V") if c in t]
    return t.sort_values(key).reset_index(drop=True)
local = table(sys.argv[3])
# The engine's numbers must be bitwise equal. drag_err is a statistic of the force series
# computed by numpy, whose summation order differs between Debian's numpy and the project
# environment's (SIMD, pairwise blocks): it is compared to 1e-12 relative, far below any
# difference a change of data could make.
cols = [c for c in ("D", "h", "mu", "V", "Fr", "drag", "n_contacts", "theta", "Z", "kappa") if c in local]
stat = [c for c in ("drag_err",) if c in local]
for d, name in zip(sys.argv[1:3], ("Snakemake 9 + slurm", "Snakemake 7.21 + slurm-v7")):
    t = table(d)
    assert len(t) == len(local) > 0, f"{name}: {len(t)} vs {len(local)} rows"
    pd.testing.assert_frame_equal(t[cols], local[cols], check_exact=True)
    pd.testing.assert_frame_equal(t[stat], local[stat], check_exact=False, rtol=1e-12, atol=0)
    print(f"table through {name}: {len(t)} pulls, identical to the local run in {', '.join(cols)}; "
          f"{', '.join(stat)} equal to 1e-12")
PY

# A pull longer than the time limit: killed (TIMEOUT), resumed by the next attempt. Its length
# is sized from a pull timed here, through the same bed (the smoke study's D = 2 bed, which the
# long sweep shares), so that neither a faster engine nor a slower machine changes the test:
# 120 s of this machine's pulling, against a 1-minute limit on the first attempt. SLURM enforces
# a limit up to half a minute late (first attempts here were killed 1.14 to 1.77 million steps
# in, 60 to 90 s of pulling; at 90 s the pull was 97 % done), so the first attempt never
# finishes it; it is killed past halfway (checkpoints every tenth), and later attempts finish
# the rest (under 7.21 --set-resources holds every attempt to 1 minute, so a third may be
# needed: 257 s for this step then, against 140-194 s with 90 s of pulling, which a late kill
# could let the first attempt finish). 3 retries leave room for a slower machine.
bed=$(find "$work/local/results" -path '*system~I/D~2/*' -name bed.h5 | head -1)
[ -f "$bed" ] || { echo "FAIL: no D = 2 bed of system I in the local smoke run"; exit 1; }
probe=20
t=$EPOCHREALTIME
OMP_NUM_THREADS=1 "$gd" pull --bed "$bed" --output "$work/probe.h5" --froude 0.5 --distance $probe --quiet >/dev/null
read -r secs distance < <(/usr/bin/python3 -c "import sys; s = float(sys.argv[2]) - float(sys.argv[1]); \
print(f'{s:.1f}', max(20, round(120 * $probe / s)))" "$t" "$EPOCHREALTIME")
echo "a $probe d pull took $secs s here: the time-limit pull is $distance d"
/usr/bin/python3 - "$work" "$distance" <<'PY'
import sys, yaml
work, distance = sys.argv[1], float(sys.argv[2])
config = yaml.safe_load(open(f"{work}/smoke.yaml"))
config["systems"]["I"]["pull"]["distance"] = distance
config["sweeps"] = [dict(name="long", system="I", D=2, depth=4, Fr=0.5)]
yaml.safe_dump(config, open(f"{work}/timelimit.yaml", "w"), sort_keys=False)
PY
limit=(--set-resources pull:runtime=1 --restart-times 3)
# Both generations at once (a pull of one thread each, on the cluster's 2 CPUs): their jobs are
# told apart by their working directory in accounting.
t=$SECONDS
run "$work/limit9" "$sm9" "$work/timelimit.yaml" --profile "$root/workflow/profiles/slurm" --jobs 2 "${fast[@]}" "${limit[@]}" pulls &
pid9=$!
run "$work/limit7" "$sm7" "$work/timelimit.yaml" --profile "$root/workflow/profiles/slurm-v7" --jobs 2 --cores 2 "${limit[@]}" pulls &
pid7=$!
wait $pid9 || exit 1
wait $pid7 || exit 1
sleep 2   # slurmctld sends the last job's end to slurmdbd asynchronously
for gen in 9 7; do
  # id|state|working directory of this generation's jobs
  timeouts=$(jobs_in "$work/limit$gen" | grep -c '|TIMEOUT|' || true)
  log=$(find "$work/limit$gen/logs" -path '*pulls*' -name '*.log' | head -1)
  run_file=$(find "$work/limit$gen/results" -name run.h5 | head -1)
  echo "Snakemake $gen, a pull over its 1-minute limit: $((SECONDS - t)) s for both, $timeouts job(s) killed at the limit; $(grep -m1 'resuming from' "$log" | sed 's/ from .* at/ at/')"
  [ "$timeouts" -ge 1 ] || { echo "FAIL: no job reached its time limit:"; sacct -n -X -P -S now-2hours -o JobID,JobName,State,WorkDir; exit 1; }
  grep -qE 'resuming from .* at step [1-9]' "$log" || { echo "FAIL: the last attempt did not resume:"; tail "$log"; exit 1; }
  [ -f "$run_file" ] || { echo "FAIL: the pull did not finish"; exit 1; }
done
echo "PASS: two of the smoke study's sweeps ran to their table and fits through SLURM with Snakemake 9 and 7.21 and matches the local run; a pull killed at its time limit resumed"
