#!/usr/bin/env bash
# Soak: a pull killed with SIGKILL at 20 or more random moments (while stepping, while writing
# a checkpoint or frames, while starting up) and resumed each time ends with the same force
# series, drag and frames, bit for bit, as the uninterrupted pull. The moments come from a fixed
# seed, so a failure can be replayed; the kills are counted only when the pull was still running.
# Extra arguments go to every pull (e.g. the active region's, whose state is checkpointed too).
#   soak.sh path/to/granudrag [kills [pull options ...]]
set -euo pipefail
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
want=${2:-20}
shift $(($# < 2 ? $# : 2))
"$gd" pour --output bed.h5 --lx 8 --ly 8 --grains 500 --intruder_diameter 2 --depth 3 \
  --kn 2e4 --ke_threshold 1e-3 --max_settle_time 10 --threads 1 --quiet >/dev/null
# Checkpoints and frames often, so that kills fall between, during and after writes.
args=(--bed bed.h5 --speed 0.5 --distance 16 --checkpoint_interval 0.1 --dump_interval 0.2 --threads 1 --quiet "$@")
"$gd" pull "${args[@]}" --output whole.h5 >/dev/null

RANDOM=2026
kills=0 attempts=0
while [ "$kills" -lt "$want" ] && [ "$attempts" -lt 400 ]; do
  attempts=$((attempts + 1))
  "$gd" pull "${args[@]}" --output soaked.h5 --resume >/dev/null 2>>resume.log &
  pid=$!
  # 0.02 to 0.6 s: from start-up (reading the bed and checkpoint) to well into the stepping.
  sleep "0.$(printf '%02d' $((2 + RANDOM % 59)))"
  if kill -9 "$pid" 2>/dev/null; then
    kills=$((kills + 1))
  fi
  wait "$pid" 2>/dev/null || true
  [ -f soaked.h5 ] && break  # it finished before this kill
done
[ "$kills" -ge "$want" ] || { echo "FAIL: only $kills kills landed in $attempts attempts (the pull ran out first)"; exit 1; }
[ -f soaked.h5 ] || "$gd" pull "${args[@]}" --output soaked.h5 --resume >/dev/null 2>>resume.log
resumed=$(grep -c "resuming from" resume.log || true)
for d in /observables/intruder_force/value /observables/cumulative_drag/value \
  /particles/frames/position/value /particles/frames/velocity/value /particles/frames/position/step; do
  same_dataset "$d" whole.h5 soaked.h5 ||
    { echo "FAIL: $d differs after $kills kills"; exit 1; }
done
a=$(drag_of whole.h5)
b=$(drag_of soaked.h5)
[ "$a" = "$b" ] || { echo "FAIL: drag $a vs $b after $kills kills"; exit 1; }
ls soaked.h5.frames.* >/dev/null 2>&1 && { echo "FAIL: frame segments left behind"; exit 1; }
if h5dump -d /observables/sleeping_grains/value whole.h5 >/dev/null 2>&1; then
  diff <(h5dump -d /observables/sleeping_grains/value whole.h5 | tail -n +3) \
    <(h5dump -d /observables/sleeping_grains/value soaked.h5 | tail -n +3) >/dev/null ||
    { echo "FAIL: the sleeping grains differ after $kills kills"; exit 1; }
  asleep=$(h5dump -d /observables/sleeping_grains/value whole.h5 | grep -oE "[0-9]+" | sort -n | tail -1)
  [ "$asleep" -gt 0 ] || { echo "FAIL: no grain ever slept: the active region was not exercised"; exit 1; }
fi
echo "PASS: $kills kills at random moments ($resumed resumes from a checkpoint), then finished: bitwise the uninterrupted pull (drag $a)"
