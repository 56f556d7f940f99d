// The one-line JSON summary triax_run prints last on stdout.
#pragma once

#include <string>

#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/protocol/stage_runner.h"

namespace vt::io {

std::string run_summary_json(const protocol::RunReport& report, const dem::Simulation& sim,
                             const std::string& results_path);

}  // namespace vt::io
