#!/usr/bin/env bash
# Time triax_bench on dense prepared samples: the shipped samples tiled
# periodically (dem/periodic_tiling.h) to N = 1000 x tile, for every tile x
# thread count x shape, in interleaved rounds (round r runs every case once,
# so a drift of the host's speed hits all cases alike), and print the
# MEDIAN cost per particle-step of each case with the packing state beside it
# (void ratio and contacts per particle at the start of the timing, mean
# stress at its start and end: the timing shears at constant volume) and, per round, the
# ratios 1 thread / T threads (x_1T), spheroid / sphere (x_sph) and this N /
# the first N of the list at the same threads and shape (x_N1, the issue's
# "flat within 20 %"): medians of the rounds' ratios. Every round runs every
# size, so all three are interleaved.
#
#   bench/run_matrix.sh [extra triax_bench args...]
#   REPEATS=5 TILES="1 2 3x2x2 4 5x5x4" THREADS="1 2" SHAPES="sphere spheroid" STEPS=1000 bench/run_matrix.sh
#   LOOSE=1 SIZES="1000 10000 100000" bench/run_matrix.sh   # the bench's own loose packing (the old extra)
#
# Samples: SPHERE_SAMPLE (default config/samples/dense_1000.h5: e 0.61, 5.3
# contacts per particle, 100 kPa) and SPHEROID_SAMPLE (default
# config/samples/dense_1000_spheroid.h5, aspect 1.2). Tiles: K (K x K x K) or
# KxKyKz; 3x2x2 = 12 000 and 5x5x4 = 100 000 particles.
# SORT=1 (default) stores the tiled sample in slab order first
# (triax_bench --sort-sample, spatial_sort.h), for every tile, thread count
# and shape alike, as LAMMPS does by default (atom_modify sort; our runs sort
# new specimens above 1536 particles, dem::order_new_specimen): the tiles come
# one after another, so two threads' runs would otherwise meet across a
# tile cut in storage order, not in space (at 12 000 spheres 4568 pairs
# cross the runs unsorted, 2600-3200 in the Morton order used up to session
# 23; slab order leaves 560 edge particles and 497 tails). SORT=0: as stored.
# The header line "vCPU speeds" times one thread pinned to each CPU (taskset,
# the first tile, 300 steps) before and after the matrix: on a VM the two
# vCPUs can differ by 30 % or more, which bounds what two threads can gain
# over one (a one-thread case runs on whichever the kernel picks).
# Before each timing the script waits up to IDLE_WAIT seconds (default 0)
# for the CPUs to be >= 90 % idle over one second, and prints the idle
# fraction it saw and the load average: on a shared machine, quote the load.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

BIN="${BIN:-build/devel/lib/virtual_triaxial/triax_bench}"
REPEATS="${REPEATS:-5}"
TILES="${TILES:-1 2 3x2x2 4 5x5x4}"
SIZES="${SIZES:-1000 10000 100000}"
THREADS="${THREADS:-1 2}"
SHAPES="${SHAPES:-sphere}"
LOOSE="${LOOSE:-0}"
CACHE_DIR="${CACHE_DIR:-/tmp/vt_bench_cache}"
IDLE_WAIT="${IDLE_WAIT:-0}"
SPHERE_SAMPLE="${SPHERE_SAMPLE:-config/samples/dense_1000.h5}"
SPHEROID_SAMPLE="${SPHEROID_SAMPLE:-config/samples/dense_1000_spheroid.h5}"
ASPECT="${ASPECT:-1.2}"
# The same number of steps for every N (the timing shears at constant
# volume: at the default 1000 steps 0.3 % strain, so every N times the same
# packing state; triax_bench's own default, 3e7/N steps, shears the small
# samples much further).
STEPS="${STEPS:-1000}"
# COST=median_step: each run's median step / N (triax_bench's
# us_per_particle_step_median_step: the cost outside the spells where the
# host runs two threads one after the other) instead of its mean. The
# column "slow" (either COST) sums the runs' slow_windows (200-step windows
# whose median step exceeds 1.5x the run's). RAW_DIR=DIR (relative to the
# project root) keeps every run's output.
COST="${COST:-mean}"
case "${COST}" in
  mean) COST=us_per_particle_step ;;
  median_step) COST=us_per_particle_step_median_step ;;
  *) echo "run_matrix: COST must be mean or median_step, not '${COST}'" >&2; exit 2 ;;
