# Shared by the bench scripts called as `NAME ROUNDS TILE STEPS [SAMPLE]`
# (source it after cd to the project root): tile_rounds NAME "$@" sets R,
# TILE, STEPS, SAMPLE (default config/samples/dense_1000.h5) and BIN (env
# BIN, default the built triax_bench), or prints the script's usage (its
# header comment) or the argument at fault and exits 2.
# usage_from_header: prints the calling script's header comment (its usage)
# on stderr and exits 2.
usage_from_header() { awk 'NR > 1 && /^#/ { print; next } NR > 1 { exit }' "$0" >&2; exit 2; }
tile_rounds() {
  local name=$1; shift
  (($# >= 3)) || usage_from_header
  R=$1; TILE=$2; STEPS=$3; SAMPLE=${4:-config/samples/dense_1000.h5}
  BIN="${BIN:-build/devel/lib/virtual_triaxial/triax_bench}"
  [[ "${R}" =~ ^[1-9][0-9]*$ ]] || { echo "${name}: ROUNDS must be a whole number >= 1, not '${R}'" >&2; exit 2; }
  [[ "${STEPS}" =~ ^[1-9][0-9]*$ ]] || { echo "${name}: STEPS must be a whole number >= 1, not '${STEPS}'" >&2; exit 2; }
  [[ -x "${BIN}" ]] || { echo "${name}: ${BIN} not built" >&2; exit 2; }
}
