# Shared by the bench scripts that time two threads (source it after cd to
# the project root, with BIN set): where the host has placed the VM's two
# vCPUs, read as the round trip of a cache line between them
# (host_scaling --pingpong, session 35: about 95-145 ns near each other,
# 465-535 ns far apart, where two threads lose).
#   round_trip_setup NAME  sets HOST (env HOST, default host_scaling beside
#                          BIN) and RT_SLOW (env, default 250 ns; a number,
#                          else exit 2 naming it)
#   round_trip             prints the round trip now [ns]; prints nothing
#                          and fails when host_scaling is missing or fails
#   near_rt BEFORE AFTER   true when both readings are below RT_SLOW
#   far_rt BEFORE AFTER    true when both are at or above it
round_trip_setup() {
  HOST="${HOST:-$(dirname "${BIN}")/host_scaling}"
  RT_SLOW="${RT_SLOW:-250}"
  [[ "${RT_SLOW}" =~ ^[0-9]+([.][0-9]+)?$ ]] || { echo "$1: RT_SLOW must be a number of ns, not '${RT_SLOW}'" >&2; exit 2; }
}
round_trip() {
  [[ -x "${HOST}" ]] || return 1
  local out
  out="$("${HOST}" --pingpong --rounds 1)" || return 1
  awk '$2 == "pingpong" { print $3; found = 1 } END { exit !found }' <<<"${out}"
}
near_rt() { awk -v b="$1" -v a="$2" -v t="${RT_SLOW}" 'BEGIN { exit !(b < t && a < t) }'; }
far_rt() { awk -v b="$1" -v a="$2" -v t="${RT_SLOW}" 'BEGIN { exit !(b >= t && a >= t) }'; }
