#!/usr/bin/env bash
# A rung of the reproduction ladder too long for one sitting, run in pieces (a bed and some of
# its pulls at a time) that survive the machine they ran on:
#   tools/rung-pieces.sh save CONFIG      # after a piece: its finished beds, pulls and job
#                                         # benchmarks into results/reproduction/<rung>/pieces/
#   tools/rung-pieces.sh restore CONFIG   # on a fresh checkout: put them back into the rung's
#                                         # results directory, so the study runs only what is missing
#   tools/rung-pieces.sh status CONFIG    # what the plan asks for, and what is finished
#   tools/rung-pieces.sh run [--commit] CONFIG BED [LEAF...]
#                                         # one piece: the bed (BED, its key: system~II/D~4/
#                                         # h~49.7/mu~0/kn~2e4/gn~199.05359/seed~2), then each pull
#                                         # LEAF (V~1, Fr~5; default: every pull the plan has on
#                                         # that bed), one job at a time on one thread, each saved
#                                         # as it finishes; --commit also commits each saved job
#                                         # (git: the job's own output and benchmark, with its CPU
#                                         # seconds), serialised with other landers by a lock in
#                                         # the git directory; one runner per bed.
#                                         # A placed rung's bed comes after its column (landed
#                                         # once per seed, then shared by the seed's beds).
#                                         # GRANUDRAG=BIN pulls with a private copy of the engine
#                                         # (a rebuild of build/ mid-piece then changes nothing).
# The engine is deterministic (a bed and a pull are the same bits on any x86-64 machine of the
# portable build and one thread per job), so a lost machine costs only the piece in flight.
# Saved files keep their modification times; restored ones take the time of the restore, beds
# before pulls, so a pull is newer than its bed whether the bed was restored with it or poured
# again on the fresh checkout first, and Snakemake takes it as finished. Beds (12 MB each) are
# committed with the pulls since a fresh machine once spent a sitting pouring two again. Nothing already in place is overwritten, and an unfinished job's checkpoint or
# temporary file is never copied (only bed.h5, run.h5 and benchmark .tsv files).
set -euo pipefail
cd "$(dirname "$0")/.."
usage() {
  echo "usage: tools/rung-pieces.sh save|restore|status config/ladder/RUNG.yaml" >&2
  echo "       tools/rung-pieces.sh run [--commit] config/ladder/RUNG.yaml BED [LEAF...]" >&2
  exit 2
}
action=${1:-}
shift || true
commit=0
if [ "$action" = run ] && [ "${1:-}" = --commit ]; then commit=1; shift; fi
config=${1:-}
shift || true
if [ -z "$action" ] || [ -z "$config" ]; then usage; fi
[ -f "$config" ] || { echo "tools/rung-pieces.sh: no config '$config' (the rungs: config/ladder/*.yaml)" >&2; exit 2; }
rung=$(basename "$config" .yaml)
results=$(/usr/bin/python3 -c 'import sys, yaml; print(yaml.safe_load(open(sys.argv[1])).get("results", "results"))' "$config")
pieces=${RUNG_PIECES_DIR:-results/reproduction/$rung/pieces}   # (the override: tests)

# The finished outputs under a directory, relative to it: a placed rung's columns first (its beds
# are placed into them, so a restored bed must be newer than its column), then beds, benchmarks
# and pulls.
finished() {
  [ -d "$1" ] || return 0
  (cd "$1" && { if [ -d columns ]; then find columns -name column.h5 -type f | sort; fi
    find beds pulls benchmarks \( -name bed.h5 -o -name run.h5 -o -name '*.tsv' \) -type f 2>/dev/null | sort; })
}

# Copies each finished file from $1 to $2 that $2 lacks, in `finished`'s order (beds, then
# benchmarks, then pulls); $3 is --preserve=timestamps to keep the files' times, or
# --no-preserve=timestamps to give them the time of the copy. Prints how many.
copy_missing() {
  local from=$1 to=$2 keep=$3 n=0 f
  while IFS= read -r f; do
    [ -n "$f" ] || continue
    [ -e "$to/$f" ] && continue
    mkdir -p "$to/$(dirname "$f")" || return 1
    { cp "$keep" "$from/$f" "$to/$f.$$.tmp" && mv "$to/$f.$$.tmp" "$to/$f"; } || return 1
    n=$((n + 1))
  done < <(finished "$from")
  echo "$n"
}

