// Sample file (DESIGN §7): everything needed to continue a run exactly
// (dem::SimulationState) plus how the sample was prepared, in HDF5.
//
// Layout (format "virtual_triaxial sample", format_version 1). Every dataset
// has a `units` string attribute ("1" = dimensionless); numbers are datasets,
// strings are attributes of their group. N particles, M contacts.
//   /                      attrs format, format_version (int64)
//   /particles/id                  (N)   int64       [1]
//             /shape               (N)   uint8       [1]   0 sphere, 1 spheroid
//             /radius              (N)   float64     [m]   nominal (equal-volume)
//             /semi_axes           (N,3) float64     [m]   (a, b, b)
//             /mass                (N)   float64     [kg]
//             /inertia             (N,3) float64     [kg m^2] principal, body frame
//             /position            (N,3) float64     [m]   x = H s (informative only)
//             /position_fractional (N,3) float64     [1]   s, what a restart uses
//             /velocity            (N,3) float64     [m/s] fluctuating velocity
//             /angular_velocity    (N,3) float64     [rad/s] world frame
//             /orientation         (N,4) float64     [1]   quaternion w x y z
//             /material            (N)   int32       [1]
//   /contacts/id_a, id_b           (M)   int64       [1]   id_a < id_b
//            /spring               (M,3) float64     [N]   tangential spring on id_b
//   /cell/h, h_reference           (3,3) float64     [m]   columns = cell edges
//        /velocity_gradient        (3,3) float64     [1/s] extension positive
//        /time                     ()    float64     [s]
//        /step                     ()    int64       [1]
//   /material/density [kg/m^3], young_modulus [Pa], poisson_ratio [1], friction [1]
//   /settings  attr damping_model ("OD"/"ND"); damping_ratio, time_step_ratio,
//              skin_ratio [1]; check_interval () int64 [1];
//              max_overlap_ratio, max_energy_error [1]; with the time step
//              from the contacts only (dem/contact_time_step.h; absent =
//              reference basis, older files): attr time_step_basis
//              ("contacts"), time_step_safety, time_step_max_ratio [1],
//              time_step, contact_critical_step [s] (inf: no contacts),
//              contact_refresh_virial [N m]
//   /energy/boundary_work, damping, friction, kinetic_translational,
//           kinetic_rotational, elastic, kinetic_reference,
//           elastic_reference [J]; has_reference () uint8 [1]
//   /preparation/seed () uint64 [1], friction_during_shrinkage [1],
//                target_pressure [Pa], initial_void_ratio [1];
//                attrs software_version, created_by, description
//
// Doubles are stored as IEEE float64 and restored bit for bit (NaN included);
// the reader uses position_fractional, never recomputes it from position.
// Writing is atomic (temporary file + rename, see hdf5_atomic_file.h).
// Reading validates presence, type and shape of every dataset and the values
// a run relies on; errors read "<file>: <dataset>: <reason>".
#pragma once

#include <cstdint>
#include <limits>
#include <string>

#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/io/hdf5_group.h"

namespace vt::io {

/// How the sample was prepared (NaN = not applicable).
struct SampleMetadata {
  std::uint64_t seed = 0;
  double friction_during_shrinkage = std::numeric_limits<double>::quiet_NaN();  ///< mu1 [1]
  double target_pressure = std::numeric_limits<double>::quiet_NaN();            ///< [Pa]
  double initial_void_ratio = std::numeric_limits<double>::quiet_NaN();         ///< e0 [1]
  std::string software_version;
  std::string created_by;
  std::string description;
};

inline constexpr const char* kSampleFormat = "virtual_triaxial sample";
inline constexpr std::int64_t kSampleFormatVersion = 1;

/// Write atomically; throws std::runtime_error naming the path (and the
/// field, for an inconsistent state).
void write_sample(const std::string& path, const dem::SimulationState& s, const SampleMetadata& meta);

/// Read and validate; throws std::runtime_error naming the path and dataset.
dem::SimulationState read_sample(const std::string& path, SampleMetadata* meta = nullptr);

/// The same layout into / from an open group (the root of a file built
/// with h5::AtomicFile, e.g. a checkpoint, io/checkpoint_file.h).
void write_sample_into(const h5::Group& root, const dem::SimulationState& s, const SampleMetadata& meta);
dem::SimulationState read_sample_from(const h5::Group& root, SampleMetadata* meta = nullptr);

}  // namespace vt::io
