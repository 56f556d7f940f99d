// Conversions dem::Measures -> the state messages dem_node publishes each
// control tick (msg/Stress, Strain, MomentIndex, KineticEnergy, Fabric).
// Pure functions, no publishing. The core's Measures already follow the
// geomechanics convention (compression positive); nothing is re-signed here.
//
// Every header is stamped with SIMULATION time (`time`, rounded to 1 ns by
// ros::Time), frame_id "cell". The tick is the `tick` field: roscpp's
// Publisher overwrites header.seq with its own message count.
#pragma once

#include <cstdint>

#include <std_msgs/Header.h>

#include "virtual_triaxial/Fabric.h"
#include "virtual_triaxial/KineticEnergy.h"
#include "virtual_triaxial/MomentIndex.h"
#include "virtual_triaxial/Strain.h"
#include "virtual_triaxial/Stress.h"
#include "virtual_triaxial/dem/measures.h"

namespace vt::ros {

/// Which control tick a message belongs to and its simulation time [s].
struct TickStamp {
  std::uint64_t tick = 0;
  double time = 0.0;
};

std_msgs::Header make_header(const TickStamp& s);

/// young [Pa] for sigma_bar_p = p / E; stiffness = dem::axis_stiffness [Pa];
/// control_period = dt * publish_every [s].
virtual_triaxial::Stress to_stress_msg(const dem::Measures& m, const TickStamp& s, double control_period,
                                       double young, const dem::Vec3& stiffness);
/// rates [1/s] applied during the tick, compression positive; t0 [s].
virtual_triaxial::Strain to_strain_msg(const dem::Measures& m, const TickStamp& s, const dem::Vec3& rates,
                                       double t0);
virtual_triaxial::MomentIndex to_moment_index_msg(const dem::Measures& m, const TickStamp& s);
virtual_triaxial::KineticEnergy to_kinetic_energy_msg(const dem::Measures& m, const TickStamp& s);
virtual_triaxial::Fabric to_fabric_msg(const dem::Measures& m, const TickStamp& s);

/// The inverse: the Measures of one tick from its five messages (for the
/// protocol node's results file). Fields the messages do not carry (volume,
/// max overlap) stay 0; the energy references are chosen so that
/// energy.balance_error() equals the message's balance_error.
dem::Measures measures_from_messages(const virtual_triaxial::Stress& stress, const virtual_triaxial::Strain& strain,
                                     const virtual_triaxial::MomentIndex& moment,
                                     const virtual_triaxial::KineticEnergy& energy,
                                     const virtual_triaxial::Fabric& fabric, std::int64_t step);

}  // namespace vt::ros