esac
SORT="${SORT:-1}"

[[ -x "${BIN}" ]] || { echo "run_matrix: ${BIN} not built (vt_ensure_built all)" >&2; exit 1; }
[[ "${REPEATS}" =~ ^[1-9][0-9]*$ ]] || { echo "run_matrix: REPEATS must be a whole number >= 1" >&2; exit 2; }

idle_fraction() {  # of all CPUs over one second, from /proc/stat
  local a b tot=0 i
  read -r -a a < <(grep '^cpu ' /proc/stat); sleep 1; read -r -a b < <(grep '^cpu ' /proc/stat)
  for i in 1 2 3 4 5 6 7 8; do tot=$((tot + b[i] - a[i])); done
  awk -v i="$((b[4] - a[4] + b[5] - a[5]))" -v t="${tot}" 'BEGIN { printf "%.2f", (t > 0 ? i / t : 1) }'
}
wait_idle() {
  local waited=0 f
  while :; do
    f="$(idle_fraction)"
    if awk -v f="${f}" 'BEGIN { exit !(f >= 0.90) }' || ((waited >= IDLE_WAIT)); then echo "${f}"; return; fi
    sleep 4; waited=$((waited + 5))
  done
}
value() { awk -F': ' -v k="$1" '$1 == k { print $2 }' "$2"; }
# shellcheck source=median.sh
source bench/median.sh

# case_args SHAPE SIZE -> args (triax_bench arguments of one case)
case_args() {
  if [[ "${LOOSE}" == 1 ]]; then
    args=(--particles "$2" --cache "${CACHE_DIR}")
    [[ "$1" == spheroid ]] && args+=(--shape spheroid --aspect "${ASPECT}")
  else
    case "$1" in
      sphere) args=(--sample "${SPHERE_SAMPLE}" --tile "$2") ;;
      spheroid) args=(--sample "${SPHEROID_SAMPLE}" --tile "$2") ;;
      *) echo "run_matrix: unknown shape '$1' (sphere or spheroid)" >&2; exit 2 ;;
    esac
    [[ "${SORT}" == 1 ]] && args+=(--sort-sample)
  fi
}

[[ "${SORT}" == 0 || "${SORT}" == 1 ]] || { echo "run_matrix: SORT must be 0 or 1" >&2; exit 2; }
# vcpu_speeds: one thread pinned to each CPU, us per particle-step
vcpu_speeds() {
  [[ "${LOOSE}" == 1 ]] && { echo "(not measured with LOOSE=1)"; return; }
  command -v taskset >/dev/null || { echo "(taskset missing)"; return; }
  local c out=""
  case_args sphere "$(echo ${list} | cut -d' ' -f1)"
  for ((c = 0; c < $(nproc); ++c)); do
    out+="cpu${c} $(taskset -c "${c}" "${BIN}" "${args[@]}" --threads 1 --steps 300 2>/dev/null | awk -F': ' '$1 == "us_per_particle_step" { print $2 }') "
  done
  echo "${out% }"
}

list="${TILES}"; [[ "${LOOSE}" == 1 ]] && { list="${SIZES}"; mkdir -p "${CACHE_DIR}"; }
work="$(mktemp -d)"; trap 'rm -rf "${work}"' EXIT
# RAW_DIR: keep every run's triax_bench output there (SIZE_T_SHAPE_ROUND)
if [[ -n "${RAW_DIR:-}" ]]; then mkdir -p "${RAW_DIR}"; trap 'cp "${work}"/* "${RAW_DIR}"/ 2>/dev/null || true; rm -rf "${work}"' EXIT; fi
echo "# $(date -u '+%F %H:%M UTC'), $(nproc) CPUs, load average at start: $(cut -d' ' -f1-3 /proc/loadavg), REPEATS=${REPEATS}, $([[ ${LOOSE} == 1 ]] && echo 'LOOSE bench packing (extra)' || echo "dense prepared samples, tiled, $([[ ${SORT} == 1 ]] && echo 'slab-sorted' || echo 'as stored')")"
echo "# vCPU speeds before (one thread pinned, us per particle-step): $(vcpu_speeds)"

