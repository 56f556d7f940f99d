// Periodic tiling of a prepared sample: kx x ky x kz copies of a periodic
// packing side by side form a larger periodic packing of the same state
// (void ratio, contacts per particle, stress and fabric of the original up
// to round-off), because a periodic cell is, by construction, one tile of an
// infinite periodic packing. Used to build dense benchmark samples of 10^4 -
// 10^5+ particles from a shipped prepared sample (issue 13).
//
// Given the state S (cell H, fractional positions s_p, contact histories):
//   H' = H diag(kx, ky, kz)                (also h_reference; L unchanged)
//   copy c = (cx, cy, cz), 0 <= c_a < k_a, particle p:
//     s' = ((s_p,x + cx)/kx, (s_p,y + cy)/ky, (s_p,z + cz)/kz)
//     id' = id_p K + (cx + kx (cy + ky cz)),      K = kx ky kz
//   (velocities, spins, orientations, masses copied). Stored order: copy by
//   copy, each copy in the original order (compact blocks in space).
// A contact (a, b) of S joins a and the minimum image of b, which lies
// n = -round(s_b - s_a) cells away (per axis, n_a in {-1, 0, 1}); in the
// tiled sample a of copy c touches b of copy (c + n) mod k. The ids keep the
// order id_a < id_b (id' = id K + copy is monotonic in id), so the spring
// (the force on id_b) and the spheroid solver cache carry over unchanged.
// Time, step and energy bookkeeping: time and step are kept; the energy
// budget's extensive terms are multiplied by K.
#pragma once

#include <array>
#include <optional>
#include <string>

#include "virtual_triaxial/dem/simulation.h"

namespace vt::dem {

/// kx x ky x kz periodic copies of `s` (each factor >= 1; throws
/// std::invalid_argument otherwise, when the ids would overflow, or when the
/// copies hold more than the 2^31 - 1 particles the core indexes).
SimulationState tile_periodic(const SimulationState& s, int kx, int ky, int kz);

/// The largest factor a tiling argument takes.
constexpr int kTileFactorMax = 100;

/// The factors of a tiling argument, "K" (K x K x K) or "KxKyKz": whole
/// numbers written in digits only (no sign or space), each in
/// [1, kTileFactorMax]; nothing when the text is not of that form. The
/// tools' tiling flags: triax_bench --tile and --pair-tile, triax_import
/// --factors.
std::optional<std::array<int, 3>> parse_tile_factors(const std::string& text);

/// The message of a tiling flag that parse_tile_factors refused:
/// "FLAG needs K or KxKyKz, whole numbers in [1, kTileFactorMax]".
std::string tile_factors_usage(const std::string& flag);

}  // namespace vt::dem
