#include "virtual_triaxial/io/scene_builder.h"

#include "virtual_triaxial/io/number_text.h"

#include <cstdio>
#include <stdexcept>
#include <string>

#include "virtual_triaxial/dem/cloud_generator.h"
#include "virtual_triaxial/dem/material_scaling.h"
#include "virtual_triaxial/dem/spatial_sort.h"
#include "virtual_triaxial/io/sample_file.h"
#include "virtual_triaxial/io/scene_error.h"

namespace vt::io {

protocol::RunOptions SceneConfig::run_options() const {
  protocol::RunOptions o;
  o.sample_interval = output.interval;
  o.progress_seconds = output.progress_seconds;
  o.control_interval = control.interval;
  o.servo = control.servo;
  o.quasi_static_threshold = control.quasi_static_threshold;
  o.young_modulus = material.young;  // the runners set the specimen's own (a sample file's) per stage
  o.qs_damping = damping.model() == dem::DampingModel::ND ? quasi_static::QsDamping::ND : quasi_static::QsDamping::OD;
  o.checkpoint_ticks = output.checkpoint_ticks;
  o.checkpoint_seconds = output.checkpoint_seconds;
  return o;
}

dem::SimulationSettings settings_from_scene(const SceneConfig& scene) {
  dem::SimulationSettings s;
  s.material = scene.material;
  s.damping = scene.damping;
  s.time_step_ratio = scene.time_step_ratio;
  s.time_step_basis = scene.time_step_basis;
  s.time_step_safety = scene.time_step_safety;
  s.time_step_max_ratio = scene.time_step_max_ratio;
  s.limits = scene.stability;
  return s;
}

namespace {

std::string num(double v) { return number_text(v, 6); }

// `material.*` beside a sample_file: density and Young's modulus are scaled
// into the sample (dem/material_scaling.h: every dimensionless quantity
// kept), a different Poisson ratio is refused (the stored tangential springs
// belong to the sample's contact law). Never silently ignored.
void apply_material_keys(const SceneConfig& scene, dem::SimulationState& st) {
  const MaterialKeysGiven& g = scene.material_given;
  const dem::Material& m = st.settings.material;
  if (g.poisson_ratio && scene.material.poisson != m.poisson)
    throw SceneError("material.poisson_ratio",
                     "the sample '" + scene.sample_file + "' was prepared with nu = " + num(m.poisson) +
                         " and its contact springs belong to it; prepare a new sample with nu = " +
                         num(scene.material.poisson) + " (triax_prepare --poisson-ratio) or leave the key out");
  dem::scale_material(st, g.density ? scene.material.density : m.density,
                      g.young_modulus ? scene.material.young : m.young);
}

}  // namespace

dem::Simulation build_simulation(const SceneConfig& scene) {
  const dem::SimulationSettings settings = settings_from_scene(scene);
  switch (scene.source) {
    case ParticleSource::Distribution: {
      const DistributionSpec& d = scene.distribution;
      dem::CloudRequest req;
      if (!d.types.empty()) {
        std::vector<std::pair<double, double>> t;
        for (const ParticleType& pt : d.types) t.emplace_back(pt.radius, pt.fraction);
        req.radii = dem::table_radii(d.count, t);
      } else {
        req.radii = dem::uniform_radii(d.count, d.radius_min, d.radius_max, d.seed);
      }
      req.density = scene.material.density;
      req.aspect = scene.cell_aspect;
      req.void_ratio = d.initial_void_ratio;
      req.aspect_ratio = d.aspect_ratio;
      req.seed = d.seed;
      dem::Cloud cloud = dem::generate_cloud(req);
      dem::order_new_specimen(cloud.particles, cloud.cell);
      return dem::Simulation(std::move(cloud.particles), cloud.cell, settings);
    }
    case ParticleSource::List: {
      const dem::PeriodicCell cell(scene.cell_lengths);
      dem::Particles p;
      for (const ParticleSpec& ps : scene.list)
        p.add_sphere(ps.id, ps.radius, scene.material.density,
                     dem::PeriodicCell::wrap(cell.to_fractional(ps.position)), ps.velocity, ps.angular_velocity);
      dem::order_new_specimen(p, cell);
      return dem::Simulation(std::move(p), cell, settings);
    }
    case ParticleSource::SampleFile: {
      dem::SimulationState st = read_sample(scene.sample_file);
      apply_material_keys(scene, st);
      st.settings.material.friction = scene.material.friction;
      st.settings.damping = scene.damping;
      st.settings.time_step_ratio = scene.time_step_ratio;
      const dem::SimulationSettings& file = st.settings;
      if (file.time_step_basis != scene.time_step_basis || file.time_step_safety != scene.time_step_safety ||
          file.time_step_max_ratio != scene.time_step_max_ratio)
        st.time_step = st.contact_critical_step = 0.0;  // another rule: derive the step afresh
      st.settings.time_step_basis = scene.time_step_basis;
      st.settings.time_step_safety = scene.time_step_safety;
      st.settings.time_step_max_ratio = scene.time_step_max_ratio;
      st.settings.limits = scene.stability;
      return dem::Simulation(st);  // as stored: a sample file may continue a run (never re-sorted)
    }
  }
  throw std::logic_error("unknown particle source");
}

}  // namespace vt::io
