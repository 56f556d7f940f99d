#include "virtual_triaxial/dem/periodic_tiling.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace vt::dem {

namespace {

Mat3 scale_columns(const Mat3& h, const int k[3]) {
  Mat3 r = h;
  for (int row = 0; row < 3; ++row)
    for (int c = 0; c < 3; ++c) r.m[row][c] *= static_cast<double>(k[c]);
  return r;
}

int wrap_index(int i, int k) { return ((i % k) + k) % k; }

}  // namespace

SimulationState tile_periodic(const SimulationState& s, int kx, int ky, int kz) {
  const int k[3] = {kx, ky, kz};
  for (int a = 0; a < 3; ++a)
    if (k[a] < 1) throw std::invalid_argument("tile: every factor must be >= 1 (got " + std::to_string(k[a]) + ")");
  const std::int64_t copies = static_cast<std::int64_t>(kx) * ky * kz;
  const Particles& p = s.particles;
  const std::size_t n = p.size();
  std::int64_t max_id = 0;
  for (std::int64_t id : p.id) {
    if (id < 0) throw std::invalid_argument("tile: particle ids must be >= 0");
    max_id = std::max(max_id, id);
  }
  if (max_id > (std::numeric_limits<std::int64_t>::max() - copies) / copies)
    throw std::invalid_argument("tile: particle ids too large for " + std::to_string(copies) + " copies");
  // storage indices are 32-bit (the neighbour list's partners and offsets)
  if (static_cast<double>(n) * static_cast<double>(copies) > static_cast<double>(std::numeric_limits<std::int32_t>::max()))
    throw std::invalid_argument("tile: " + std::to_string(n) + " particles x " + std::to_string(copies) +
                                " copies is more than the 2^31 - 1 particles the core indexes");

  SimulationState t = s;
  t.h = scale_columns(s.h, k);
  t.h_reference = scale_columns(s.h_reference, k);
  Particles& q = t.particles;
  q.resize(n * static_cast<std::size_t>(copies));
  std::size_t out = 0;
  for (int cz = 0; cz < kz; ++cz)
    for (int cy = 0; cy < ky; ++cy)
      for (int cx = 0; cx < kx; ++cx) {
        const std::int64_t copy = cx + static_cast<std::int64_t>(kx) * (cy + static_cast<std::int64_t>(ky) * cz);
        for (std::size_t i = 0; i < n; ++i, ++out) {
          q.id[out] = p.id[i] * copies + copy;
          q.shape[out] = p.shape[i];
          q.radius[out] = p.radius[i];
          q.semi_axes[out] = p.semi_axes[i];
          q.mass[out] = p.mass[i];
          q.inertia[out] = p.inertia[i];
          q.frac[out] = {(p.frac[i].x + cx) / kx, (p.frac[i].y + cy) / ky, (p.frac[i].z + cz) / kz};
          q.velocity[out] = p.velocity[i];
          q.omega[out] = p.omega[i];
          q.orientation[out] = p.orientation[i];
          q.material[out] = p.material[i];
        }
      }

  std::unordered_map<std::int64_t, std::size_t> index;
  index.reserve(n);
  for (std::size_t i = 0; i < n; ++i) index.emplace(p.id[i], i);
  t.contacts.clear();
  t.contacts.reserve(s.contacts.size() * static_cast<std::size_t>(copies));
  for (const ContactHistory& c : s.contacts) {
    const auto ia = index.find(c.id_a), ib = index.find(c.id_b);
    if (ia == index.end() || ib == index.end())
      throw std::invalid_argument("tile: contact (" + std::to_string(c.id_a) + ", " + std::to_string(c.id_b) +
                                  ") names a missing particle");
    const Vec3 ds = p.frac[ib->second] - p.frac[ia->second];
    const int shift[3] = {-static_cast<int>(std::nearbyint(ds.x)), -static_cast<int>(std::nearbyint(ds.y)),
                          -static_cast<int>(std::nearbyint(ds.z))};
    for (int cz = 0; cz < kz; ++cz)
      for (int cy = 0; cy < ky; ++cy)
        for (int cx = 0; cx < kx; ++cx) {
          const std::int64_t copy_a = cx + static_cast<std::int64_t>(kx) * (cy + static_cast<std::int64_t>(ky) * cz);
          const std::int64_t copy_b =
              wrap_index(cx + shift[0], kx) +
              static_cast<std::int64_t>(kx) *
                  (wrap_index(cy + shift[1], ky) + static_cast<std::int64_t>(ky) * wrap_index(cz + shift[2], kz));
          ContactHistory h = c;
          h.id_a = c.id_a * copies + copy_a;
          h.id_b = c.id_b * copies + copy_b;
          t.contacts.push_back(h);
        }
  }

  const double kk = static_cast<double>(copies);
  EnergyBudget& e = t.energy;
  e.boundary_work *= kk;
  e.damping *= kk;
  e.friction *= kk;
  e.kinetic_translational *= kk;
  e.kinetic_rotational *= kk;
  e.elastic *= kk;
  e.kinetic_reference *= kk;
  e.elastic_reference *= kk;
  return t;
}

std::optional<std::array<int, 3>> parse_tile_factors(const std::string& text) {
  // "K" or three whole numbers joined by 'x': digits only (no sign, space or
  // other character), each in [1, kTileFactorMax]
  std::array<int, 3> k{0, 0, 0};
  std::size_t parts = 0, begin = 0;
  while (true) {
    const std::size_t end = std::min(text.find('x', begin), text.size());
    if (parts == 3 || end == begin) return std::nullopt;
    int value = 0;
    for (std::size_t c = begin; c < end; ++c) {
      if (text[c] < '0' || text[c] > '9') return std::nullopt;
      value = 10 * value + (text[c] - '0');
      if (value > kTileFactorMax) return std::nullopt;  // also keeps long numbers from wrapping
    }
    if (value < 1) return std::nullopt;
    k[parts++] = value;
    if (end == text.size()) break;
    begin = end + 1;
  }
  if (parts == 1) k[1] = k[2] = k[0];
  else if (parts != 3) return std::nullopt;
  return k;
}

std::string tile_factors_usage(const std::string& flag) {
  return flag + " needs K or KxKyKz, whole numbers in [1, " + std::to_string(kTileFactorMax) + "]";
}

}  // namespace vt::dem