echo "# cost per particle-step: ${COST}"
printf '%-8s %-7s %-3s %-9s %-9s %-9s %-9s %-8s %-9s %-9s %-9s %-8s %-7s %-7s %-10s %s\n' \
  size N T shape us_median us_min us_max e contacts/p p_kPa bytes/p x_1T x_sph x_N1 idle/load slow
if [[ "${LOOSE}" == 1 ]]; then  # prepare (or load) once, untimed
  for s in ${list}; do
    for shape in ${SHAPES}; do case_args "${shape}" "${s}"; "${BIN}" "${args[@]}" --threads 1 --steps 1 "$@" >/dev/null 2>&1; done
  done
fi
# Round r runs every size, thread count and shape once, so the ratios
# between sizes (x_N1) are interleaved as well as those within one size.
for ((r = 0; r < REPEATS; ++r)); do
  for s in ${list}; do
    for t in ${THREADS}; do
      for shape in ${SHAPES}; do
        case_args "${shape}" "${s}"
        idle="$(wait_idle)/$(cut -d' ' -f1 /proc/loadavg)"
        out="${work}/${s}_${t}_${shape}_${r}"
        "${BIN}" "${args[@]}" --threads "${t}" --steps "${STEPS}" "$@" >"${out}" 2>/dev/null || { echo "run_matrix: triax_bench ${args[*]} failed" >&2; exit 1; }
        echo "${idle}" >"${out}.idle"
      done
    done
  done
done
us() { for ((r = 0; r < REPEATS; ++r)); do value "${COST}" "${work}/$1_$2_$3_${r}"; done; }
ratio() {  # SIZE_A T_A SHAPE_A SIZE_B T_B SHAPE_B: median over rounds of (case a) / (case b)
  for ((r = 0; r < REPEATS; ++r)); do
    awk -v a="$(value "${COST}" "${work}/$1_$2_$3_${r}")" \
        -v b="$(value "${COST}" "${work}/$4_$5_$6_${r}")" 'BEGIN { printf "%.4f\n", a / b }'
  done | median
}
slow() {  # SIZE T SHAPE: the rounds' slow windows summed, "slow/windows"
  for ((r = 0; r < REPEATS; ++r)); do value slow_windows "${work}/$1_$2_$3_${r}"; done |
    awk '{ s += $1; w += $3 } END { printf "%d/%d", s, w }'
}
first="$(echo ${THREADS} | cut -d' ' -f1)"
first_size="$(echo ${list} | cut -d' ' -f1)"
for s in ${list}; do
  for t in ${THREADS}; do
    for shape in ${SHAPES}; do
      f="${work}/${s}_${t}_${shape}_0"
      x1="-"; [[ "${t}" != "${first}" ]] && x1="$(ratio "${s}" "${first}" "${shape}" "${s}" "${t}" "${shape}")"
      xs="-"; [[ "${shape}" != sphere && " ${SHAPES} " == *" sphere "* ]] && xs="$(ratio "${s}" "${t}" "${shape}" "${s}" "${t}" sphere)"
      xn="-"; [[ "${s}" != "${first_size}" ]] && xn="$(ratio "${s}" "${t}" "${shape}" "${first_size}" "${t}" "${shape}")"
      printf '%-8s %-7s %-3s %-9s %-9s %-9s %-9s %-8s %-9s %-9s %-9s %-8s %-7s %-7s %-10s %s\n' \
        "${s}" "$(value particles "${f}")" "${t}" "${shape}" "$(us "${s}" "${t}" "${shape}" | median)" \
        "$(us "${s}" "${t}" "${shape}" | sort -g | head -1)" "$(us "${s}" "${t}" "${shape}" | sort -g | tail -1)" \
        "$(value void_ratio_start "${f}")" "$(value contacts_per_particle_start "${f}")" \
        "$(awk -v p="$(value mean_stress_pa_start "${f}")" -v q="$(value mean_stress_pa "${f}")" 'BEGIN { printf "%.0f-%.0f", p / 1e3, q / 1e3 }')" \
        "$(value rss_bytes_per_particle "${f}")" "${x1}" "${xs}" "${xn}" "$(cat "${f}.idle")" \
        "$(slow "${s}" "${t}" "${shape}")"
    done
  done
done
echo "# vCPU speeds after: $(vcpu_speeds)"
