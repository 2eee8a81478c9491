#!/usr/bin/env bash
# Inputs are never outputs, one writer per output, unreadable checkpoints moved aside, damaged
# inputs refused by name, and a write that fails half-way (file size limit: what a full disk
# does) leaves the previous output intact and says what failed. Prints a table of every bad
# input tried: input | exit code | message.
#   file_safety.sh path/to/granudrag
set -uo pipefail
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
expect() {  # expect "what it should say" command...
  local want=$1; shift
  local out code
  capture 300 "$@"
  table "$*" "$code" "$(grep -F 'error' <<<"$out" | head -1)"
  said "$want" || { fail "'$*' -> exit $code, expected 1 and a message containing '$want'; got:"; echo "$out"; }
}
small=(--lx 8 --ly 8 --depth 2 --grains 400 --kn 2e4 --max_settle_time 1 --quiet)
"$gd" pour --output b.h5 "${small[@]}" >/dev/null 2>&1 || fail "a good pour failed"
"$gd" pull --bed b.h5 --output r.h5 --distance 0.2 --quiet >/dev/null 2>&1 || fail "a good pull failed"
cp b.h5 b.orig

# 1. Inputs are never outputs.
expect "--output b.h5 is the same file as --bed b.h5: choose another output path" \
  "$gd" pull --bed b.h5 --output b.h5 --speed 1
ln b.h5 hard.h5
expect "--output hard.h5 is the same file as --bed b.h5" "$gd" pull --bed b.h5 --output hard.h5
ln -s b.h5 soft.h5
expect "--output b.h5 is the same file as --bed soft.h5" "$gd" pull --bed soft.h5 --output b.h5
mkdir sub
expect "--output sub/../b.h5 is the same file as --bed b.h5" "$gd" pull --bed b.h5 --output sub/../b.h5
expect "--output r.h5.checkpoint.h5 is the same file as --bed r.h5.checkpoint.h5" \
  "$gd" pull --bed r.h5.checkpoint.h5 --output r.h5.checkpoint.h5
printf 'lx: 8\n' > p.yaml
expect "--output p.yaml is the same file as --config p.yaml" "$gd" pour --config p.yaml --output p.yaml "${small[@]}"
expect "--output r.h5 exists and is a run file, not a bed file" "$gd" pour --output r.h5 "${small[@]}"
expect "--output b.h5 exists and is a bed file, not a run file" "$gd" pull --bed r.h5 --output b.h5
expect "--output b.h5 exists and is a bed file, not a text file" "$gd" restitution --output b.h5 --speeds 0.1
expect "--output p.yaml exists and is not an HDF5 file, not a bed file" "$gd" pour --output p.yaml "${small[@]}"
expect "the data file b.h5.data is the same file as --bed b.h5.data" \
  "$gd" export-lammps --bed b.h5.data --output b.h5
expect "--output sub is a directory" "$gd" pour --output sub "${small[@]}"
cmp -s b.h5 b.orig || fail "the bed changed"

# 2. One writer per output. A long pull holds r2.h5's lock; a second writer is refused; killed
# hard, it leaves a stale lock that the retry (--resume, as the workflow retries) takes over.
long=(--bed b.h5 --output r2.h5 --speed 0.5 --distance 3 --checkpoint_interval 0.05 --quiet)
"$gd" pull "${long[@]}" >/dev/null 2>&1 &
pid=$!
wait_for_file r2.h5.checkpoint.h5 "$pid"
if kill -0 "$pid" 2>/dev/null; then
  grep -q "^pid $pid host $(hostname)$" r2.h5.lock || fail "the lock does not name pid $pid: $(cat r2.h5.lock)"
  expect "output 'r2.h5' is being written by process $pid on this host" "$gd" pull "${long[@]}"
  kill -9 "$pid"; wait "$pid" 2>/dev/null
  [ -f r2.h5.lock ] || fail "no stale lock after kill -9 (the test would not test the take-over)"
  cp r2.h5.checkpoint.h5 ck.h5  # a real checkpoint, damaged below
  out=$("$gd" pull "${long[@]}" --resume 2>&1) || fail "the retry after kill -9 failed: $out"
  grep -q "taking over the stale lock 'r2.h5.lock' of process $pid" <<<"$out" || fail "no take-over: $out"
  grep -q "resuming from r2.h5.checkpoint.h5" <<<"$out" || fail "the retry did not resume: $out"
  { [ -f r2.h5 ] && [ ! -e r2.h5.lock ]; } || fail "after the retry: no run file, or the lock is left"
else
  fail "the pull ended before its first checkpoint"
fi
echo "pid 12 host some-other-node" > r3.h5.lock
expect "rm 'r3.h5.lock'" "$gd" pull --bed b.h5 --output r3.h5 --distance 0.2
rm r3.h5.lock
# SIGTERM (a cluster's time limit) removes the lock on the way out.
"$gd" pull "${long[@]/r2.h5/r4.h5}" >/dev/null 2>&1 &
pid=$!
wait_for_file r4.h5.checkpoint.h5 "$pid"
[ -e r4.h5.lock ] || fail "the pull writing r4.h5 holds no lock"
kill -TERM "$pid" 2>/dev/null || fail "the pull writing r4.h5 ended before its first checkpoint"
wait "$pid" 2>/dev/null
[ -e r4.h5.lock ] && fail "SIGTERM left the lock"

