#include "virtual_triaxial/dem/cloud_generator.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include "virtual_triaxial/dem/random_stream.h"

namespace vt::dem {

namespace {

/// Bin grid over [0,1)^3 fractional space for overlap queries.
class PlacementGrid {
 public:
  PlacementGrid(const Vec3& box, double cutoff) {
    for (int a = 0; a < 3; ++a) n_[a] = std::max(1, static_cast<int>(std::floor(box[a] / cutoff)));
    bins_.resize(static_cast<std::size_t>(n_[0]) * n_[1] * n_[2]);
  }
  std::size_t bin_of(const Vec3& s) const {
    int b[3];
    for (int a = 0; a < 3; ++a) b[a] = std::min(n_[a] - 1, static_cast<int>(s[a] * n_[a]));
    return (static_cast<std::size_t>(b[2]) * n_[1] + b[1]) * n_[0] + b[0];
  }
  void insert(const Vec3& s, std::int32_t idx) { bins_[bin_of(s)].push_back(idx); }
  template <class F>
  bool any_near(const Vec3& s, F&& overlaps) const {
    int b[3];
    for (int a = 0; a < 3; ++a) b[a] = std::min(n_[a] - 1, static_cast<int>(s[a] * n_[a]));
    const int rx = n_[0] >= 3 ? 1 : 0, ry = n_[1] >= 3 ? 1 : 0, rz = n_[2] >= 3 ? 1 : 0;
    if (n_[0] < 3 || n_[1] < 3 || n_[2] < 3) {  // small box: check everything
      for (const auto& bin : bins_)
        for (std::int32_t k : bin)
          if (overlaps(k)) return true;
      return false;
    }
    for (int dz = -rz; dz <= rz; ++dz)
      for (int dy = -ry; dy <= ry; ++dy)
        for (int dx = -rx; dx <= rx; ++dx) {
          const int x = (b[0] + dx + n_[0]) % n_[0], y = (b[1] + dy + n_[1]) % n_[1], z = (b[2] + dz + n_[2]) % n_[2];
          for (std::int32_t k : bins_[(static_cast<std::size_t>(z) * n_[1] + y) * n_[0] + x])
            if (overlaps(k)) return true;
        }
    return false;
  }

 private:
  int n_[3] = {1, 1, 1};
  std::vector<std::vector<std::int32_t>> bins_;
};

bool try_place_all(const CloudRequest& req, const std::vector<double>& sorted, const Vec3& box,
                   RandomStream& rng, Cloud& out) {
  const PeriodicCell cell(box);
  PlacementGrid grid(box, 2.0 * sorted.front());
  Particles p;
  p.reserve(sorted.size());
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    const double r = sorted[i];
    bool placed = false;
    for (int t = 0; t < req.attempts_per_particle && !placed; ++t) {
      const Vec3 s{rng.uniform(), rng.uniform(), rng.uniform()};
      const bool clash = grid.any_near(s, [&](std::int32_t k) {
        const double reach = r + p.radius[static_cast<std::size_t>(k)];
        return norm2(cell.branch(s, p.frac[static_cast<std::size_t>(k)])) < reach * reach;
      });
      if (!clash) {
        p.add_sphere(static_cast<std::int64_t>(i), r, req.density, s);
        grid.insert(s, static_cast<std::int32_t>(i));
        placed = true;
      }
    }
    if (!placed) return false;
  }
  out.particles = std::move(p);
  out.cell = cell;
  return true;
}

}  // namespace

Quaternion random_orientation(RandomStream& rng) {
  const double u1 = rng.uniform(), u2 = 2.0 * M_PI * rng.uniform(), u3 = 2.0 * M_PI * rng.uniform();
  const double s1 = std::sqrt(1.0 - u1), s2 = std::sqrt(u1);
  return {s2 * std::cos(u3), s1 * std::sin(u2), s1 * std::cos(u2), s2 * std::sin(u3)};
}

