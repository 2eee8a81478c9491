#!/usr/bin/env bash
# Runs every test: installs missing Debian packages, builds from scratch in build/, runs the
# GoogleTest suite and CLI checks (ctest), then the Python tests with Debian's interpreter.
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
if [ -d tests/python ]; then
  "$PY" -m pytest -q tests/python
fi
echo "all tests passed"
