#!/usr/bin/env bash
# Runs every test: installs missing Debian packages, builds in build/, runs the GoogleTest
# suite and the command-line tests (ctest: bad input, kill + resume, parity with LAMMPS), the
# Python tests (analysis, workflow smoke study, incremental sweeps) with Debian's interpreter,
# and the SLURM profile on a real one-node cluster.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh test
# Debian's interpreter, not whichever python3 comes first on PATH (it may lack the packages).
PY=/usr/bin/python3
jobs=$(nproc)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DGRANUDRAG_TESTS=ON >/dev/null
cmake --build build -j "$jobs"
# Serial: each test uses both cores itself (OpenMP), and oversubscribed threads crawl.
(cd build && ctest --output-on-failure)
# Python: the analysis package, then the workflow (lint, smoke study end to end, incremental
# sweeps) on the binary just built.
GRANUDRAG="$PWD/build/granudrag" "$PY" -m pytest -q tests/python tests/workflow
# The SLURM profile on a real one-node cluster started here (needs root or passwordless sudo).
tests/workflow/slurm/test_slurm.sh build/granudrag
echo "all tests passed"
