#!/usr/bin/env bash
# granudrag vs LAMMPS gran/hertz/history on the same bed, contact law and steps, in one session.
#
#   bench/compare_lammps.sh [GRAINS] [STEPS] [SETTLE]     (defaults 20000 2000 15000)
#
# granudrag collapses an fcc lattice into a bed in contact (SETTLE untimed steps), writes that
# state as a LAMMPS data file plus an input script, then times STEPS steps on 1 and 2 OpenMP
# threads. LAMMPS (Debian's `lmp`, which has no OPENMP package) runs the same STEPS from the
# same state serially and on 2 MPI ranks. Both report the final kinetic energies per grain, a
# check that they computed the same thing. Needs: apt-get install lammps openmpi-bin.
set -euo pipefail
cd "$(dirname "$0")/.."
grains=${1:-20000}
steps=${2:-2000}
settle=${3:-15000}
out=bench/out
mkdir -p "$out"
command -v lmp >/dev/null || { echo "LAMMPS not found: apt-get install lammps openmpi-bin" >&2; exit 1; }
[ -x build/granudrag ] || { cmake -S . -B build >/dev/null && cmake --build build -j "$(nproc)" >/dev/null; }

echo "== granudrag ($(build/granudrag version))"
build/granudrag bench --grains "$grains" --steps "$steps" --settle "$settle" --threads 1,2 \
  --lammps "$out/bed" 2>/dev/null | tee "$out/granudrag.txt"

mpi_root=""
[ "$(id -u)" -eq 0 ] && mpi_root="--allow-run-as-root"
echo "== LAMMPS ($(lmp -h 2>/dev/null | grep -m1 -o 'LAMMPS ([^)]*)' || echo lmp))"
(cd "$out" && OMP_NUM_THREADS=1 lmp -in bed.in -log lammps1.log -screen none)
(cd "$out" && OMP_NUM_THREADS=1 mpirun $mpi_root -np 2 lmp -in bed.in -log lammps2.log -screen none)

loop_time() { awk '/^Loop time of/ {print $4}' "$1"; }
final_ke() { awk -v s="$steps" '$1==s && NF>=4 {print $3, $4}' "$1" | tail -1; }
g1=$(awk '$1=="1" && NF>=9 {print $3}' "$out/granudrag.txt")
g2=$(awk '$1=="2" && NF>=9 {print $3}' "$out/granudrag.txt")
l1=$(loop_time "$out/lammps1.log")
l2=$(loop_time "$out/lammps2.log")
gke=$(awk '/final energy per grain/ {print $7, $9}' "$out/granudrag.txt" | tr -d ',')

echo
echo "== $grains grains, $steps steps, same bed and contact law"
printf "%-22s %6s %10s %18s %14s\n" code cores "wall[s]" "particle-steps/s" "vs LAMMPS 1"
for row in "granudrag(OpenMP) 1 $g1" "granudrag(OpenMP) 2 $g2" "LAMMPS(serial) 1 $l1" "LAMMPS(MPI) 2 $l2"; do
  set -- $row
  awk -v c="$1" -v n="$2" -v w="$3" -v g="$grains" -v s="$steps" -v ref="$l1" \
    'BEGIN {printf "%-22s %6d %10.2f %18.4g %13.2fx\n", c, n, w, g*s/w, ref/w}'
done
awk -v a="$g1" -v b="$g2" 'BEGIN {printf "granudrag 2-thread speed-up: %.2fx\n", a/b}'
awk -v a="$l1" -v b="$l2" 'BEGIN {printf "LAMMPS 2-rank speed-up:      %.2fx\n", a/b}'
echo "final KE per grain (translational rotational): granudrag $gke | LAMMPS $(final_ke "$out/lammps1.log")"