# 3. An unreadable checkpoint is moved aside and the pull starts over; a mismatched one is kept.
short=(--bed b.h5 --output r5.h5 --distance 0.2 --resume --quiet)
for damage in truncated bitflip9 bitflip40 bitflip100 text; do
  rm -f r5.h5 r5.h5.checkpoint.h5.corrupt
  case $damage in
    truncated) head -c 30000 ck.h5 > r5.h5.checkpoint.h5 ;;
    bitflip*) /usr/bin/python3 -c "
b = bytearray(open('ck.h5', 'rb').read()); b[${damage#bitflip}] ^= 0x04; open('r5.h5.checkpoint.h5', 'wb').write(b)" ;;
    text) echo "not a checkpoint" > r5.h5.checkpoint.h5 ;;
  esac
  out=$("$gd" pull "${short[@]}" 2>&1); code=$?
  table "pull --resume with a $damage checkpoint" "$code" "$(grep -F 'granudrag:' <<<"$out" | head -2)"
  { [ "$code" -eq 0 ] && grep -q "moved it aside to 'r5.h5.checkpoint.h5.corrupt' and starting over" <<<"$out" \
    && [ -f r5.h5.checkpoint.h5.corrupt ] && [ -f r5.h5 ]; } || fail "$damage checkpoint: exit $code: $out"
done
# A run file where the checkpoint goes is somebody's result: refused, not moved or replaced.
rm -f r5.h5
cp r.h5 r5.h5.checkpoint.h5
expect "the checkpoint r5.h5.checkpoint.h5 exists and is a run file, not a checkpoint" "$gd" pull "${short[@]}"
cmp -s r.h5 r5.h5.checkpoint.h5 || fail "the run file at the checkpoint's path changed"
# Written with other options: an error, and the checkpoint is kept.
cp ck.h5 r6.h5.checkpoint.h5
expect "now:        speed: 0.7" "$gd" pull --bed b.h5 --output r6.h5 --speed 0.7 --distance 3 \
  --checkpoint_interval 0.05 --resume --quiet
cmp -s ck.h5 r6.h5.checkpoint.h5 || fail "a mismatched checkpoint was not kept"

# 4. Damaged beds through the binary: exit 1 and a message naming the file, or a normal pull.
size=$(stat -c %s b.h5)
for k in 0 1 2 3 4 5 6 7 8 9; do
  head -c $((size * k / 10)) b.h5 > t$k.h5
  expect "t$k.h5" "$gd" pull --bed t$k.h5 --output rt$k.h5 --distance 0.2 --quiet
done
for at in 0 9 40 100 300 700 1500 3000 6000 12000 24000 48000; do
  /usr/bin/python3 -c "
b = bytearray(open('b.h5', 'rb').read()); b[$at % len(b)] ^= 0x04; open('f$at.h5', 'wb').write(b)"
  out=$(timeout 300 "$gd" pull --bed f$at.h5 --output rf$at.h5 --distance 0.2 --quiet 2>&1); code=$?
  table "pull --bed (bed with bit 2 of byte $at flipped)" "$code" "$(grep -F 'error' <<<"$out" | head -1)"
  { [ "$code" -eq 0 ] || { [ "$code" -eq 1 ] && grep -qF "f$at.h5" <<<"$out"; }; } \
    || fail "bit flip at $at: exit $code: $out"
done

# 5. A write that fails half-way (file size limit, as a full disk: SIGXFSZ ignored, so write()
# fails with EFBIG) leaves the previous output as it was and says what failed.
cp r.h5 r.before
cp b.h5 b.before
for cmd in pull pour; do
  if [ $cmd = pull ]; then args=(pull --bed b.before --output r.h5 --distance 0.2 --quiet); target=r.h5
  else args=(pour --output b.h5 "${small[@]}"); target=b.h5; fi
  out=$(bash -c 'trap "" XFSZ; ulimit -f 24; exec "$@"' _ "$gd" "${args[@]}" 2>&1); code=$?
  table "$cmd with a 24 kB file size limit" "$code" "$(grep -F 'error' <<<"$out" | head -1)"
  { [ "$code" -eq 1 ] && grep -q "$target" <<<"$out"; } || fail "$cmd under ulimit -f: exit $code: $out"
  cmp -s "$target" "${target%.h5}.before" || fail "$cmd under ulimit -f changed the previous $target"
  [ -e "$target.tmp" ] && fail "$cmd under ulimit -f left $target.tmp"
  [ -e "$target.lock" ] && fail "$cmd under ulimit -f left $target.lock"
done
"$gd" restitution --output x.csv --speeds 0.1 --kn 2e4 >/dev/null 2>&1 || fail "a good restitution failed"
cp x.csv x.before
speeds=$(seq -s, 0.01 0.01 0.8)  # 80 lines of CSV: more than the 1 kB allowed
out=$(bash -c 'trap "" XFSZ; ulimit -f 1; exec "$@"' _ "$gd" restitution --output x.csv --speeds "$speeds" \
  --kn 2e4 2>&1); code=$?
table "restitution of 80 speeds with a 1 kB file size limit" "$code" "$(grep -F 'error' <<<"$out" | head -1)"
{ [ "$code" -eq 1 ] && grep -q "x.csv" <<<"$out"; } || fail "restitution under ulimit -f: $code: $out"
cmp -s x.csv x.before || fail "restitution under ulimit -f changed the previous x.csv"
[ -e x.csv.tmp ] && fail "restitution under ulimit -f left x.csv.tmp"

[ "$fails" -eq 0 ] && echo "PASS: outputs protected, locks, checkpoints moved aside, damaged inputs refused"
exit "$fails"
