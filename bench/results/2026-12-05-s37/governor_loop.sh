#!/bin/bash
# repeated auto runs of the contacts shear of dense_4000 with governor logs and round trips
cd /tmp/s37/lmp4000
B=/work/main/build/devel/lib/virtual_triaxial
for i in $(seq 1 ${1:-150}); do
  a=$($B/host_scaling --pingpong --rounds 1 | awk '/median_round_trip_ns/{print $2}')
  w=$($B/triax_run ours_contacts.yaml --out /tmp/s37/govlogs/x.h5 --governor-log /tmp/s37/govlogs/g$i.csv --quiet 2>&1 | grep -o '"wall_seconds":[0-9.]*' | cut -d: -f2)
  b=$($B/host_scaling --pingpong --rounds 1 | awk '/median_round_trip_ns/{print $2}')
  one=$(awk -F, 'NR>1 && $2==1 {s+=$4+$5} END{print s+0}' /tmp/s37/govlogs/g$i.csv)
  echo "$i $(date +%H:%M:%S) rt $a $b wall $w one $one"
  sleep ${2:-4}
done
