// Builds dem_node's specimen (a dem::Simulation) from a sample file or a
// scene, and applies the node's parameter overrides. ROS-free.
//
//   sample  HDF5 sample file (io/sample_file.h), continued exactly;
//   scene   YAML scene (config/scenes/README.md) via io::build_simulation;
//           the scene's stages are NOT run (the protocol node runs tests).
// Overrides (dem_node ~damping_model, ~damping_ratio, ~time_step_ratio) are
// applied on every load, after the file's own settings. The cell's strain
// reference is reset to the loaded shape, so published strains count from
// the load (the reference only affects the strain measures, not the motion).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/io/sample_file.h"

namespace vt::ros {

struct SpecimenOverrides {
  std::optional<std::string> damping_model;  ///< "OD" or "ND"
  std::optional<double> damping_ratio;       ///< xi >= 0
  std::optional<double> time_step_ratio;     ///< c_t > 0

  /// "" when valid, else "<param>: <reason>" (param names without "~").
  std::string validate() const;
};

struct Specimen {
  std::unique_ptr<dem::Simulation> sim;
  io::SampleMetadata meta;
  std::string source;    ///< the file it came from
  std::string warning;   ///< non-fatal remarks ("" if none)
  std::int64_t snapshot_interval = 0;  ///< a scene's output.snapshot_interval (0: none, or a sample file)
};

class SpecimenLoader {
 public:
  explicit SpecimenLoader(SpecimenOverrides o) : overrides_(std::move(o)) {}
  /// Throws std::runtime_error / std::invalid_argument with a message that
  /// names the file and field.
  Specimen load_sample(const std::string& path) const;
  /// A checkpoint of a test that goes on (io/checkpoint_file.h is a sample
  /// file): its state exactly, strain reference and settings included (the
  /// overrides were applied when the test started).
  Specimen load_checkpoint(const std::string& path) const;
  Specimen load_scene(const std::string& path) const;

 private:
  void apply(Specimen& s) const;
  SpecimenOverrides overrides_;
};

}  // namespace vt::ros
