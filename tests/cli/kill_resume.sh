#!/usr/bin/env bash
# A pull killed with SIGKILL and resumed gives the same force series, drag and frames
# (--dump_interval), bit for bit, as an uninterrupted pull with the same thread count.
#   kill_resume.sh path/to/granudrag
set -euo pipefail
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
"$gd" pour --output bed.h5 --lx 10 --ly 10 --grains 1200 --intruder_diameter 2 --depth 4 \
  --kn 2e4 --ke_threshold 1e-4 --max_settle_time 40 --threads 2 --quiet >/dev/null
args=(--bed bed.h5 --speed 0.5 --distance 4 --checkpoint_interval 0.5 --dump_interval 0.25 --threads 2 --quiet)
"$gd" pull "${args[@]}" --output whole.h5 >/dev/null

"$gd" pull "${args[@]}" --output killed.h5 >/dev/null &
pid=$!
# Kill hard as soon as the first of its 8 checkpoints exists (written to a temporary file, then
# renamed: complete when it appears). Event-driven, however slowly the machine runs; 600 s only
# bounds a pull that never checkpoints.
wait_for_file killed.h5.checkpoint.h5 "$pid"
kill -9 "$pid" 2>/dev/null || { echo "FAIL: the pull finished before it could be killed"; exit 1; }
wait "$pid" 2>/dev/null || true
[ -f killed.h5 ] && { echo "FAIL: a killed pull left a run file"; exit 1; }
[ -f killed.h5.checkpoint.h5 ] || { echo "FAIL: no checkpoint survived the kill"; exit 1; }
ls killed.h5.checkpoint.h5.tmp >/dev/null 2>&1 && echo "note: a half-written checkpoint.tmp was left and is ignored"
[ -f killed.h5.frames.00000000.h5 ] || { echo "FAIL: the frames the checkpoint counts are not in a sealed segment"; ls; exit 1; }
"$gd" pull "${args[@]}" --output killed.h5 --resume 2>resume.log >/dev/null
grep -q "resuming from" resume.log || { echo "FAIL: --resume did not resume"; cat resume.log; exit 1; }
for d in /observables/intruder_force/value /observables/cumulative_drag/value \
  /particles/frames/position/value /particles/frames/velocity/value /particles/frames/position/step; do
  same_dataset "$d" whole.h5 killed.h5 || { echo "FAIL: $d differs after kill and resume"; exit 1; }
done
a=$(drag_of whole.h5)
b=$(drag_of killed.h5)
[ "$a" = "$b" ] || { echo "FAIL: drag $a vs $b"; exit 1; }
ls killed.h5.frames.* >/dev/null 2>&1 && { echo "FAIL: frame segments left behind"; ls; exit 1; }
cmp -s whole.h5.xdmf <(sed 's/killed\.h5/whole.h5/g' killed.h5.xdmf) || { echo "FAIL: the frames' sidecars differ"; exit 1; }
frames=$(grep -c "<Time Value" killed.h5.xdmf)
[ "$frames" = 33 ] || { echo "FAIL: $frames frames in the sidecar, expected 33 (8 time units every 0.25, and step 0)"; exit 1; }
echo "PASS: killed and resumed pull is bitwise identical (drag $a, $frames frames)"
