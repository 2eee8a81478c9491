#!/usr/bin/env bash
# Runs every test: installs missing Debian packages and the project environment .venv/
# (tools/install-deps.sh); the format and lint checks (tools/lint.sh); builds in build/
# (warnings are errors) and runs the GoogleTest suite and the command-line tests (ctest: bad
# input, kill + resume, parity with LAMMPS); builds the unit tests with AddressSanitizer +
# UndefinedBehaviorSanitizer in build-asan/ and runs them; the Python tests: the analysis under
# the project environment, the workflow (smoke study, incremental sweeps, snakemake --lint,
# --report) under it with Snakemake 9 and under Debian's interpreter with Snakemake 7.21; and the
# smoke study's beds, pulls, table and fits (two of its sweeps) through both SLURM profiles on
# a real one-node cluster with accounting.
# Prints how long each step took.
#   tools/test.sh           every test (the README's test command, and CI's)
#   tools/test.sh --quick   the inner loop: lint, build, the C++ unit tests and the Python unit
#                           tests (tests/python) under the project environment; no sanitizers,
#                           command-line, workflow or SLURM tests
set -euo pipefail
cd "$(dirname "$0")/.."
quick=false
case "${1:-}" in
  --quick) quick=true ;;
  "") ;;
  *) echo "tools/test.sh: unknown option '$1' (use --quick for the inner loop, nothing for every test)" >&2; exit 2 ;;
esac
tools/install-deps.sh test
# Debian's interpreter, not whichever python3 comes first on PATH (it may lack the packages).
PY=/usr/bin/python3
jobs=$(nproc)
start=$SECONDS
step_start=$SECONDS
took() {  # took "what": the time since the previous step ended
  echo "test.sh: $1 took $((SECONDS - step_start)) s"
  step_start=$SECONDS
}
# Commands run side by side: `beside LOG COMMAND...` starts one in the background, its output
# to LOG; `joined` waits for every one started, prints the last line of each log (from pytest's
# table of its slowest tests on, where it printed one; the whole log of one that failed) and
# fails if any did.
beside_started=()
beside() {
  local log=$1
  shift
  "$@" > "$log" 2>&1 &
  beside_started+=("$! $log")
}
joined() {
  local ok=true entry pid log
  for entry in "${beside_started[@]}"; do
    read -r pid log <<<"$entry"
    echo "--- $log:"
    if ! wait "$pid"; then
      cat "$log"
      ok=false
    elif grep -q '^=* slowest' "$log"; then
      sed -n '/^=* slowest/,$p' "$log"
    else
      tail -n 1 "$log"
    fi
  done
  beside_started=()
  $ok
}

tools/lint.sh
took "format and lint checks"

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DGRANUDRAG_TESTS=ON >/dev/null
cmake --build build -j "$jobs"
took "build"
# The analysis tests that take most of the analysis tests' time (ParaView's, the figures', the
# fits' calibration): a process of their own, beside the others, in --quick and in the full run.
slow_python=(tests/python/test_paraview.py tests/python/test_figures.py tests/python/test_calibration.py)
# Side by side: each test declares its cores (PROCESSORS 2 for the two-thread tests, one
# thread for the others; see CMakeLists.txt), so ctest never oversubscribes the machine.
if $quick; then
  (cd build && ctest -j "$jobs" --output-on-failure -L unit)
  took "C++ unit tests"
  # Two processes side by side: ParaView's, the figures' and the calibration's tests, and the
  # others; one process took 208 s (fresh clone of 3482489, 2026-11-26), ParaView's and the
  # figures' against the rest 105 and 153 s.
  qtmp=$(mktemp -d)
  trap 'rm -rf "$qtmp"' EXIT
  beside "$qtmp/drawing.log" env GRANUDRAG="$PWD/build/granudrag" .venv/bin/python -m pytest -q \
    -p no:cacheprovider --basetemp "$qtmp/drawing" "${slow_python[@]}"
  beside "$qtmp/rest.log" env GRANUDRAG="$PWD/build/granudrag" .venv/bin/python -m pytest -q \
    -p no:cacheprovider --basetemp "$qtmp/rest" "${slow_python[@]/#/--ignore=}" tests/python
  joined || { echo "test.sh: Python unit tests failed (their output above)" >&2; exit 1; }
  took "Python unit tests (two processes)"
  echo "quick tests passed in $((SECONDS - start)) s (every test: tools/test.sh)"
  exit 0
