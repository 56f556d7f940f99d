#!/usr/bin/env bash
# Run triax_bench for N in {1000, 10000, 100000} x T in {1, 2} and print a
# table (best of REPEATS timings per case; the sample of each N is prepared
# once and cached in CACHE_DIR).
#
#   bench/run_matrix.sh [extra triax_bench args...]
#   REPEATS=3 SIZES="1000 10000 100000" THREADS="1 2" CACHE_DIR=/tmp/vt_bench_cache \
#     bench/run_matrix.sh --no-sort
#   SHAPES="sphere spheroid" ASPECT=1.2 SIZES=10000 bench/run_matrix.sh
#
# SHAPES (default "sphere") lists the particle shapes to time; "spheroid"
# adds `--shape spheroid --aspect ASPECT`. The repeats of the shapes are
# interleaved (sphere, spheroid, sphere, ...), so a drift of the host's
# speed hits both alike, and each spheroid row gives its cost over the
# sphere row's in the column x_sphere (issue 5: at most 2.5 at N = 10^4).
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
SHAPES="${SHAPES:-sphere}"
ASPECT="${ASPECT:-1.2}"
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

# args = triax_bench arguments of shape $1, then the script's own.
set_args() {
  case "$1" in
    sphere) args=() ;;
    spheroid) args=(--shape spheroid --aspect "${ASPECT}") ;;
    *) echo "run_matrix: unknown shape '$1' in SHAPES (sphere or spheroid)" >&2; exit 2 ;;
  esac
}
seen=" "
for shape in ${SHAPES}; do
  set_args "${shape}"
  [[ "${seen}" != *" ${shape} "* ]] || { echo "run_matrix: shape '${shape}' twice in SHAPES" >&2; exit 2; }
  seen+="${shape} "
done
[[ "${REPEATS}" =~ ^[1-9][0-9]*$ ]] || { echo "run_matrix: REPEATS must be a whole number >= 1" >&2; exit 2; }

row() { printf '%-8s %-3s %-9s %-10s %-9s %-9s %-9s %-8s %-9s %-9s %-6s %-9s %s\n' "$@"; }
row N T shape us/p-step best_of bytes/p peak_MB pairs/p contacts/p prep_s idle x_sphere fingerprint
for n in ${SIZES}; do
  declare -A prep=()
  for shape in ${SHAPES}; do
    set_args "${shape}"
    args+=("$@")
    # Prepare (or load) the sample once, untimed.
    "${BIN}" --particles "${n}" --threads 1 --steps 1 --cache "${CACHE_DIR}" "${args[@]}" >/dev/null \
      2>"${CACHE_DIR}/prep_${n}_${shape}.log" || {
      echo "run_matrix: preparation of N=${n} (${shape}) failed, see ${CACHE_DIR}/prep_${n}_${shape}.log" >&2; exit 1; }
    prep[${shape}]="$("${BIN}" --particles "${n}" --threads 1 --steps 1 --cache "${CACHE_DIR}" "${args[@]}" 2>/dev/null |
                      awk -F': ' '$1 == "preparation_seconds" { split($2, a, " "); print a[1] }')"
  done
  for t in ${THREADS}; do
    declare -A best=() out_best=() idle_seen=()
    for ((r = 0; r < REPEATS; ++r)); do
      for shape in ${SHAPES}; do
        set_args "${shape}"
        args+=("$@")
        idle_seen[${shape}]="$(wait_idle)"
        out="$(mktemp)"
        "${BIN}" --particles "${n}" --threads "${t}" --cache "${CACHE_DIR}" "${args[@]}" >"${out}" 2>/dev/null
        us="$(value us_per_particle_step "${out}")"
        if [[ -z "${best[${shape}]:-}" ]] || awk -v a="${us}" -v b="${best[${shape}]}" 'BEGIN { exit !(a < b) }'; then
          best[${shape}]="${us}"
          [[ -n "${out_best[${shape}]:-}" ]] && rm -f "${out_best[${shape}]}"
          out_best[${shape}]="${out}"
        else
          rm -f "${out}"
        fi
      done
    done
    for shape in ${SHAPES}; do
      ratio="-"
      if [[ "${shape}" != sphere && -n "${best[sphere]:-}" ]]; then
        ratio="$(awk -v a="${best[${shape}]}" -v b="${best[sphere]}" 'BEGIN { printf "%.2f", a / b }')"
      fi
      f="${out_best[${shape}]}"
      row "${n}" "${t}" "${shape}" "${best[${shape}]}" "${REPEATS}" \
        "$(value rss_bytes_per_particle "${f}")" "$(value peak_rss_mb "${f}")" \
        "$(value neighbour_pairs_per_particle "${f}")" "$(value contacts_per_particle "${f}")" \
        "${prep[${shape}]}" "${idle_seen[${shape}]}" "${ratio}" "$(value state_fingerprint "${f}")"
      rm -f "${f}"
    done
    unset best out_best idle_seen
  done
  unset prep
done
