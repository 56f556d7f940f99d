// Gathers the five state messages dem_node publishes for one control tick
// (stress, strain, moment_index, kinetic_energy, fabric) so a consumer can act
// once it has the complete state of tick k. Messages of one tick arrive on
// separate connections in any order; older ticks are dropped once a newer
// tick is complete. Not thread-safe (used from one callback queue).
#pragma once

#include <cstdint>
#include <map>
#include <optional>

#include "virtual_triaxial/Fabric.h"
#include "virtual_triaxial/KineticEnergy.h"
#include "virtual_triaxial/MomentIndex.h"
#include "virtual_triaxial/Strain.h"
#include "virtual_triaxial/Stress.h"

namespace vt::ros {

struct TickMessages {
  std::optional<virtual_triaxial::Stress> stress;
  std::optional<virtual_triaxial::Strain> strain;
  std::optional<virtual_triaxial::MomentIndex> moment;
  std::optional<virtual_triaxial::KineticEnergy> energy;
  std::optional<virtual_triaxial::Fabric> fabric;
  bool complete() const { return stress && strain && moment && energy && fabric; }
};

class TickCollector {
 public:
  void add(const virtual_triaxial::Stress& m) { slot(m.tick).stress = m; }
  void add(const virtual_triaxial::Strain& m) { slot(m.tick).strain = m; }
  void add(const virtual_triaxial::MomentIndex& m) { slot(m.tick).moment = m; }
  void add(const virtual_triaxial::KineticEnergy& m) { slot(m.tick).energy = m; }
  void add(const virtual_triaxial::Fabric& m) { slot(m.tick).fabric = m; }

  /// The complete state of `tick`, removed from the collector (with every
  /// older tick); nullopt while a message is missing.
  std::optional<TickMessages> take(std::uint64_t tick);
  /// Newest tick any message was seen for (0 if none).
  std::uint64_t newest() const { return newest_; }
  void clear() { ticks_.clear(); }

 private:
  TickMessages& slot(std::uint64_t tick);
  std::map<std::uint64_t, TickMessages> ticks_;
  std::uint64_t newest_ = 0;
};

}  // namespace vt::ros
