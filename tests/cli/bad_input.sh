#!/usr/bin/env bash
# Bad input gets a clear error naming the problem (and exit code 1), never a crash or a hang.
#   bad_input.sh path/to/granudrag
set -uo pipefail
# shellcheck source=tests/cli/lib.sh
. "$(dirname "$0")/lib.sh"
expect() {  # expect "what it should say" command...
  local want=$1; shift
  local out code
  capture 60 "$@"
  if said "$want"; then
    echo "ok: $want"
  else
    fail "'$*' -> exit $code, expected 1 and a message containing '$want'; got:"; echo "$out"
  fi
}
small=(--ly 8 --grains 400 --kn 2e4 --max_settle_time 1 --quiet)
expect "unknown option '--frition'" "$gd" pour --output b.h5 "${small[@]}" --lx 8 --depth 2 --frition 0.5
expect "did you mean '--grains'" "$gd" pour --output b.h5 --lx 8 --depth 2 --ly 8 --grain 400
expect "'mu'" "$gd" pour --output b.h5 "${small[@]}" --lx 8 --depth 2 --mu -0.1
expect "'lx'" "$gd" pour --output b.h5 "${small[@]}" --lx 0 --depth 2
expect "'intruder_x'" "$gd" pour --output b.h5 "${small[@]}" --lx 8 --depth 2 --intruder_x 9
expect "deeper than the bed" "$gd" pour --output b.h5 "${small[@]}" --lx 8 --depth 40
expect "dt <=" "$gd" pour --output b.h5 "${small[@]}" --lx 8 --depth 2 --dt 0.1
expect "'output'" "$gd" pour "${small[@]}" --lx 8 --depth 2
expect "does not exist" "$gd" pour --output nodir/b.h5 "${small[@]}" --lx 8 --depth 2
printf 'lx: 8\nfriction: 0.3\n' > bad.yaml
expect "bad.yaml" "$gd" pour --output b.h5 --config bad.yaml
expect "missing.h5" "$gd" pull --bed missing.h5 --output r.h5
echo "not hdf5" > text.h5
expect "text.h5" "$gd" pull --bed text.h5 --output r.h5
"$gd" pour --output good.h5 "${small[@]}" --lx 8 --depth 2 >/dev/null 2>&1 || fail "a good pour failed"
head -c 20000 good.h5 > truncated.h5
expect "truncated.h5" "$gd" pull --bed truncated.h5 --output r.h5
expect "'speed'" "$gd" pull --bed good.h5 --output r.h5 --speed -1
cp good.h5 future.h5
/usr/bin/python3 -c "import h5py; h5py.File('future.h5', 'r+')['/granudrag'].attrs['version'] = 99"
expect "format version 99" "$gd" pull --bed future.h5 --output r.h5
"$gd" pull --bed good.h5 --output run.h5 --distance 0.5 --quiet >/dev/null 2>&1
expect "not a granudrag-bed file" "$gd" pull --bed run.h5 --output r2.h5
# A coarser pull step: refused below 16 steps per collision, and at 32 it is half the bed's
# default step (t_c/64), recorded in the run file.
expect "'collision_steps'" "$gd" pull --bed good.h5 --output r.h5 --collision_steps 8
"$gd" pull --bed good.h5 --output run32.h5 --distance 0.5 --collision_steps 32 --quiet >/dev/null 2>&1 ||
  fail "a pull with --collision_steps 32 failed"
ratio=$(/usr/bin/python3 -c "import h5py; print(h5py.File('run32.h5')['/run'].attrs['dt'] / h5py.File('good.h5')['/contact'].attrs['dt'])")
if /usr/bin/python3 -c "import sys; sys.exit(abs($ratio - 2) > 1e-12)"; then
  echo "ok: collision_steps 32 steps at twice the bed's dt"
else
  fail "--collision_steps 32: the run's dt is $ratio times the bed's, expected 2"
fi
expect "either 'speed' or 'froude'" "$gd" pull --bed good.h5 --output r.h5 --speed 1 --froude 1
expect "either 'active_radius' (in d) or 'active_diameters'" "$gd" pull --bed good.h5 --output r.h5 --active_radius 5 --active_diameters 3
expect "'transient'" "$gd" pull --bed good.h5 --output r.h5 --distance 2 --transient 3
expect "either 'youngs_modulus'" "$gd" pour --output b.h5 --ly 8 --grains 400 --lx 8 --depth 2 --youngs_modulus 1e6 --kn 2e4
printf 'title\n\nabc atoms\n' > bad.data
expect "bad.data', line 3" "$gd" import-lammps --data bad.data --output i.h5
# A checkpoint of a pull with other options is refused on --resume, naming the difference.
# The pull is long (100 d) and checkpoints every 0.05: it is killed as soon as its first
# checkpoint exists (written to a temporary file, then renamed: complete when it appears),
# however slowly the machine runs; 600 s only bounds a pull that never checkpoints.
long=(--bed good.h5 --output k.h5 --distance 100 --checkpoint_interval 0.05)
"$gd" pull "${long[@]}" --speed 0.5 --quiet >/dev/null 2>&1 &
pid=$!
wait_for_file k.h5.checkpoint.h5 "$pid"
kill -9 "$pid" 2>/dev/null
wait "$pid" 2>/dev/null
if [ -f k.h5.checkpoint.h5 ]; then
  expect "now:        speed: 0.7" "$gd" pull "${long[@]}" --speed 0.7 --resume
else
  fail "the pull wrote no checkpoint (it ended, or wrote none in 600 s)"
fi
[ "$fails" -eq 0 ] && echo "PASS: every bad input was refused with its message"
exit "$fails"
