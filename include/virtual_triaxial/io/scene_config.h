// A scene as read from YAML (config/scenes/*.yaml): material, particles,
// cell, damping, time step ratio, stages with stop criteria, output.
// All values SI. Strain rates and strains in scene files follow the
// geomechanics convention: compression positive.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "virtual_triaxial/dem/mass_damping.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/dem/material.h"
#include "virtual_triaxial/dem/stability_monitor.h"
#include "virtual_triaxial/dem/vec3.h"
#include "virtual_triaxial/protocol/stage_runner.h"
#include "virtual_triaxial/protocol/stage_spec.h"

namespace vt::io {

/// One particle type of a size distribution (count-based).
struct ParticleType {
  double radius = 0;     ///< [m]
  double fraction = 0;   ///< number fraction, types sum to 1
};

/// Explicitly listed particle.
struct ParticleSpec {
  std::int64_t id = 0;
  double radius = 0;            ///< [m]
  dem::Vec3 position;           ///< [m], Cartesian
  dem::Vec3 velocity;           ///< [m/s]
  dem::Vec3 angular_velocity;   ///< [rad/s]
};

struct DistributionSpec {
  std::int64_t count = 0;
  // Either a uniform radius range or a table of types.
  double radius_min = 0, radius_max = 0;  ///< [m], uniform in radius
  std::vector<ParticleType> types;
  std::uint64_t seed = 1;
  double initial_void_ratio = 3.0;  ///< loose cloud: cell volume = (1+e) V_solids
  double aspect_ratio = 1.0;        ///< a/b of every particle: prolate spheroids of the nominal radius; 1 = spheres
};

enum class ParticleSource { Distribution, List, SampleFile };

// Stages live in the ROS-free protocol library; the scene refers to them.
using protocol::StageSpec;
using protocol::StageType;
using protocol::StopCriteria;

struct OutputSpec {
  std::int64_t interval = 100;         ///< steps between recorded samples
  double progress_seconds = 2.0;       ///< wall seconds between progress lines
  /// Steps between VTK snapshots of the specimen (io/vtk_snapshot_writer.h),
  /// counted from each stage start; 0 = none (default). A multiple of interval.
  std::int64_t snapshot_interval = 0;
  /// Checkpoints inside a stage (protocol/run_checkpoint.h; triax_run
  /// --resume): on the first sample after checkpoint_ticks control ticks or
  /// checkpoint_seconds wall seconds (0 = that trigger off).
  std::int64_t checkpoint_ticks = 0;
  double checkpoint_seconds = 60.0;
};

/// `control:` -- control ticks, the servo of servo stages, the summary.
struct ControlSpec {
  std::int64_t interval = 1;               ///< DEM steps per control tick (= dem_node publish_every)
  protocol::ServoSettings servo;           ///< strategy, gain, max_dimensionless_rate
  double quasi_static_threshold = 1e-3;    ///< I_QS of the shear summary
};

/// Which `material` keys the YAML gave (beside a sample_file they change
/// the loaded sample: density and modulus are scaled in, a different
/// Poisson ratio is refused; see scene_builder.h).
struct MaterialKeysGiven {
  bool density = false, young_modulus = false, poisson_ratio = false;
};

struct SceneConfig {
  std::string source_path;             ///< the YAML file (for relative paths)
  dem::Material material;
  MaterialKeysGiven material_given;
  ParticleSource source = ParticleSource::Distribution;
  DistributionSpec distribution;
  std::vector<ParticleSpec> list;
  std::string sample_file;             ///< resolved path when source == SampleFile
  dem::Vec3 cell_lengths;              ///< [m], required for List
  dem::Vec3 cell_aspect{1, 1, 1};      ///< for Distribution
  dem::MassDamping damping;
  double time_step_ratio = 0.3;
  /// time_step_basis: contacts -> dt from the contacts (dem/contact_time_step.h).
  /// A YAML scene defaults to contacts unless it sets time_step_ratio
  /// (scene_parser.cpp); a SceneConfig built in code keeps c_t.
  dem::TimeStepBasis time_step_basis = dem::TimeStepBasis::ReferenceTime;
  double time_step_safety = dem::SimulationSettings{}.time_step_safety;
  double time_step_max_ratio = dem::SimulationSettings{}.time_step_max_ratio;
  bool time_step_warning = false;      ///< c_t >= 1 accepted with a warning
  dem::StabilityLimits stability;
  std::vector<StageSpec> stages;
  OutputSpec output;
  ControlSpec control;

  /// The StageRunner options this scene asks for.
  protocol::RunOptions run_options() const;
};

}  // namespace vt::io
