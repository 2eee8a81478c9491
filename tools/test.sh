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
#   tools/test.sh --quick   the inner loop: lint, build, the C++ and Python unit tests (tests/python,
#                           the project environment) but the slow ones (quick_skip below; the
#                           `slow` marker); no sanitizers, command-line, workflow or SLURM tests
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

# The test sources in unity batches of eight (CMakeLists.txt): 117 s of CPU to compile them
# instead of 207 s, one source per compiler run (2026-12-02, a busy 2-core machine).
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DGRANUDRAG_TESTS=ON -DGRANUDRAG_UNITY_TESTS=ON >/dev/null
cmake --build build -j "$jobs"
took "build"
# The unit tests that integrate a bed for many steps (2.5 s or more each on an idle 2-core machine,
# 22 of 190 measured 2026-12-03): --quick leaves them out, the full run below runs every one.
quick_skip=ActiveRegion.APullWithSleepingGrainsResumesFromACheckpointBitwise:ActiveRegion.ARegionWiderThanTheBoxChangesNoBitOfAPull
quick_skip+=:ActiveRegion.SkippingQuietGrainsChangesNoBitOfAPull:ActiveRegion.TheIntegratorSplitsTheBodiesItStepsEvenlyBetweenThreads
quick_skip+=':Checksums.*:Conservation.EnergyOfDensePackingOver1e5Steps:Friction/PourDepth.*:FuzzReaders.*'
quick_skip+=':Observables.NinetyFivePercentIntervalsCover*ForceSeries:Oracle.FastForcesEqualBruteForceOnIntruderScene'
quick_skip+=:Oracle.WithSleepingGrainsTheFastPathComputesWhatTheOracleDoes:Placement.TheBedSettlesAroundTheHeldIntruderAtItsDepth
quick_skip+=:Pour.SettleDampingKeepsThePackingAndResumesBitwise:Pull.AReplicaStartsFromTheSameBedWithOneGrainNudgedAndResumesBitwise
quick_skip+=:Pull.AResumedPullStopsAtTheSameStepAsAnUninterruptedOne:Pull.ATargetErrorStopsThePullOnceTheDragIsThatPrecise
quick_skip+=:Pull.FramesComeAtStepZeroAndEveryDumpIntervalAndResumeWhereTheCheckpointCounted
quick_skip+=:Pull.MeasuresDragAndContactsOfAMovingIntruder:Pull.ResumedFromCheckpointIsBitwiseIdentical
quick_skip+=:SpatialOrder.APouredBedSweptAlongXTakesTheTwoColoursOnTwoAndFourThreadsWithTheSameForces
quick_skip+=:SpatialOrder.APullStepsTheBedSweptAlongXResumesBitwiseAndShowsTheBedsOrder
quick_skip+=:SpatialOrder.IsAPermutationWithIntrudersLastSweepingAWideBedAlongItsLongerAxis
if $quick; then
  # Three processes side by side: the other C++ unit tests in one process (it pours the pull
  # tests' shared bed once, where ctest's process per test pours it for each: 14 s of CPU for
  # 161 tests, against 142 s of wall time for all 190 through ctest), and the Python unit tests
  # not marked slow (tests/python/conftest.py: over about 2 s each), the figures' apart.
  qtmp=$(mktemp -d)
  trap 'rm -rf "$qtmp"' EXIT
  beside "$qtmp/unit.log" env OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive build/granudrag_tests --gtest_brief=1 \
    --gtest_filter="-$quick_skip"
  beside "$qtmp/drawing.log" env GRANUDRAG="$PWD/build/granudrag" .venv/bin/python -m pytest -q \
    -p no:cacheprovider -m "not slow" --basetemp "$qtmp/drawing" tests/python/test_figures.py
  beside "$qtmp/rest.log" env GRANUDRAG="$PWD/build/granudrag" .venv/bin/python -m pytest -q \
    -p no:cacheprovider -m "not slow" --basetemp "$qtmp/rest" --ignore=tests/python/test_figures.py tests/python
  joined || { echo "test.sh: unit tests failed (their output above)" >&2; exit 1; }
  took "unit tests: C++ and Python, but those marked slow (three processes)"
  echo "quick tests passed in $((SECONDS - start)) s (every test: tools/test.sh)"
  exit 0
fi
# The analysis tests that take most of the analysis tests' time (ParaView's, the figures', the
# fits' calibration): a process of their own, beside the others (below).
slow_python=(tests/python/test_paraview.py tests/python/test_figures.py tests/python/test_calibration.py)
# Side by side: each test declares its cores (PROCESSORS 2 for the two-thread tests, one
# thread for the others; see CMakeLists.txt), so ctest never oversubscribes the machine.
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
# compiles the library one source per compiler run, so a missing #include still fails there.
# -g1: line tables only, which is all a sanitizer's stack needs (file:line of every frame);
# full debug information (-g) took 47.6 s of CPU for a batch of the tests, -g1 33.8 s, and
# 4.3 against 3.5 s for one of the library's (2026-12-02, the same compiler commands).
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" \
  -DGRANUDRAG_SANITIZE="address;undefined" -DGRANUDRAG_TESTS=ON \
  -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=8 >/dev/null