namespace {

/// Spheroid cloud: the sphere cloud of the bounding radii a_i = r_i k_i^(2/3),
/// at the void ratio that makes the spheroids' void ratio the requested one,
/// then each sphere replaced by a spheroid (a_i, a_i/k_i) of random
/// orientation. The sphere generator places the bounding spheres largest
/// first with ids in that order; k follows its sphere through the same
/// stable descending sort.
Cloud generate_spheroid_cloud(const CloudRequest& req, const std::vector<double>& k) {
  CloudRequest spheres = req;
  spheres.aspect_ratio = 1.0;
  spheres.aspect_ratios.clear();
  double v_bound = 0.0, v_spheroid = 0.0;
  std::vector<std::pair<double, double>> ak(req.radii.size());  // (a, k)
  for (std::size_t i = 0; i < req.radii.size(); ++i) {
    const double a = req.radii[i] * std::cbrt(k[i] * k[i]);
    spheres.radii[i] = a;
    ak[i] = {a, k[i]};
    v_bound += sphere_volume(a);
    v_spheroid += sphere_volume(a) / (k[i] * k[i]);
  }
  // V_box = (1 + e) V_spheroids = (1 + e_spheres) V_bounding
  spheres.void_ratio = (1.0 + req.void_ratio) * v_spheroid / v_bound - 1.0;
  if (!(spheres.void_ratio > 0.0))
    throw std::invalid_argument("initial_void_ratio: too small for the bounding spheres of the spheroids "
                                "(need (1 + e) V_spheroids > V_bounding)");
  std::stable_sort(ak.begin(), ak.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
  Cloud c = generate_cloud(spheres);
  RandomStream rng(req.seed ^ 0x5851f42d4c957f2dULL);
  const Particles& p = c.particles;
  Particles out;
  out.reserve(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double a = p.radius[i];
    const double ki = ak[static_cast<std::size_t>(p.id[i])].second;
    if (ki == 1.0)
      out.add_sphere(p.id[i], a, req.density, p.frac[i], {}, {}, p.material[i]);
    else
      out.add_spheroid(p.id[i], a, a / ki, req.density, p.frac[i], random_orientation(rng), {}, {}, p.material[i]);
  }
  c.particles = std::move(out);
  return c;
}

}  // namespace

Cloud generate_cloud(const CloudRequest& req) {
  if (req.radii.size() < 2) throw std::invalid_argument("particles.count: at least 2 particles are needed");
  for (double r : req.radii)
    if (!(r > 0.0 && std::isfinite(r))) throw std::invalid_argument("particles.radius: must be > 0");
  if (!(req.void_ratio > 0.0)) throw std::invalid_argument("initial_void_ratio: must be > 0");
  if (!(req.aspect_ratio >= 1.0 && std::isfinite(req.aspect_ratio)))
    throw std::invalid_argument("particles.aspect_ratio: must be >= 1 (prolate spheroids; 1 = spheres)");
  if (!req.aspect_ratios.empty() && req.aspect_ratios.size() != req.radii.size())
    throw std::invalid_argument("particles.aspect_ratios: one per particle (" + std::to_string(req.radii.size()) +
                                "), got " + std::to_string(req.aspect_ratios.size()));
  std::vector<double> k = req.aspect_ratios.empty() ? std::vector<double>(req.radii.size(), req.aspect_ratio)
                                                    : req.aspect_ratios;
  bool any = false;
  for (double ki : k) {
    if (!(ki >= 1.0 && std::isfinite(ki)))
      throw std::invalid_argument("particles.aspect_ratio: must be >= 1 (prolate spheroids; 1 = spheres)");
    any = any || ki != 1.0;
  }
  if (any) return generate_spheroid_cloud(req, k);
  for (int a = 0; a < 3; ++a)
    if (!(req.aspect[a] > 0.0)) throw std::invalid_argument("cell.aspect: must be > 0");
  std::vector<double> sorted = req.radii;
  std::stable_sort(sorted.begin(), sorted.end(), std::greater<double>());
  double vs = 0.0;
  for (double r : sorted) vs += sphere_volume(r);
  const double prod = req.aspect.x * req.aspect.y * req.aspect.z;
  double scale = std::cbrt((1.0 + req.void_ratio) * vs / prod);
  // The box must be wide enough for minimum-image neighbour search.
  const double min_aspect = std::min(req.aspect.x, std::min(req.aspect.y, req.aspect.z));
  scale = std::max(scale, 4.5 * sorted.front() / min_aspect);
  RandomStream rng(req.seed);
  Cloud out;
  for (int growth = 0; growth < 200; ++growth) {
    const Vec3 box = scale * req.aspect;
    if (try_place_all(req, sorted, box, rng, out)) {
      out.box_growths = growth;
      return out;
    }
    scale *= std::cbrt(1.05);
  }
  throw std::runtime_error("cloud generation: could not place the particles");
}

std::vector<double> uniform_radii(std::int64_t count, double rmin, double rmax, std::uint64_t seed) {
  RandomStream rng(seed ^ 0x9e3779b97f4a7c15ULL);
  std::vector<double> r(static_cast<std::size_t>(count));
  for (double& x : r) x = rng.uniform(rmin, rmax);
  return r;
}

std::vector<double> table_radii(std::int64_t count, const std::vector<std::pair<double, double>>& types) {
  std::vector<std::int64_t> n(types.size());
  std::vector<std::pair<double, std::size_t>> rem;
  std::int64_t used = 0;
  for (std::size_t k = 0; k < types.size(); ++k) {
    const double exact = types[k].second * static_cast<double>(count);
    n[k] = static_cast<std::int64_t>(std::floor(exact));
    used += n[k];
    rem.emplace_back(exact - static_cast<double>(n[k]), k);
  }
  std::stable_sort(rem.begin(), rem.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t k = 0; used < count && k < rem.size(); ++k, ++used) ++n[rem[k].second];
  std::vector<double> r;
  for (std::size_t k = 0; k < types.size(); ++k) r.insert(r.end(), static_cast<std::size_t>(n[k]), types[k].first);
  return r;
}

}  // namespace vt::dem