snakemake=${SNAKEMAKE:-.venv/bin/snakemake}

# CPU seconds of a finished job, from its Snakemake benchmark (the cpu_time column; tab-separated,
# since a job of a day or more writes its h:m:s as "1 day, 2:03:04").
cpu_of() { awk -F'\t' 'NR == 2 {print $10}' "$1" 2>/dev/null; }

# Runs one job (its output path, $1) on one thread, saves it into the pieces and, with --commit,
# commits the job's own output and benchmark ($3) there, under the landers' lock; $2: the commit's
# subject. The engine's path (GRANUDRAG) is an input of every job, so Snakemake is told to take a
# finished job as finished by its files' times alone (--rerun-triggers mtime): a private copy of
# the engine does not re-run what the usual one made. Any failure returns 1, said on stderr.
land() {
  local target=$1 subject=$2 bench=$3 rel_target rel_bench
  if [ ! -f "$target" ]; then
    OMP_NUM_THREADS=1 "$snakemake" --nolock --cores 1 --rerun-triggers mtime --configfile "$config" \
      ${GRANUDRAG:+--config "granudrag=$GRANUDRAG"} -- "$target" ||
      { echo "tools/rung-pieces.sh: the job for $target failed (its log is under the config's logs:)" >&2; return 1; }
  fi
  rel_target=${target#"$results"/} rel_bench=${bench#"$results"/}
  if ! (
    flock 9 || exit 1
    copy_missing "$results" "$pieces" --preserve=timestamps > /dev/null || exit 1
    [ "$commit" = 1 ] || exit 0
    [ -n "$(git -C "$pieces" status --porcelain -- "$rel_target" "$rel_bench")" ] || exit 0
    git -C "$pieces" add -- "$rel_target" "$rel_bench" || exit 1
    git -C "$pieces" commit -q -m "$rung: $subject landed" \
      -m "CPU $(cpu_of "$bench") s (job benchmark, 1 thread, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs))." \
      -- "$rel_target" "$rel_bench" || exit 1
  ) 9> "$lockdir/rung-pieces.lock"; then
    echo "tools/rung-pieces.sh: $target finished but was not saved$([ "$commit" = 1 ] && echo " or committed") (above)" >&2
    return 1
  fi
  echo "tools/rung-pieces.sh: $subject landed ($(cpu_of "$bench") CPU s)" >&2
}

# A piece: the bed $1, then each of its pulls ($2...; default: the plan's on that bed), each
# checked against the plan before anything runs; one runner per bed (a lock per bed in the git
# directory of the pieces: a second runner on the same bed is refused, not raced).
run_piece() {
  local bed=$1 leaf leaves plan=$results/plan/pulls.txt short column column_short names collock
  shift
  leaves=("$@")
  # The bed's name in a subject line (its key without the system, K_n and gamma_n: a rung's own)
  # and, when its system is placed (`placement:`), the key of the column it is placed into; read
  # by the path scheme's one declaration (analysis/core/path_scheme.py).
  names=$(PYTHONPATH=. /usr/bin/python3 -c 'import sys, yaml
from analysis.core import path_scheme as s
fields = s.parse(s.BED, sys.argv[1])
if fields is None:
    sys.exit(1)
def short(components):  # a key without the parts a rung holds fixed, as words
    return s.key([c for c in components if c not in (s.SYSTEM, s.STIFFNESS, s.DAMPING)], fields).replace("/", " ")
print(short(s.BED))
system = (yaml.safe_load(open(sys.argv[2])).get("systems") or {}).get(fields["system"]) or {}
if "placement" in system:
    print(s.key(s.COLUMN, fields))
    print(short(s.COLUMN))' \
    "$bed" "$config") ||
    { echo "tools/rung-pieces.sh: '$bed' is not a bed's key (a line of $plan without its last part)" >&2; exit 2; }
  short=$(sed -n 1p <<< "$names") column=$(sed -n 2p <<< "$names") column_short=$(sed -n 3p <<< "$names")
  "$snakemake" --nolock --configfile "$config" --dry-run --quiet > /dev/null 2>&1 ||
    { echo "tools/rung-pieces.sh: Snakemake cannot plan $config (run: $snakemake --dry-run --configfile $config)" >&2; exit 2; }
  [ -f "$plan" ] || { echo "tools/rung-pieces.sh: the dry run wrote no plan ($plan)" >&2; exit 2; }
  if [ ${#leaves[@]} -eq 0 ]; then
    mapfile -t leaves < <(sed -n "s#^$bed/##p" "$plan")
    [ ${#leaves[@]} -gt 0 ] || { echo "tools/rung-pieces.sh: the plan ($plan) has no pull on '$bed'" >&2; exit 2; }
  fi
  for leaf in "${leaves[@]}"; do
    grep -qxF "$bed/$leaf" "$plan" ||
      { echo "tools/rung-pieces.sh: '$bed/$leaf' is not in the plan ($plan): a pull the config does not ask for" >&2; exit 2; }
  done
  mkdir -p "$pieces"
  lockdir=$(git -C "$pieces" rev-parse --absolute-git-dir 2>/dev/null) ||
    { [ "$commit" = 0 ] || { echo "tools/rung-pieces.sh: --commit, but $pieces is not in a git repository" >&2; exit 2; }
      lockdir=$pieces; }
  exec {bedlock}> "$lockdir/rung-pieces.$(printf %s "$rung/$bed" | md5sum | cut -c1-16).lock"
  flock -n "$bedlock" || { echo "tools/rung-pieces.sh: another runner is working on '$bed'" >&2; exit 2; }
  if [ -n "$column" ]; then
    # The seed's beds share the column: a runner on another of them waits here, then finds it.
    exec {collock}> "$lockdir/rung-pieces.$(printf %s "$rung/$column" | md5sum | cut -c1-16).lock"
    flock "$collock"
    land "$results/columns/$column/column.h5" "$column_short column" "$results/benchmarks/columns/$column.tsv" ||
      exit 1
    flock -u "$collock"
  fi
  land "$results/beds/$bed/bed.h5" "$short bed" "$results/benchmarks/beds/$bed.tsv" || exit 1
  for leaf in "${leaves[@]}"; do
    land "$results/pulls/$bed/$leaf/run.h5" "$short, $leaf" "$results/benchmarks/pulls/$bed/$leaf.tsv" || exit 1
  done
}

case "$action" in
  save)
    [ -d "$results" ] || { echo "tools/rung-pieces.sh: no results directory '$results' (run the rung first)" >&2; exit 2; }
    n=$(copy_missing "$results" "$pieces" --preserve=timestamps)
    echo "tools/rung-pieces.sh: $n new file(s) saved in $pieces ($(du -sh "$pieces" | cut -f1) in all); commit them with: git add $pieces"
    ;;
  restore)
    [ -d "$pieces" ] || { echo "tools/rung-pieces.sh: no saved pieces in '$pieces'" >&2; exit 2; }
    n=$(copy_missing "$pieces" "$results" --no-preserve=timestamps)
    echo "tools/rung-pieces.sh: $n file(s) restored into $results; now: tools/study.sh --configfile $config"
    ;;
  status)
    tools/study.sh --configfile "$config" --dry-run --quiet >/dev/null 2>&1 || true
    planned=$(wc -l < "$results/plan/pulls.txt" 2>/dev/null || echo "?")
    pulls=$(finished "$pieces" | grep -c '/run.h5$' || true)
    beds=$(finished "$pieces" | grep -c '/bed.h5$' || true)
    echo "$rung: $pulls of $planned pulls and $beds bed(s) saved in $pieces"
    ;;
  run)
    bed=${1:-}
    [ -n "$bed" ] || usage
    shift
    run_piece "$bed" "$@"
    ;;
  *) usage ;;
esac
