// The one-line JSON summary triax_run prints last on stdout.
#pragma once

#include <cstdint>
#include <string>

#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/protocol/stage_runner.h"

namespace vt::io {

/// What a summary needs to know of the specimen besides the RunReport (so
/// the ROS protocol node, which has no Simulation, can write one too).
struct RunContext {
  std::size_t particles = 0;
  double t0 = 0, dt = 0, l0 = 0;               ///< [s], [s], [m]
  double energy_relative_balance_error = 0;    ///< [1]
  /// Spheroid contact solver over the run (spheroid_contact.h); -1 = unknown
  /// (the rig's protocol node does not see them).
  std::int64_t spheroid_contact_solves = -1, spheroid_contact_fallbacks = -1, spheroid_contact_failures = -1;
  /// Control ticks on which dem_node waited in vain for a lockstep
  /// participant's command (the rig only; -1 = not applicable).
  std::int64_t lockstep_timeouts = -1;
};
RunContext run_context(const dem::Simulation& sim);

std::string run_summary_json(const protocol::RunReport& report, const RunContext& ctx,
                             const std::string& results_path);
/// The summary of a test still running, rewritten at every flush of its
/// results (verdict `interrupted`, `partial` true, the samples flushed and
/// the stage): what a kill leaves (the rig's summary.json).
std::string partial_summary_json(std::size_t samples, const std::string& stage, const std::string& results);
inline std::string run_summary_json(const protocol::RunReport& report, const dem::Simulation& sim,
                                    const std::string& results_path) {
  return run_summary_json(report, run_context(sim), results_path);
}

}  // namespace vt::io
