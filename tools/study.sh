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
# One study at a time per working directory: a run (not a dry run) holds a lock of its own,
# .snakemake/granudrag-study.lock there, for as long as it lives (flock; the file names the
# holder); a second run is refused, naming the first. A run killed outright (SIGKILL, a
# rebooted node) leaves Snakemake's lock: the next run clears it (snakemake --unlock, said on
# stderr) when no run holds that lock and no Snakemake or granudrag process works there.
set -euo pipefail
cd "$(dirname "$0")/.."
snakemake=${SNAKEMAKE:-.venv/bin/snakemake}
me="tools/study.sh"

# Snakemake's working directory (--directory), and whether this is a dry run.
dir=. dry=0 prev=
for arg in "$@"; do
  case "$prev" in --directory | -d) dir=$arg ;; esac
  case "$arg" in
    --directory=*) dir=${arg#--directory=} ;;
    --dry-run | --dryrun) dry=1 ;;
    -[a-zA-Z]*) if [[ $arg =~ ^-[a-zA-Z]*n[a-zA-Z]*$ ]]; then dry=1; fi ;;   # -n, -np, ...
  esac
  prev=$arg
done

# Live processes of a study working in $dir (Snakemake, a job of its), one per line.
workers() {
  local here p name cmd
  here=$(cd "$dir" && pwd -P)
  for p in /proc/[0-9]*; do
    [ "${p#/proc/}" != $$ ] || continue
    [ "$(readlink "$p/cwd" 2>/dev/null)" = "$here" ] || continue
    name=$(cat "$p/comm" 2>/dev/null) || continue
    cmd=$(tr '\0' ' ' <"$p/cmdline" 2>/dev/null) || continue
    case "$name" in
      snakemake | granudrag | resumable.sh) ;;
      python*) [[ " $cmd" == *" -m snakemake "* || $cmd == *"/snakemake "* ]] || continue ;;
      *) continue ;;
    esac
    echo "pid ${p#/proc/}: $cmd"
  done
}

if [ "$dry" = 0 ]; then
  mkdir -p "$dir/.snakemake"
  lock="$dir/.snakemake/granudrag-study.lock"
  exec 9>>"$lock"
  if ! flock -n 9; then
    sleep 0.2   # the holder may be writing its line
    echo "$me: refused: another study runs in ${dir} (it holds $lock): $(cat "$lock")." \
      "Wait for it to end, or stop it (kill its pid) and run again." >&2
    exit 1
  fi
  # Kept by the exec below: the lock lives as long as Snakemake.
  printf 'pid %s on %s, started %s: %s\n' "$$" "$(hostname)" "$(date -Is)" "$me${*:+ $*}" >"$lock"
fi

tools/install-deps.sh study
# Always an up-to-date engine (an incremental build is seconds); the workflow's own build rule
# only builds a missing binary, and does not make finished results out of date.
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)" --target granudrag >/dev/null

if [ "$dry" = 0 ] && [ -n "$(ls -A "$dir/.snakemake/locks" 2>/dev/null)" ]; then
  live=$(workers)
  if [ -n "$live" ]; then
    echo "$me: refused: Snakemake's lock in ${dir}/.snakemake/locks belongs to a run still at" \
      "work there, not started by $me:" >&2
    echo "$live" >&2
    exit 1
  fi
  echo "$me: Snakemake's lock in ${dir}/.snakemake/locks was left by a run that is no longer" \
    "alive (killed outright?): no study holds $lock and no Snakemake or granudrag process" \
    "works there; unlocking it (snakemake --unlock)." >&2
  "$snakemake" "$@" --unlock >&2
fi
# The project environment's Snakemake (or $SNAKEMAKE), not whichever comes first on PATH.
exec "$snakemake" --cores all --rerun-incomplete --keep-going "$@"
