// Builds the Simulation a scene describes.
//   distribution  loose cloud (phase 1 of chapter 4.3.1) from the size
//                 distribution, seed, aspect ratios and initial void ratio;
//   list          the explicit particles in a cell of the given lengths;
//                 (distribution and list: stored in slab order above
//                 1536 particles, dem::order_new_specimen, ids kept)
//   sample_file   a saved sample, continued exactly, in its stored order
//                 (never re-sorted). Material (density,
//                 modulus, Poisson ratio) comes from the sample unless the
//                 scene gives `material.density` / `material.young_modulus`:
//                 those are scaled into the sample keeping every
//                 dimensionless quantity (dem/material_scaling.h, chapter 3);
//                 a `material.poisson_ratio` other than the sample's is
//                 refused naming the field. Friction, damping, c_t and
//                 stability limits come from the scene.
#pragma once

#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/io/scene_config.h"

namespace vt::io {

dem::SimulationSettings settings_from_scene(const SceneConfig& scene);
dem::Simulation build_simulation(const SceneConfig& scene);

}  // namespace vt::io