cmake --build build-asan -j "$jobs" --target granudrag_tests
took "sanitizer build"
# In two processes side by side, one thread each but for the oracle tests' own 2 (waiting
# passively): the tests are single-threaded at -O1 under instrumentation. The second process
# takes the long resume, fuzzing and checksum tests (83 s of instrumented time, measured
# 2026-11-26), the first every other one (81 s, the oracle its longest): GoogleTest's own
# sharding (test i in shard i mod N) put the long tests together, 146 s against 51 s. Each
# process pours the pull tests' shared bed once. On the slower machine class the first took
# 498 s and the second 317 s (.ci/run of 78b958b, 2026-12-02), so the oracle's intruder scene
# (about 33 s instrumented on the faster machine) moved to the second: any test under 181 s
# shortens the step. Each process prints its slowest tests, to balance them by measurement.
asan_long='Pull.AResumedPullStopsAtTheSameStepAsAnUninterruptedOne:FuzzReaders.*'
asan_long+=:Oracle.FastForcesEqualBruteForceOnIntruderScene
asan_long+=:Pour.ResumedFromACheckpointItEndsBitwiseAsAnUninterruptedPour
asan_long+=:ActiveRegion.APullWithSleepingGrainsResumesFromACheckpointBitwise
asan_long+=:Checksums.ABitFlippedInsideAnyDatasetsDataIsNamedOnReadAndTheReadersNeverPassItOn
# Balanced by the processes' totals (.ci/run of fde9d1c, 2026-12-02, idle: 276 s and 243 s):
# the replica's test (20 s) moved here.
asan_long+=:Pull.AReplicaStartsFromTheSameBedWithOneGrainNudgedAndResumesBitwise
asan_tests() {  # asan_tests FILTER: the unit tests FILTER selects
  OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive \
    ASAN_OPTIONS=halt_on_error=1:detect_leaks=1:abort_on_error=0:strict_string_checks=1 \
    UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    build-asan/granudrag_tests --gtest_filter="$1"
}
beside build-asan/rest.log asan_tests "-$asan_skip:$asan_long"
beside build-asan/long.log asan_tests "$asan_long"
joined || { echo "test.sh: sanitizer tests failed (their output above)" >&2; exit 1; }
for log in build-asan/rest.log build-asan/long.log; do
  echo "--- $log: $(grep -o '[0-9]* ms total' "$log" | tail -n 1); its slowest tests (ms):"
  awk '/^\[       OK \] .* ms\)$/ { gsub(/[(]/, "", $(NF - 1)); print $(NF - 1), $4 }' "$log" |
    sort -rn | sed -n 1,6p
done
took "unit tests under AddressSanitizer + UndefinedBehaviorSanitizer (two processes)"

# Python, on the binary just built, in two passes side by side, each in its own temporary
# directories: debian.log, Debian's interpreter and packages with /usr/bin/snakemake 7.21;
# venv.log, the project environment (.venv/: pinned NumPy, pandas, SciPy, ... and Snakemake 9).
# A test runs in both passes only when what it tests differs between them (issue 75: with
# every workflow test in both, the passes took 1,053 and 1,191 s on the slower machine class,
# .ci/run of 78b958b, 2026-12-02). The analysis unit tests (tests/python) run once, in the
# project environment's pass, but for the ones below that balance the two; Debian's pass adds
# the packaging and command-line ones (the package installed for it, its entry points).
# Debian's packages run the smoke study's table, fits, figures and report end to end; the
# analysis code it does not reach (the ladder, the validation comparisons) is tested on the
# project environment's packages only.
pytmp=$(mktemp -d)
trap 'rm -rf "$pytmp"' EXIT
# Under both Snakemake generations: what Snakemake itself does for the workflow, which 7.21 and
# 9 may do differently. The smoke study end to end (the fixture `smoke`; on Debian's packages
# too) and what test_smoke.py asks of it: dry-run plans, --forcerun, --rerun-triggers, --report,
# --lint, the profiles parsed, a grid extended (which jobs its parameter and input changes make
# Snakemake run again). A failed pull under --keep-going: the onsuccess/onerror hooks and a
# placeholder output left in place or retried. tools/study.sh's lock, which reads Snakemake's
# lock files, and a study killed with SIGKILL, which Snakemake must unlock and rerun as
# incomplete. Hostile config values through Snakemake's `:q` quoting. The placement rules'
# plan, and a failed or killed placement, whose outputs Snakemake removes. Every validation
# config's plan (its input functions under each generation's DAG). The config schema's checks
# of every shipped config and of bad keys, on each stack's jsonschema and YAML.
workflow_both=(tests/workflow/test_smoke.py tests/workflow/test_study_lock.py
  tests/workflow/test_study.py::test_schema_errors_name_the_key tests/workflow/test_study.py::test_shipped_configs_are_valid
  tests/workflow/test_faults.py::test_a_failed_pull_lets_the_others_finish_is_listed_with_its_reason_and_is_retried_alone
  tests/workflow/test_paths.py::TestInTheWorkflow::test_a_config_value_with_a_semicolon_and_command_substitution_runs_nothing
  tests/workflow/test_paths.py::TestInTheWorkflow::test_a_brace_path_is_refused_by_the_workflow_naming_the_key
  tests/workflow/test_placement.py::test_the_rules_pour_a_column_per_seed_and_place_each_bed
  tests/workflow/test_placement.py::test_a_failed_placement_leaves_no_bed_and_says_why
  tests/workflow/test_placement.py::test_a_placement_killed_mid_run_starts_over_cleanly
  tests/workflow/test_validation_target.py::test_every_validation_config_plans_its_comparison)
