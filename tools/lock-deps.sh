#!/usr/bin/env bash
# Refreshes requirements/project.txt, the pinned and hashed lock of the project environment
# (.venv/), from requirements/project.in: every package at the newest version the pins of
# project.in allow, with the sha256 of each of its published files. Run it after editing
# project.in (or to take up new releases), review the diff, run tools/test.sh, commit both
# files; tools/install-deps.sh then remakes .venv/ because the lock changed.
#   tools/lock-deps.sh [pip-compile options, e.g. --upgrade-package pandas]
# pip-compile (pip-tools) runs in a throw-away environment made with Debian's /usr/bin/python3,
# so the lock is resolved for the interpreter .venv/ is made from (CPython 3.11 on Debian 12).
set -euo pipefail
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 -m venv "$tmp/venv"
"$tmp/venv/bin/pip" install --quiet --disable-pip-version-check pip-tools==7.6.2
"$tmp/venv/bin/pip-compile" --quiet --generate-hashes --allow-unsafe --strip-extras --no-header \
  --output-file requirements/project.txt "$@" requirements/project.in
echo "lock-deps: requirements/project.txt: $(grep -cE '^[A-Za-z0-9]' requirements/project.txt) packages pinned"
