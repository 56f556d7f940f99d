#include "virtual_triaxial/io/scene_builder.h"

#include <stdexcept>

#include "virtual_triaxial/dem/cloud_generator.h"
#include "virtual_triaxial/io/sample_file.h"

namespace vt::io {

protocol::RunOptions SceneConfig::run_options() const {
  protocol::RunOptions o;
  o.sample_interval = output.interval;
  o.progress_seconds = output.progress_seconds;
  o.control_interval = control.interval;
  o.servo = control.servo;
  o.quasi_static_threshold = control.quasi_static_threshold;
  return o;
}

dem::SimulationSettings settings_from_scene(const SceneConfig& scene) {
  dem::SimulationSettings s;
  s.material = scene.material;
  s.damping = scene.damping;
  s.time_step_ratio = scene.time_step_ratio;
  s.limits = scene.stability;
  return s;
}

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
      return dem::Simulation(std::move(cloud.particles), cloud.cell, settings);
    }
    case ParticleSource::List: {
      const dem::PeriodicCell cell(scene.cell_lengths);
      dem::Particles p;
      for (const ParticleSpec& ps : scene.list)
        p.add_sphere(ps.id, ps.radius, scene.material.density,
                     dem::PeriodicCell::wrap(cell.to_fractional(ps.position)), ps.velocity, ps.angular_velocity);
      return dem::Simulation(std::move(p), cell, settings);
    }
    case ParticleSource::SampleFile: {
      dem::SimulationState st = read_sample(scene.sample_file);
      st.settings.material.friction = scene.material.friction;
      st.settings.damping = scene.damping;
      st.settings.time_step_ratio = scene.time_step_ratio;
      st.settings.limits = scene.stability;
      return dem::Simulation(st);
    }
  }
  throw std::logic_error("unknown particle source");
}

}  // namespace vt::io
