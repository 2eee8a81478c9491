#!/usr/bin/env bash
# One attempt of a checkpointed simulation job (rules bed and pull):
#   resumable.sh OUTPUT LOG ATTEMPT ARGS NEWER_THAN -- granudrag pour|pull ... --resume ...
# - the checkpoint OUTPUT.checkpoint.h5 is resumed unless its arguments (ARGS, kept in
#   OUTPUT.checkpoint.h5.args) changed or it is not newer than NEWER_THAN (the bed a pull
#   reads; empty for a pour);
# - a job can reach its time limit after the simulation has finished, in Snakemake's own
#   bookkeeping: Snakemake then deletes OUTPUT as a failed job's, and the checkpoint went with
#   the finished run, so the next attempt would start from step 0. A finished run is kept as a
#   hard link OUTPUT.done (no extra disk), which a retry (ATTEMPT > 1) with the same ARGS puts
#   back; attempt 1 (a new run, --forcerun, a deleted output) removes it;
# - Snakemake deletes LOG before every attempt: every attempt's output is appended to
#   LOG.attempts, which is copied to LOG at the end;
# - an attempt that fails leaves OUTPUT.failed (not a Snakemake output): its exit status, attempt,
#   host, time and reason (the engine's last error line), written atomically; an attempt that
#   finishes removes it. A pull the engine stopped itself (exit status 1: a run-guard stop, an
#   unreadable input), when the workflow sets GRANUDRAG_ALLOW_FAILED=1 (table.allow_failed),
#   leaves a placeholder at OUTPUT instead of failing the job, so that the study's table and
#   report are made without the pull and list it; the end of the run removes the placeholder,
#   and the next run retries the pull (workflow/granudrag_study/failures.py).
set -euo pipefail
out=$1 log=$2 attempt=$3 args=$4 newer=$5
shift 5
[ "${1:-}" = "--" ] && shift
ckpt="$out.checkpoint.h5" done="$out.done" history="$log.attempts"
[ "$attempt" -gt 1 ] || rm -f "$done" "$done.args" "$history"
echo "attempt $attempt (job ${SLURM_JOB_ID:-local} on $(hostname)) at $(date -Is)" >>"$history"
status=0
if [ -e "$done" ] && [ "$(cat "$done.args" 2>/dev/null)" = "$args" ]; then
  echo "finished by an earlier attempt, whose job was killed afterwards: kept $out" >>"$history"
  ln -f "$done" "$out" 2>/dev/null || cp -p "$done" "$out"
else
  rm -f "$done" "$done.args"
  if [ -e "$ckpt" ] && { { [ -n "$newer" ] && ! [ "$ckpt" -nt "$newer" ]; } ||
    [ "$(cat "$ckpt.args" 2>/dev/null)" != "$args" ]; }; then
    echo "checkpoint older than $newer or of other arguments: removed" >>"$history"
    rm -f "$ckpt"
  fi
  echo "$args" >"$ckpt.args"
  rm -f "$out.lock"   # a dead job's (Snakemake runs one job per output)
  before=$(wc -l <"$history")
  "$@" >>"$history" 2>&1 || status=$?
  if [ "$status" -eq 0 ]; then
    ln -f "$out" "$done" 2>/dev/null || cp -p "$out" "$done"
    mv -f "$ckpt.args" "$done.args"
  else
    # The reason: this attempt's last error line, else its last line.
    said=$(tail -n +"$((before + 1))" "$history" | tr '\r' '\n' | grep -v '^[[:space:]]*$' || true)
    reason=$(grep -E 'error|Error|ERROR' <<<"$said" | tail -n 1 || true)
    [ -n "$reason" ] || reason=$(tail -n 1 <<<"$said")
    printf 'status: %s\nattempt: %s\nhost: %s\nat: %s\nreason: %s\n' "$status" "$attempt" \
      "$(hostname)" "$(date -Is)" "${reason:-(no output)}" >"$out.failed.tmp"
    mv -f "$out.failed.tmp" "$out.failed"
    echo "failed (exit status $status): $out.failed" >>"$history"
  fi
fi
[ "$status" -ne 0 ] || rm -f "$out.failed"
if [ "$status" -eq 1 ] && [ "${2:-}" = pull ] && [ "${GRANUDRAG_ALLOW_FAILED:-0}" = 1 ]; then
  # Atomic too; its first line is what workflow/granudrag_study/failures.py looks for.
  printf '%s\n' "granudrag: failed pull placeholder" \
    "not a run file: this pull failed, its reason is in $(basename "$out").failed; the study's table" \
    "left it out (table.allow_failed) and the study's next run retries it" >"$out.placeholder.tmp"
  mv -f "$out.placeholder.tmp" "$out"
  echo "table.allow_failed: the study goes on without this pull (placeholder at $out)" >>"$history"
  status=0
fi
cp "$history" "$log"
exit "$status"
