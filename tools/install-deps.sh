#!/usr/bin/env bash
# Installs the Debian packages granudrag needs that are missing (sudo when not root), and for
# study/test/all/venv:
#   - the project environment .venv/ (Debian's /usr/bin/python3 -m venv): Snakemake 9, its SLURM
#     executor plugin, the analysis libraries, pytest, ruff and snakefmt at the versions and
#     hashes of requirements/project.txt (remade only when that file changed, else seconds;
#     tools/lock-deps.sh refreshes the lock), and the analysis package in it (pip install -e .);
#   - the analysis package (pyproject.toml) for Debian's /usr/bin/python3 too, in editable mode
#     in the user's site-packages (no sudo; reinstalled only when missing, installed from
#     another checkout or with other command-line entries), for Debian's /usr/bin/snakemake 7.21.
# Usage: tools/install-deps.sh [build|study|test|all|venv]   (default: all)
#   venv: only .venv/ (python3-venv must be installed)
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
build_pkgs=(g++ cmake make git libeigen3-dev libgtest-dev libhdf5-dev libyaml-cpp-dev hdf5-tools)
python_pkgs=(python3 python3-numpy python3-scipy python3-pandas python3-matplotlib python3-h5py
             python3-yaml python3-pytest python3-jsonschema python3-pil python3-pip python3-setuptools
             python3-venv snakemake)
# A real one-node SLURM cluster with accounting (slurmdbd on a MariaDB server) for the
# profiles' test (tests/workflow/slurm).
slurm_pkgs=(slurmctld slurmd slurm-client slurmdbd munge mariadb-server)
# The paper's own code, for the parity test and the benchmark comparison.
peer_pkgs=(lammps openmpi-bin)
# The style checks of tools/lint.sh that are not in the project environment (C++, shell).
lint_pkgs=(clang-format shellcheck)
case "${1:-all}" in
  build) wanted=("${build_pkgs[@]}") ;;
  study) wanted=("${build_pkgs[@]}" "${python_pkgs[@]}") ;;
  test|all) wanted=("${build_pkgs[@]}" "${python_pkgs[@]}" "${peer_pkgs[@]}" "${slurm_pkgs[@]}" "${lint_pkgs[@]}") ;;
  venv) wanted=() ;;
  *) echo "usage: $0 [build|study|test|all|venv]" >&2; exit 2 ;;
esac
# Pictures: Fig. 1's 3D panels and pull movies (ParaView's pvbatch under a virtual X server, ffmpeg).
case "${1:-all}" in study|test|all) wanted+=(paraview python3-paraview xvfb xauth ffmpeg) ;; esac
missing=()
for p in ${wanted[@]+"${wanted[@]}"}; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}" >&2
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi
[ "${1:-all}" = build ] && exit 0

# Where the interpreter's `analysis` comes from, asked from / so that the current directory
# does not answer; "stale" when its installed command-line entries are not pyproject.toml's
# (an install from before [project.scripts] changed).
where='
import sys, tomllib
from importlib.metadata import distribution
import analysis, granudrag_study
scripts = tomllib.load(open(sys.argv[1], "rb"))["project"].get("scripts", {})
installed = {e.name: e.value for e in distribution("granudrag-analysis").entry_points if e.group == "console_scripts"}
print(analysis.__path__[0] + " " + granudrag_study.__path__[0] if scripts == installed else "stale")
'

# The project environment: made again when requirements/project.txt differs from the copy
# kept in it (a fresh venv, so nothing outside the lock lingers); the analysis package in it
# from this checkout.
venv="$repo/.venv"
lock="$repo/requirements/project.txt"
if ! cmp -s "$lock" "$venv/requirements-project.txt" || [ ! -x "$venv/bin/snakemake" ]; then
  echo "install-deps: making $venv from $lock (pinned, hashed; about a minute)" >&2
  rm -rf "$venv"
  /usr/bin/python3 -m venv "$venv"
  # The two dependencies published only as source are built with the lock's setuptools and
  # wheel, installed first.
  awk '/^(setuptools|wheel)==/ {on = 1} on {print} on && !/\\$/ {on = 0}' "$lock" > "$venv/build-tools.txt"
  "$venv/bin/pip" install --quiet --disable-pip-version-check --require-hashes --no-deps \
    -r "$venv/build-tools.txt" >&2
  "$venv/bin/pip" install --quiet --disable-pip-version-check --require-hashes --no-build-isolation \
    -r "$lock" >&2
  cp "$lock" "$venv/requirements-project.txt"
fi
installed=$(cd / && { "$venv/bin/python" -c "$where" "$repo/pyproject.toml" 2>/dev/null || true; })
if [ "$installed" != "$repo/analysis $repo/workflow/granudrag_study" ]; then
  echo "install-deps: installing the analysis package from $repo into $venv (pip, editable)" >&2
  "$venv/bin/pip" install --quiet --disable-pip-version-check --no-deps --no-build-isolation -e "$repo" >&2
fi
[ "${1:-all}" = venv ] && exit 0
# `analysis` from this checkout, with pyproject.toml's entries, for Debian's interpreter too?
installed=$(cd / && { /usr/bin/python3 -c "$where" "$repo/pyproject.toml" 2>/dev/null || true; })
if [ "$installed" != "$repo/analysis $repo/workflow/granudrag_study" ]; then
  echo "install-deps: installing the analysis package from $repo (pip, editable, user site)" >&2
  /usr/bin/python3 -m pip install --quiet --user --break-system-packages --no-deps --no-build-isolation \
    --no-warn-script-location -e "$repo" >&2
fi
