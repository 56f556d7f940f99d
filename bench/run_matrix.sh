#!/usr/bin/env bash
# Run triax_bench for N in {1000, 10000, 100000} x T in {1, 2} and print a
# table (best of REPEATS timings per case; the sample of each N is prepared
# once and cached in CACHE_DIR).
#
#   bench/run_matrix.sh [extra triax_bench args...]
#   REPEATS=3 SIZES="1000 10000 100000" THREADS="1 2" CACHE_DIR=/tmp/vt_bench_cache \
#     bench/run_matrix.sh --no-sort
#
# Timings on a shared machine are only meaningful when nothing else runs: two
# OpenMP threads on two cores with a third busy process make every barrier
# wait for a descheduled thread (factors of 5-50 slower). Before each timing
# the script waits (up to IDLE_WAIT seconds) until the CPUs are >= 90 % idle
# over one second, and reports the idle fraction it saw.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

BIN="${BIN:-build/devel/lib/virtual_triaxial/triax_bench}"
REPEATS="${REPEATS:-3}"
SIZES="${SIZES:-1000 10000 100000}"
THREADS="${THREADS:-1 2}"
CACHE_DIR="${CACHE_DIR:-/tmp/vt_bench_cache}"
IDLE_WAIT="${IDLE_WAIT:-600}"
mkdir -p "${CACHE_DIR}"

[[ -x "${BIN}" ]] || { echo "run_matrix: ${BIN} not built (vt_ensure_built all)" >&2; exit 1; }

# Idle fraction of all CPUs over one second, from /proc/stat.
idle_fraction() {
  local a b
  read -r -a a < <(grep '^cpu ' /proc/stat)
  sleep 1
  read -r -a b < <(grep '^cpu ' /proc/stat)
  local tot=0 i
  for i in 1 2 3 4 5 6 7 8; do tot=$((tot + b[i] - a[i])); done
  local idle=$((b[4] - a[4] + b[5] - a[5]))
  awk -v i="${idle}" -v t="${tot}" 'BEGIN { printf "%.2f", (t > 0 ? i / t : 1) }'
}

wait_idle() {
  local waited=0 f
  while :; do
    f="$(idle_fraction)"
    if awk -v f="${f}" 'BEGIN { exit !(f >= 0.90) }' || ((waited >= IDLE_WAIT)); then
      echo "${f}"
      return
    fi
    sleep 4
    waited=$((waited + 5))
  done
}

value() { awk -F': ' -v k="$1" '$1 == k { print $2 }' "$2"; }

printf '%-8s %-3s %-10s %-9s %-9s %-9s %-8s %-9s %-9s %-6s %s\n' \
  N T us/p-step best_of bytes/p peak_MB pairs/p contacts/p prep_s idle fingerprint
for n in ${SIZES}; do
  # Prepare (or load) the sample once, untimed.
  "${BIN}" --particles "${n}" --threads 1 --steps 1 --cache "${CACHE_DIR}" "$@" >/dev/null 2>"${CACHE_DIR}/prep_${n}.log" || {
    echo "run_matrix: preparation of N=${n} failed, see ${CACHE_DIR}/prep_${n}.log" >&2; exit 1; }
  prep="$("${BIN}" --particles "${n}" --threads 1 --steps 1 --cache "${CACHE_DIR}" "$@" 2>/dev/null |
          awk -F': ' '$1 == "preparation_seconds" { split($2, a, " "); print a[1] }')"
  for t in ${THREADS}; do
    best="" out_best=""
    idle_seen=""
    for ((r = 0; r < REPEATS; ++r)); do
      idle_seen="$(wait_idle)"
      out="$(mktemp)"
      "${BIN}" --particles "${n}" --threads "${t}" --cache "${CACHE_DIR}" "$@" >"${out}" 2>/dev/null
      us="$(value us_per_particle_step "${out}")"
      if [[ -z "${best}" ]] || awk -v a="${us}" -v b="${best}" 'BEGIN { exit !(a < b) }'; then
        best="${us}"
        [[ -n "${out_best}" ]] && rm -f "${out_best}"
        out_best="${out}"
      else
        rm -f "${out}"
      fi
    done
    printf '%-8s %-3s %-10s %-9s %-9s %-9s %-8s %-9s %-9s %-6s %s\n' "${n}" "${t}" "${best}" "${REPEATS}" \
      "$(value rss_bytes_per_particle "${out_best}")" "$(value peak_rss_mb "${out_best}")" \
      "$(value neighbour_pairs_per_particle "${out_best}")" "$(value contacts_per_particle "${out_best}")" \
      "${prep}" "${idle_seen}" "$(value state_fingerprint "${out_best}")"
    rm -f "${out_best}"
  done
done