# Once, every other workflow test: its subject is the engine, the analysis or the workflow's
# own library (the plan, paths, costs; resumable.sh), reached the same way under either
# generation. The study killed three times tests the pulls' resume and a table identical to an
# uninterrupted one's (a SIGKILL under 7.21 is test_study_lock.py's, and the SLURM step's time
# limit under slurm-v7); the study from an odd path, the same `:q` quoting the hostile values
# test under both; the validation studies, the placed study and the movie target end to end,
# rules of the same kind as the smoke study's, whose plans are tested under both;
# test_stacks.py starts both interpreters itself; bed chaining runs Debian's Snakemake in
# either pass. Most run in the project environment's pass (Snakemake 9 is what tools/study.sh
# runs); these in Debian's, to balance the two (from the passes' slowest tests on the slower
# machine class in that run: the study killed three times 63 s in Debian's pass and 75 s in the
# project environment's, the odd path 35 and 37 s, the movie 120 s in Debian's; the placed study
# 28 s and the placement validation 30 s, in the one pass whose table listed each).
movie=tests/workflow/test_smoke.py::test_the_movie_target_pulls_figure_4s_pull_again_with_frames  # with test_smoke.py
workflow_debian_only=(tests/workflow/test_bed_chaining.py
  tests/workflow/test_faults.py::test_a_study_killed_three_times_at_random_moments_ends_as_an_uninterrupted_one
  tests/workflow/test_paths.py::TestInTheWorkflow::test_the_smoke_study_runs_from_a_path_with_a_space_quotes_and_a_non_ascii_letter
  tests/workflow/test_placement.py::test_a_placed_study_runs_to_its_table_and_a_new_depth_reuses_the_column
  tests/workflow/test_validation_target.py::test_placement_validation_compares_placed_beds_with_poured_ones)
# The figures', ParaView's and the fits' calibration's unit tests (slow_python, above) also run
# in Debian's pass only, for balance (the passes took 268 and 491 s with the first two in the
# project environment's, faster machine, 2026-11-26): the smoke study draws every figure under
# each generation, so the project environment's matplotlib still draws them, and `--quick` runs
# all three there.
# Each pass prints its slowest tests (pytest --durations): where the suite's time goes, and
# what to move to balance the two.
durations=(--durations=25 --durations-min=5)
beside "$pytmp/debian.log" env GRANUDRAG="$PWD/build/granudrag" "$PY" -m pytest -q -p no:cacheprovider "${durations[@]}" \
  --basetemp "$pytmp/debian" "${workflow_both[@]}" "${workflow_debian_only[@]}" \
  tests/python/test_packaging.py tests/python/test_cli.py "${slow_python[@]}"
beside "$pytmp/venv.log" env GRANUDRAG="$PWD/build/granudrag" GRANUDRAG_SNAKEMAKE="$PWD/.venv/bin/snakemake" \
  .venv/bin/python -m pytest -q -p no:cacheprovider "${durations[@]}" --basetemp "$pytmp/venv" "${slow_python[@]/#/--ignore=}" \
  "${workflow_debian_only[@]/#/--deselect=}" --deselect="$movie" tests/python tests/workflow
joined || { echo "test.sh: a Python pass failed (its output above)" >&2; exit 1; }
took "Python tests: the workflow under Debian's Python + Snakemake 7.21 and everything under the project environment + Snakemake 9, side by side"
# Both SLURM profiles on a real one-node cluster with accounting (slurmdbd, MariaDB) started
# here (needs root or passwordless sudo): two of the smoke study's sweeps to their table and fits
# through Snakemake 9 + the executor plugin and through 7.21 + slurm-v7, and a pull killed at its
# time limit that resumes.
tests/workflow/slurm/test_slurm.sh build/granudrag
took "SLURM tests (both profiles)"
echo "all tests passed in $((SECONDS - start)) s"
