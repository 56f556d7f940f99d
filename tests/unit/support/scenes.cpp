#include "support/scenes.h"

#include <gtest/gtest.h>

#include "virtual_triaxial/dem/cloud_generator.h"
#include "virtual_triaxial/dem/random_stream.h"
#include "virtual_triaxial/dem/spatial_sort.h"

namespace vt::test {

dem::Material test_material(double friction) {
  dem::Material m;
  m.density = 2650.0;
  m.young = 70e9;
  m.poisson = 0.3;
  m.friction = friction;
  return m;
}

dem::SimulationSettings undamped(double ct, double friction) {
  dem::SimulationSettings s;
  s.material = test_material(friction);
  s.damping = dem::MassDamping(dem::DampingModel::OD, 0.0);
  s.time_step_ratio = ct;
  return s;
}

CloudScene polydisperse_cloud(std::int64_t n, double void_ratio, std::uint64_t seed,
                              double length_scale, double density) {
  dem::CloudRequest req;
  req.radii = dem::uniform_radii(n, 0.8e-3, 1.2e-3, seed);
  req.density = density;
  req.void_ratio = void_ratio;
  req.seed = seed;
  dem::Cloud c = dem::generate_cloud(req);
  CloudScene s;
  if (length_scale == 1.0) {
    s.particles = std::move(c.particles);
    s.cell = c.cell;
    return s;
  }
  // Same fractional geometry, every length scaled.
  dem::Particles& p = c.particles;
  dem::Particles q;
  for (std::size_t i = 0; i < p.size(); ++i)
    q.add_sphere(p.id[i], length_scale * p.radius[i], density, p.frac[i]);
  s.particles = std::move(q);
  s.cell = dem::PeriodicCell(length_scale * dem::Vec3{c.cell.h()(0, 0), c.cell.h()(1, 1), c.cell.h()(2, 2)});
  return s;
}

CloudScene spheroid_cloud(std::int64_t n, double aspect, double void_ratio, std::uint64_t seed, double density) {
  CloudScene spheres = polydisperse_cloud(n, void_ratio, seed, 1.0, density);
  dem::RandomStream rng(seed + 7919);
  const dem::Particles& p = spheres.particles;
  CloudScene s;
  s.cell = spheres.cell;
  for (std::size_t i = 0; i < p.size(); ++i)
    s.particles.add_spheroid(p.id[i], p.radius[i], p.radius[i] / aspect, density, p.frac[i],
                             dem::random_orientation(rng));
  return s;
}

void randomize_velocities(dem::Particles& p, double speed, double spin, std::uint64_t seed) {
  dem::RandomStream rng(seed);
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.velocity[i] = {speed * rng.uniform(-1, 1), speed * rng.uniform(-1, 1), speed * rng.uniform(-1, 1)};
    p.omega[i] = {spin * rng.uniform(-1, 1), spin * rng.uniform(-1, 1), spin * rng.uniform(-1, 1)};
  }
}

dem::SimulationState spatially_sorted(dem::SimulationState s) {
  dem::spatial_sort(s);
  return s;
}

bool has_owner_stored_after(const dem::NeighborList& list) {
  // a particle i with entries of its own and an entry whose owner is stored
  // after it (partner i < owner)
  const std::vector<std::int32_t>& off = list.offsets();
  const std::vector<std::int32_t>& owners = list.owners();
  const std::vector<std::int32_t>& partner = list.pairs().partner;
  for (std::size_t e = 0; e < partner.size(); ++e) {
    const auto j = static_cast<std::size_t>(partner[e]);
    if (partner[e] < owners[e] && off[j + 1] > off[j]) return true;
  }
  return false;
}

dem::SimulationState loaded_packing(int particles) {
  CloudScene sc = polydisperse_cloud(particles, 1.8, 5);
  dem::SimulationSettings s = undamped(0.3, 0.5);
  s.damping = dem::MassDamping(dem::DampingModel::ND, 0.02);
  dem::Simulation sim(std::move(sc.particles), sc.cell, s);
  sim.set_strain_rates(dem::Vec3{-1, -1, -1} * (4e-4 / sim.time_scale().t0));
  EXPECT_EQ(sim.run(1200), 1200) << sim.failure();
  // then shear at constant volume so springs keep changing
  const double r = 2e-4 / sim.time_scale().t0;
  sim.set_strain_rates({0.5 * r, 0.5 * r, -r});
  return sim.state();
}

}  // namespace vt::test
