// SpecimenLoader: sample / scene -> dem::Simulation with overrides.
// See specimen_loader.h.
#include "virtual_triaxial/ros/specimen_loader.h"

#include <cmath>
#include <stdexcept>

#include "virtual_triaxial/dem/mass_damping.h"
#include "virtual_triaxial/io/scene_builder.h"
#include "virtual_triaxial/io/scene_parser.h"

namespace vt::ros {

std::string SpecimenOverrides::validate() const {
  dem::DampingModel m;
  if (damping_model && !dem::parse_damping_model(*damping_model, m))
    return "damping_model: '" + *damping_model + "' is not " + dem::damping_model_names();
  if (damping_model && damping_ratio) {
    const std::string bad = dem::damping_parameter_error(m, *damping_ratio);
    if (!bad.empty()) return "damping_ratio: " + bad + " for damping model " + *damping_model;
  } else if (damping_ratio && !(std::isfinite(*damping_ratio) && *damping_ratio >= 0.0)) {
    return "damping_ratio: must be a finite number >= 0";
  }
  if (time_step_ratio && !(std::isfinite(*time_step_ratio) && *time_step_ratio > 0.0))
    return "time_step_ratio: must be a finite number > 0";
  return "";
}

void SpecimenLoader::apply(Specimen& s) const {
  dem::Simulation& sim = *s.sim;
  if (overrides_.damping_model || overrides_.damping_ratio) {
    dem::DampingModel model = sim.settings().damping.model();
    if (overrides_.damping_model) dem::parse_damping_model(*overrides_.damping_model, model);
    const double ratio = overrides_.damping_ratio ? *overrides_.damping_ratio : sim.settings().damping.ratio();
    sim.set_damping(dem::MassDamping(model, ratio));
  }
  const bool contacts = sim.settings().time_step_basis == dem::TimeStepBasis::Contacts;
  if (overrides_.time_step_ratio) sim.set_time_step_ratio(*overrides_.time_step_ratio);
  if (overrides_.time_step_ratio && contacts)
    s.warning += "~time_step_ratio is unused: this specimen takes its time step from the contacts "
                 "(set time_step_ratio in the scene to use c_t); ";
  if (!contacts && sim.settings().time_step_ratio >= 1.0)
    s.warning += "time_step_ratio " + std::to_string(sim.settings().time_step_ratio) +
                 " >= 1: the step exceeds the critical estimate; ";
  sim.reset_strain_reference();
}

Specimen SpecimenLoader::load_sample(const std::string& path) const {
  const std::string bad = overrides_.validate();
  if (!bad.empty()) throw std::invalid_argument(bad);
  Specimen s;
  dem::SimulationState st = io::read_sample(path, &s.meta);
  s.sim = std::make_unique<dem::Simulation>(st);
  s.source = path;
  apply(s);
  return s;
}

Specimen SpecimenLoader::load_checkpoint(const std::string& path) const {
  Specimen s;
  s.sim = std::make_unique<dem::Simulation>(io::read_sample(path, &s.meta));
  s.source = path;
  return s;
}

Specimen SpecimenLoader::load_scene(const std::string& path) const {
  const std::string bad = overrides_.validate();
  if (!bad.empty()) throw std::invalid_argument(bad);
  Specimen s;
  const io::SceneConfig scene = io::load_scene(path);
  s.sim = std::make_unique<dem::Simulation>(io::build_simulation(scene));
  s.source = path;
  s.snapshot_interval = scene.output.snapshot_interval;
  s.meta.created_by = "dem_node scene " + path;
  if (!scene.stages.empty())
    s.warning += "the scene's " + std::to_string(scene.stages.size()) +
                 " stage(s) are not run by dem_node (the protocol node runs tests); ";
  if (scene.time_step_warning) s.warning += "scene time_step_ratio >= 1; ";
  apply(s);
  return s;
}

}  // namespace vt::ros
