#include "virtual_triaxial/dem/spatial_sort.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "virtual_triaxial/dem/chunked.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/dem/thread_governor.h"

namespace vt::dem {

namespace {

template <class T>
void permute_vector(std::vector<T>& v, const std::vector<std::int32_t>& order) {
  if (v.size() != order.size()) throw std::invalid_argument("permute: particle arrays differ in length");
  std::vector<T> out;
  out.reserve(v.size());
  for (std::int32_t k : order) out.push_back(v[static_cast<std::size_t>(k)]);
  v.swap(out);
}

}  // namespace

SortGrid sort_grid(const Particles& p, const PeriodicCell& cell) {
  SortGrid g;
  const double width = 2.0 * p.max_bounding_radius();
  const Vec3 h = cell.heights();
  for (int a = 0; a < 3; ++a) {
    const double k = width > 0.0 ? std::floor(h[a] / width) : 1.0;
    g.bins[a] = static_cast<int>(std::min(std::max(k, 1.0), 2097152.0));
  }
  // the most bins first; equal counts keep s_3, s_2, s_1
  std::stable_sort(g.axes, g.axes + 3, [&g](int x, int y) { return g.bins[x] > g.bins[y]; });
  return g;
}

std::array<int, 3> SortGrid::bins_of(const Vec3& s) const {
  const Vec3 w = PeriodicCell::wrap(s);
  std::array<int, 3> b{};
  for (int a = 0; a < 3; ++a) b[static_cast<std::size_t>(a)] = std::min(bins[a] - 1, std::max(0, static_cast<int>(w[a] * bins[a])));
  return b;
}

std::vector<std::int32_t> spatial_order(const Particles& p, const PeriodicCell& cell) {
  const std::size_t n = p.size();
  const SortGrid g = sort_grid(p, cell);
  const int a0 = g.axes[0], a1 = g.axes[1], a2 = g.axes[2];
  std::vector<std::pair<std::uint64_t, std::int32_t>> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::array<int, 3> bi = g.bins_of(p.frac[i]);
    const auto b = [&bi](int axis) { return static_cast<std::uint64_t>(bi[static_cast<std::size_t>(axis)]); };
    // (b_slab nb_mid + b_mid) nb_fast + b_fast (< 2^63)
    const std::uint64_t k = (b(a0) * static_cast<std::uint64_t>(g.bins[a1]) + b(a1)) *
                                static_cast<std::uint64_t>(g.bins[a2]) + b(a2);
    key[i] = {k, static_cast<std::int32_t>(i)};
  }
  std::sort(key.begin(), key.end());  // ties broken by old index: stable
  std::vector<std::int32_t> order(n);
  for (std::size_t k = 0; k < n; ++k) order[k] = key[k].second;
  return order;
}

void permute(Particles& p, const std::vector<std::int32_t>& order) {
  std::vector<char> seen(order.size(), 0);
  for (std::int32_t k : order) {
    if (k < 0 || static_cast<std::size_t>(k) >= order.size() || seen[static_cast<std::size_t>(k)])
      throw std::invalid_argument("permute: order is not a permutation of the particle indices");
    seen[static_cast<std::size_t>(k)] = 1;
  }
  permute_vector(p.id, order);
  permute_vector(p.shape, order);
  permute_vector(p.radius, order);
  permute_vector(p.semi_axes, order);
  permute_vector(p.mass, order);
  permute_vector(p.inertia, order);
  permute_vector(p.frac, order);
  permute_vector(p.velocity, order);
  permute_vector(p.omega, order);
  permute_vector(p.orientation, order);
  permute_vector(p.material, order);
}

void spatial_sort(Particles& p, const PeriodicCell& cell) { permute(p, spatial_order(p, cell)); }

void spatial_sort(SimulationState& s) { spatial_sort(s.particles, PeriodicCell(s.h, s.h_reference)); }

// the first size that two threads take (2 chunks of 512 each)
static_assert(kSortFromParticles == (2 * ThreadGovernor::kMinChunksPerThread - 1) * kChunkSize);

bool sorts_new_specimen(std::size_t n) { return n > kSortFromParticles; }

void order_new_specimen(Particles& p, const PeriodicCell& cell) {
  if (sorts_new_specimen(p.size())) spatial_sort(p, cell);
}

void order_new_specimen(SimulationState& s) {
  if (sorts_new_specimen(s.particles.size())) spatial_sort(s);
}

}  // namespace vt::dem
