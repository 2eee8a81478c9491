#!/usr/bin/env bash
# Installs the Debian packages granudrag needs that are missing (sudo when not root), and for
# study/test/all the analysis package (pyproject.toml) for Debian's /usr/bin/python3, in
# editable mode in the user's site-packages (no sudo; reinstalled only when missing or
# installed from another checkout).
# Usage: tools/install-deps.sh [build|study|test|all]   (default: all)
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
build_pkgs=(g++ cmake make git libeigen3-dev libgtest-dev libhdf5-dev libyaml-cpp-dev hdf5-tools)
python_pkgs=(python3 python3-numpy python3-scipy python3-pandas python3-matplotlib python3-h5py
             python3-yaml python3-pytest python3-jsonschema python3-pil python3-pip python3-setuptools
             snakemake)
# A real one-node SLURM cluster for the profile's test (tests/workflow/slurm).
slurm_pkgs=(slurmctld slurmd slurm-client munge)
# The paper's own code, for the parity test and the benchmark comparison.
peer_pkgs=(lammps openmpi-bin)
case "${1:-all}" in
  build) wanted=("${build_pkgs[@]}") ;;
  study) wanted=("${build_pkgs[@]}" "${python_pkgs[@]}") ;;
  test|all) wanted=("${build_pkgs[@]}" "${python_pkgs[@]}" "${peer_pkgs[@]}" "${slurm_pkgs[@]}" clang-format python3-venv) ;;
  *) echo "usage: $0 [build|study|test|all]" >&2; exit 2 ;;
esac
# Pictures: Fig. 1's 3D panels and pull movies (ParaView's pvbatch under a virtual X server, ffmpeg).
case "${1:-all}" in study|test|all) wanted+=(paraview python3-paraview xvfb xauth ffmpeg) ;; esac
missing=()
for p in "${wanted[@]}"; do
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
# `analysis` from this checkout? (Asked from / so that the current directory does not answer.)
installed=$(cd / && /usr/bin/python3 -c 'import analysis; print(analysis.__path__[0])' 2>/dev/null || true)
if [ "$installed" != "$repo/analysis" ]; then
  echo "install-deps: installing the analysis package from $repo (pip, editable, user site)" >&2
  /usr/bin/python3 -m pip install --quiet --user --break-system-packages --no-deps --no-build-isolation \
    --no-warn-script-location -e "$repo" >&2
fi
