# shellcheck shell=bash
# Sourced by bench/compare_lammps.sh and bench/size_growth.sh: the pull both time, counted in
# steps of the bed's dt, so that their figures are of the same workload.
#
# recipe_pull GD BED STEPS SPEED [EVERY] sets
#   every       steps per force sample: EVERY, or `granudrag pull`'s default sample_interval (a
#               study's sampling) in steps of the bed's dt
#   distance    travel half a step short of STEPS steps at SPEED (granudrag rounds it up to STEPS)
#   interval    the sample interval, every x dt
#   checkpoint  the checkpoint interval: one checkpoint, half-way
# GD is the granudrag binary, BED the bed file.
# shellcheck disable=SC2034  # every, distance, interval and checkpoint are the caller's
recipe_pull() {
  local gd=$1 bed=$2 steps=$3 speed=$4 dt sample
  every=${5:-}
  dt=$(/usr/bin/python3 -c "import h5py; print(repr(float(h5py.File('$bed')['/contact'].attrs['dt'])))")
  if [ -z "$every" ]; then
    sample=$("$gd" pull --help | awk '$1 == "sample_interval" {print $4}')
    every=$(/usr/bin/python3 -c "print(max(1, round($sample / $dt)))")
  fi
  distance=$(/usr/bin/python3 -c "print(repr(($steps - 0.5) * $dt * $speed))")
  interval=$(/usr/bin/python3 -c "print(repr($every * $dt))")
  checkpoint=$(/usr/bin/python3 -c "print(repr(($steps // 2) * $dt))")
}