fi
(cd build && ctest -j "$jobs" --output-on-failure)
took "C++ and command-line tests"

# The unit tests under AddressSanitizer + UndefinedBehaviorSanitizer (-O1 -g, assertions on):
# any out-of-bounds access, use after free, leak or undefined behaviour stops the run with a
# stack. A few processes, not one per test, so the pull tests pour their shared bed once per
# process (as separate ctest processes each would pour it again: 205 s instead of 160 s). Not run here, the four tests that integrate
# a whole bed for thousands of steps: minutes each under instrumentation (6 to 12 on a busy
# 2-core machine), for the same
# code (contact loops, integrator, pour and pull steps) the shorter tests run on fewer steps.
# ThreadSanitizer is not run: see CMakeLists.txt.
asan_skip=Conservation.EnergyOfDensePackingOver1e5Steps:Pull.MeasuresDragAndContactsOfAMovingIntruder
asan_skip+=':Pour.DoesNotStopBeforeTheGrainsHaveFallen:Friction/PourDepth.*'
# and the sequential-stopping pull, 114 s under instrumentation (10 s in the release suite), for
# the pull loop the other pull tests run; the stopping rule runs under instrumentation in
# Pull.AResumedPullStopsAtTheSameStepAsAnUninterruptedOne.
asan_skip+=:Pull.ATargetErrorStopsThePullOnceTheDragIsThatPrecise
# and two whose code runs instrumented in others: a pull resumed from its checkpoint (34 s; the
# checkpoint is written, read and resumed under instrumentation by the stopping rule's resume
# test above, the active region's and the pour's), and the error's coverage of the two recorded
# sets of series (seconds of arithmetic; the estimator runs instrumented on AR(1) series).
asan_skip+=':Pull.ResumedFromCheckpointIsBitwiseIdentical:Observables.NinetyFivePercentIntervalsCover*'
# A unity build (eight sources per compiler run): the instrumented build compiles every source a
# second time, and most of its time went to parsing the same GoogleTest, Eigen and HDF5 headers
# in each file: 213 s of CPU instead of 409 s (measured 2026-11-26). The release build above
# stays one source per compiler run, so a missing #include still fails there.
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" \
  -DGRANUDRAG_SANITIZE="address;undefined" -DGRANUDRAG_TESTS=ON \
  -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=8 >/dev/null
cmake --build build-asan -j "$jobs" --target granudrag_tests
took "sanitizer build"
# In two processes side by side, one thread each but for the oracle tests' own 2 (waiting
# passively): the tests are single-threaded at -O1 under instrumentation. The second process
# takes the long resume, fuzzing and checksum tests (83 s of instrumented time, measured
# 2026-11-26), the first every other one (81 s, the oracle its longest): GoogleTest's own
# sharding (test i in shard i mod N) put the long tests together, 146 s against 51 s. Each
# process pours the pull tests' shared bed once.
asan_long='Pull.AResumedPullStopsAtTheSameStepAsAnUninterruptedOne:FuzzReaders.*'
asan_long+=:Pour.ResumedFromACheckpointItEndsBitwiseAsAnUninterruptedPour
asan_long+=:ActiveRegion.APullWithSleepingGrainsResumesFromACheckpointBitwise
asan_long+=:Checksums.ABitFlippedInsideAnyDatasetsDataIsNamedOnReadAndTheReadersNeverPassItOn
asan_tests() {  # asan_tests FILTER: the unit tests FILTER selects
  OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive \
    ASAN_OPTIONS=halt_on_error=1:detect_leaks=1:abort_on_error=0:strict_string_checks=1 \
    UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    build-asan/granudrag_tests --gtest_brief=1 --gtest_filter="$1"
}
beside build-asan/rest.log asan_tests "-$asan_skip:$asan_long"
beside build-asan/long.log asan_tests "$asan_long"
joined || { echo "test.sh: sanitizer tests failed (their output above)" >&2; exit 1; }
took "unit tests under AddressSanitizer + UndefinedBehaviorSanitizer (two processes)"

