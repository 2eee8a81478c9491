#!/usr/bin/env bash
# A pour killed with SIGKILL and resumed gives the same bed and frames (--dump_interval), bit for
# bit, as an uninterrupted pour with the same checkpoint interval and thread count.
#   pour_kill_resume.sh path/to/granudrag
set -euo pipefail
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
args=(--lx 10 --ly 10 --grains 1200 --intruder_diameter 2 --depth 4 --kn 2e4 --ke_threshold 1e-9
  --max_settle_time 20 --checkpoint_interval 2 --dump_interval 1 --threads 2 --quiet)
"$gd" pour "${args[@]}" --output whole.h5 >/dev/null
[ -f whole.h5.checkpoint.h5 ] && { echo "FAIL: a finished pour left its checkpoint"; exit 1; }

"$gd" pour "${args[@]}" --output killed.h5 >/dev/null &
pid=$!
# Kill hard as soon as the first of its 9 checkpoints exists (written to a temporary file, then
# renamed: complete when it appears). Event-driven, however slowly the machine runs; 600 s only
# bounds a pour that never checkpoints.
wait_for_file killed.h5.checkpoint.h5 "$pid"
kill -9 "$pid" 2>/dev/null || { echo "FAIL: the pour finished before it could be killed"; exit 1; }
wait "$pid" 2>/dev/null || true
[ -f killed.h5 ] && { echo "FAIL: a killed pour left a bed file"; exit 1; }
[ -f killed.h5.checkpoint.h5 ] || { echo "FAIL: no checkpoint survived the kill"; exit 1; }
# Another option than the checkpoint's is refused, naming it.
if "$gd" pour "${args[@]}" --seed 2 --output killed.h5 --resume >other.log 2>&1; then
  echo "FAIL: a checkpoint of another pour was used"; exit 1
fi
grep -q "now:        seed: 2" other.log || { echo "FAIL: the refusal does not name the seed"; cat other.log; exit 1; }
"$gd" pour "${args[@]}" --output killed.h5 --resume 2>resume.log >/dev/null
grep -q "resuming from" resume.log || { echo "FAIL: --resume did not resume"; cat resume.log; exit 1; }
[ -f killed.h5.checkpoint.h5 ] && { echo "FAIL: the finished pour left its checkpoint"; exit 1; }
for d in /particles/all/position/value /particles/all/velocity/value /particles/all/angular_velocity/value \
  /contacts/shear /bed/profile/packing_fraction /particles/frames/position/value /particles/frames/velocity/value \
  /particles/frames/position/time; do
  same_dataset "$d" whole.h5 killed.h5 || { echo "FAIL: $d differs after kill and resume"; exit 1; }
done
# A damaged checkpoint (truncated mid-file, as by a node dying during a copy) is moved aside and
# the pour starts over, so a scheduler's retry always makes progress; the bed is still the same.
printf 'not a checkpoint, truncated' >broken.h5.checkpoint.h5
"$gd" pour "${args[@]}" --output broken.h5 --resume 2>broken.log >/dev/null \
  || { echo "FAIL: a damaged checkpoint stopped the pour"; cat broken.log; exit 1; }
{ grep -q "moved it aside to 'broken.h5.checkpoint.h5.corrupt'" broken.log && [ -f broken.h5.checkpoint.h5.corrupt ]; } \
  || { echo "FAIL: the damaged checkpoint was not moved aside"; cat broken.log; exit 1; }
same_dataset /particles/all/position/value whole.h5 broken.h5 \
  || { echo "FAIL: the pour started over after a damaged checkpoint differs"; exit 1; }
ls killed.h5.frames.*.h5 >/dev/null 2>&1 && { echo "FAIL: frame segments left behind"; ls; exit 1; }
frames=$(grep -c "<Time Value" killed.h5.frames.xdmf)
[ "$frames" -ge 10 ] || { echo "FAIL: only $frames frames in the sidecar"; exit 1; }
echo "PASS: killed and resumed pour is bitwise identical ($frames frames too); a damaged checkpoint is moved aside"
