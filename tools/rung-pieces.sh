#!/usr/bin/env bash
# A rung of the reproduction ladder too long for one sitting, run in pieces (a bed and some of
# its pulls at a time) that survive the machine they ran on:
#   tools/rung-pieces.sh save CONFIG      # after a piece: its finished beds, pulls and job
#                                         # benchmarks into results/reproduction/<rung>/pieces/
#   tools/rung-pieces.sh restore CONFIG   # on a fresh checkout: put them back into the rung's
#                                         # results directory, so the study runs only what is missing
#   tools/rung-pieces.sh status CONFIG    # what the plan asks for, and what is finished
# The engine is deterministic (a bed and a pull are the same bits on any x86-64 machine of the
# portable build and one thread per job), so a lost machine costs only the piece in flight.
# Saved files keep their modification times; restored ones take the time of the restore, beds
# before pulls, so a pull is newer than its bed whether the bed was restored with it or poured
# again on the fresh checkout first, and Snakemake takes it as finished. Beds (12 MB each) are
# committed with the pulls since a fresh machine once spent a sitting pouring two again. Nothing already in place is overwritten, and an unfinished job's checkpoint or
# temporary file is never copied (only bed.h5, run.h5 and benchmark .tsv files).
set -euo pipefail
cd "$(dirname "$0")/.."
usage() { echo "usage: tools/rung-pieces.sh save|restore|status config/ladder/RUNG.yaml" >&2; exit 2; }
action=${1:-}
config=${2:-}
if [ -z "$action" ] || [ -z "$config" ]; then usage; fi
[ -f "$config" ] || { echo "tools/rung-pieces.sh: no config '$config' (the rungs: config/ladder/*.yaml)" >&2; exit 2; }
rung=$(basename "$config" .yaml)
results=$(/usr/bin/python3 -c 'import sys, yaml; print(yaml.safe_load(open(sys.argv[1])).get("results", "results"))' "$config")
pieces=${RUNG_PIECES_DIR:-results/reproduction/$rung/pieces}   # (the override: tests)

# The finished outputs under a directory, relative to it: beds, pulls and their benchmarks.
finished() {
  [ -d "$1" ] || return 0
  (cd "$1" && find beds pulls benchmarks \( -name bed.h5 -o -name run.h5 -o -name '*.tsv' \) -type f 2>/dev/null | sort)
}

# Copies each finished file from $1 to $2 that $2 lacks, in `finished`'s order (beds, then
# benchmarks, then pulls); $3 is --preserve=timestamps to keep the files' times, or
# --no-preserve=timestamps to give them the time of the copy. Prints how many.
copy_missing() {
  local from=$1 to=$2 keep=$3 n=0 f
  while IFS= read -r f; do
    [ -n "$f" ] || continue
    [ -e "$to/$f" ] && continue
    mkdir -p "$to/$(dirname "$f")"
    cp "$keep" "$from/$f" "$to/$f.tmp.$$"
    mv "$to/$f.tmp.$$" "$to/$f"
    n=$((n + 1))
  done < <(finished "$from")
  echo "$n"
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
  *) usage ;;
esac