# Python, on the binary just built: the analysis package (tests/python) under the project
# environment (.venv/: pinned NumPy, pandas, SciPy, ... and Snakemake 9), and the workflow (lint,
# smoke study end to end, incremental sweeps, report; tests/workflow) under each Snakemake
# generation: the project environment's 9 and Debian's /usr/bin/snakemake 7.21 on Debian's
# interpreter and packages, where the smoke study runs the table, fits, figures and report on
# Debian's NumPy, pandas, SciPy and matplotlib. Under Debian's interpreter the analysis unit tests
# add the packaging and command-line ones (the package installed for it, its entry points) and
# the figures' and ParaView's (below); running all of them a second time cost 140 s on 2 cores.
# What this leaves untested on Debian's packages is analysis code the smoke study does not reach
# (the ladder, the validation comparisons).
# The two passes run side by side, each in its own temporary directories (debian.log: Debian's
# Python and Snakemake 7.21; venv.log: the project environment and Snakemake 9).
pytmp=$(mktemp -d)
trap 'rm -rf "$pytmp"' EXIT
# The figures' and ParaView's unit tests (slow_python, above; 110 s of the analysis tests' 250) run in Debian's pass
# only, which balances the two (they took 268 and 491 s with both there, 2026-11-26): the smoke
# study draws every figure under each Snakemake generation, so the project environment's
# matplotlib still draws them; `--quick` runs them under the project environment. So does the
# fits' calibration on synthetic studies (33 s; the passes took 291 and 337 s with it in the
# project environment's, 2026-11-26), whose figures are the same on Debian's packages.
# Workflow tests whose subject is not the Snakemake generation run in one pass only, chosen to
# balance the two (measured 2026-11-26 under Debian's pass): the movie target (46 s: a pull with
# frames and ParaView's drawing, plain rules the smoke study runs under both) and the bed
# chaining test (4 s; it runs Debian's Snakemake in either pass) in Debian's; the two validation
# studies end to end (11 s), the measured cost estimate (2 s) and a committed rung refitted on
# both Python stacks (test_stacks.py, which starts both interpreters itself) in the project environment's.
# Everything about the generations (the smoke study, faults, kill and unlock, --lint, --report,
# --rerun-triggers, extending a grid, every validation config planned) runs in both.
workflow_debian_only=(tests/workflow/test_smoke.py::test_the_movie_target_pulls_figure_4s_pull_again_with_frames
  tests/workflow/test_bed_chaining.py)
workflow_venv_only=(tests/workflow/test_stacks.py::test_a_committed_rung_refits_alike
  tests/workflow/test_validation_target.py::test_yield_speed_validation_runs_end_to_end
  tests/workflow/test_validation_target.py::test_pull_length_validation_runs_end_to_end
  tests/workflow/test_study.py::test_estimate_cost_measures_throughput_and_scales_the_cost)
# Each pass prints its slowest tests (pytest --durations), where the suite's time goes.
durations=(--durations=12 --durations-min=10)
beside "$pytmp/debian.log" env GRANUDRAG="$PWD/build/granudrag" "$PY" -m pytest -q -p no:cacheprovider "${durations[@]}" \
  --basetemp "$pytmp/debian" "${workflow_venv_only[@]/#/--deselect=}" \
  tests/workflow tests/python/test_packaging.py tests/python/test_cli.py "${slow_python[@]}"
beside "$pytmp/venv.log" env GRANUDRAG="$PWD/build/granudrag" GRANUDRAG_SNAKEMAKE="$PWD/.venv/bin/snakemake" \
  .venv/bin/python -m pytest -q -p no:cacheprovider "${durations[@]}" --basetemp "$pytmp/venv" "${slow_python[@]/#/--ignore=}" \
  "${workflow_debian_only[@]/#/--deselect=}" tests/python tests/workflow
joined || { echo "test.sh: a Python pass failed (its output above)" >&2; exit 1; }
took "Python tests: the workflow under Debian's Python + Snakemake 7.21 and everything under the project environment + Snakemake 9, side by side"
# Both SLURM profiles on a real one-node cluster with accounting (slurmdbd, MariaDB) started
# here (needs root or passwordless sudo): two of the smoke study's sweeps to their table and fits
# through Snakemake 9 + the executor plugin and through 7.21 + slurm-v7, and a pull killed at its
# time limit that resumes.
tests/workflow/slurm/test_slurm.sh build/granudrag
took "SLURM tests (both profiles)"
echo "all tests passed in $((SECONDS - start)) s"
