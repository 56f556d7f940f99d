// The ~predict_quasi_static service of test_protocol_node: a thin adapter
// from a protocol file to io::build_qs_advice (the numbers of `triax_qs
// predict`: eq. 84/85 eps'_QS, eq. 72, the shear stage's run plan) and into
// the response. Loads the protocol and builds its specimen on its own (the
// rig's dem_node is not touched); a bad protocol is a refusal naming the
// field (success = false, message), never an exception.
#pragma once

#include <string>

#include "virtual_triaxial/PredictQuasiStatic.h"

namespace vt::ros {

/// Fills `rs` for the protocol at `path` (cost <= 0: measured on the sample).
void answer_qs_advice(const std::string& path, double cost_per_particle_step,
                      virtual_triaxial::PredictQuasiStatic::Response& rs);

}  // namespace vt::ros
