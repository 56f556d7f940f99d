#!/bin/bash
# A/B of two whole builds' thread governor (triax_run --threads auto) on the
# drained shear of dense_4000.h5 with the time step from the contacts (the
# LAMMPS side by side's "ours contacts" scene), order alternating by round,
# the cache-line round trip read before and after each round.
#   governor_ab.sh ROUNDS DIR_A DIR_B SCENE.yaml > rows
# row: round time rt_before rt_after wall_A one_A wall_B one_B
R=$1; A=$2; B=$3; SCENE=$4
H=/work/main/build/devel/lib/virtual_triaxial/host_scaling
run() {  # DIR -> "wall steps_on_one"
  local e
  e=$(LD_LIBRARY_PATH=$1 "$1/triax_run" "${SCENE}" --out /tmp/s37/ab_x.h5 --quiet 2>&1)
  echo "$(grep -o '"wall_seconds":[0-9.]*' <<<"$e" | cut -d: -f2) $(sed -n 's/.*run time: \([0-9]*\) steps on 1.*/\1/p' <<<"$e")"
}
for i in $(seq 1 "$R"); do
  a=$($H --pingpong --rounds 1 | awk '/median_round_trip_ns/{print $2}')
  if ((i % 2)); then ra=$(run "$A"); rb=$(run "$B"); else rb=$(run "$B"); ra=$(run "$A"); fi
  b=$($H --pingpong --rounds 1 | awk '/median_round_trip_ns/{print $2}')
  echo "$i $(date +%H:%M:%S) $a $b $ra $rb"
  sleep 1
done
