#!/usr/bin/env bash
# Two threads against one, beside what this host gives two threads of any
# program (bench/host_scaling.cpp), in the same interleaved rounds: each
# round runs host_scaling once (its seven kernels, of which this prints
# compute, fma, sync, cache and memory: S = (t_solo0 + t_solo1) / max(t_0, t_1)),
# then triax_bench on one thread and on two on the tiled sample, the
# two-thread run between two readings of the round trip of a cache line
# between the two CPUs (host_scaling --pingpong: rt_ns, before/after).
# Prints per round the host's S of each kernel, the steal share, rt_ns,
# ours (one-thread / two-thread cost) and ours / S_sync, then the medians,
# and the median of ours over the rounds whose two round trips were both
# below RT_SLOW ns (default 250) and over those with both at or above it
# (bench/round_trip.sh). S_sync is the ceiling of a program that, like the
# DEM step, meets at a barrier every 300 us and loads neither cache nor memory; ours
# falls further below it by what the step adds (barriers' own cost, the
# completions of sums, shared cache and memory traffic). rt_ns near 120
# or near 500 says in which of the host's two kinds of window the round
# ran (session 35: ours drops in the second; the phase may change within
# a round, so rounds whose two readings disagree are left out of both).
#
#   bench/two_thread_ceiling.sh ROUNDS TILE STEPS [SAMPLE]
#   bench/two_thread_ceiling.sh 10 3x2x2 2000          # 12 000 dense spheres
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
# shellcheck source=tile_rounds.sh
source bench/tile_rounds.sh
tile_rounds two_thread_ceiling "$@"
# shellcheck source=median.sh
source bench/median.sh
# shellcheck source=round_trip.sh
source bench/round_trip.sh
round_trip_setup two_thread_ceiling
[[ -x "${HOST}" ]] || { echo "two_thread_ceiling: ${HOST} not built" >&2; exit 2; }
cost() {
  "${BIN}" --sample "${SAMPLE}" --tile "${TILE}" --sort-sample --threads "$1" --steps "${STEPS}" 2>/dev/null |
    awk '/^us_per_particle_step:/ { print $2 }'
}
echo "# $(date -u '+%F %H:%M UTC'), ${SAMPLE} tiled ${TILE}, slab-sorted, ${STEPS} steps, ${R} rounds, load average $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-6s %9s %9s %9s %9s %9s %7s %11s %9s %9s %7s %9s\n' round S_compute S_fma S_sync S_cache S_memory steal% rt_ns one_us two_us ours ours/S_s
sc=(); sf=(); sy=(); sa=(); sm=(); ou=(); rel=(); near=(); far=()
for ((r = 1; r <= R; ++r)); do
  host="$("${HOST}" --rounds 1 --seconds 0.1)"
  s_of() { awk -v k="$1" '$2 == k { print $(NF - 1) }' <<<"${host}"; }
  # the kernels' steal shares (-1: unreadable, left out; not the pingpong line)
  steal="$(awk '$1 ~ /^[0-9]+$/ && $2 != "pingpong" && $NF >= 0 { s += $NF; n++ } END { if (n) printf "%.2f", s / n; else print "-" }' <<<"${host}")"
  c="$(s_of compute)"; f="$(s_of fma)"; y="$(s_of sync)"; a="$(s_of cache)"; m="$(s_of memory)"
  one="$(cost 1)"; rb="$(round_trip || true)"; two="$(cost 2)"; ra="$(round_trip || true)"
  [[ -n "${one}" && -n "${two}" && -n "${y}" && -n "${f}" && -n "${rb}" && -n "${ra}" ]] ||
    { echo "two_thread_ceiling: a run failed" >&2; exit 1; }
  ours="$(awk -v a="${one}" -v b="${two}" 'BEGIN { printf "%.3f", a / b }')"
  ratio="$(awk -v o="${ours}" -v s="${y}" 'BEGIN { printf "%.3f", o / s }')"
  printf '%-6s %9s %9s %9s %9s %9s %7s %11s %9s %9s %7s %9s\n' "${r}" "${c}" "${f}" "${y}" "${a}" "${m}" "${steal}" \
    "${rb%.*}/${ra%.*}" "${one}" "${two}" "${ours}" "${ratio}"
  sc+=("${c}"); sf+=("${f}"); sy+=("${y}"); sa+=("${a}"); sm+=("${m}"); ou+=("${ours}"); rel+=("${ratio}")
  if near_rt "${rb}" "${ra}"; then near+=("${ours}"); elif far_rt "${rb}" "${ra}"; then far+=("${ours}"); fi
done
printf '%-6s %9s %9s %9s %9s %9s %7s %11s %9s %9s %7s %9s\n' median "$(median_of "${sc[@]}")" "$(median_of "${sf[@]}")" \
  "$(median_of "${sy[@]}")" "$(median_of "${sa[@]}")" "$(median_of "${sm[@]}")" "" "" "" "" \
  "$(median_of "${ou[@]}")" "$(median_of "${rel[@]}")"
echo "ours, round trips both below ${RT_SLOW} ns: median $(median_of "${near[@]}") (${#near[@]} rounds)"
echo "ours, round trips both at or above ${RT_SLOW} ns: median $(median_of "${far[@]}") (${#far[@]} rounds)"
