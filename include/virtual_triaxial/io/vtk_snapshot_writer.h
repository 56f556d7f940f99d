// A time series of specimen snapshots (dem/specimen_snapshot.h) as VTK XML
// files that ParaView (5.11) and VTK (9.1) read without plugins. Directory
// layout, snapshot k (6 digits):
//   particles_k.vtp   PolyData, one vertex per particle at x = H s [m].
//                     Point data: id, shape (0 sphere, 1 spheroid), radius
//                     [m] (nominal), diameter [m] (2 radius, for the Glyph
//                     filter's sphere of radius 0.5), semi_axes (a, b, b)
//                     [m], orientation (quaternion w x y z, body -> world),
//                     symmetry_axis (q (1,0,0)), shape_tensor (3x3, R
//                     diag(2a, 2b, 2b) R^T [m], for the Tensor Glyph filter:
//                     its default sphere becomes the spheroid), velocity
//                     (fluctuating) [m/s], spin [rad/s], contact_count, idle
//                     (section 4.5).
//                     Field data: TimeValue [s], step, cell_matrix (H, row
//                     major) [m], strain (log, compression positive),
//                     stress (the core's Love-Weber stress, row major,
//                     compression positive) [Pa].
//   contacts_k.vtp    PolyData, one line per contact from x_i to x_i + branch
//                     (the partner's periodic image). Cell data: id_i, id_j,
//                     branch [m], normal_force (|F_n|) [N],
//                     normal_force_vector, tangential_force (on j) [N],
//                     tangential_force_magnitude [N], overlap [m], sliding.
//                     Point data: normal_force (for the Tube filter's
//                     "vary radius by scalar").
//   cell_k.vtp        PolyData, the 12 edges of the periodic cell.
//   particles.pvd, contacts.pvd, cell.pvd   collections (timestep = time [s])
//   snapshots.csv     index, step, time [s], label, strains, p [Pa],
//                     contacts: what each snapshot is (e.g. "stage shear start").
// ASCII data arrays, numbers in the shortest form that reads back to the
// same double (std::to_chars). Every file is written atomically and checked
// (atomic_text_file.h); the collections are rewritten after each snapshot,
// so a killed run leaves a complete series. ROS-free.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "virtual_triaxial/dem/specimen_snapshot.h"

namespace vt::io {

class VtkSnapshotSeries {
 public:
  /// Creates `directory` (and parents) and removes the files of an earlier
  /// series in it (the names above only). Throws std::runtime_error naming it.
  explicit VtkSnapshotSeries(std::string directory);

  /// Writes snapshot number count() and rewrites the collections. `label`
  /// says what it is (no commas or newlines; they are replaced by spaces).
  void write(const dem::SpecimenSnapshot& s, const std::string& label);

  const std::string& directory() const { return dir_; }
  std::size_t count() const { return entries_.size(); }
  /// Step of the last snapshot written (-1 before the first).
  std::int64_t last_step() const { return entries_.empty() ? -1 : entries_.back().step; }

 private:
  struct Entry {
    std::int64_t step = 0;
    double time = 0;
    std::string label;
    dem::Vec3 strain;
    double p = 0;
    std::size_t contacts = 0;
  };
  void write_collections() const;

  std::string dir_;
  std::vector<Entry> entries_;
};

/// The three VTK documents of one snapshot (exposed for tests).
std::string vtk_particles_document(const dem::SpecimenSnapshot& s);
std::string vtk_contacts_document(const dem::SpecimenSnapshot& s);
std::string vtk_cell_document(const dem::SpecimenSnapshot& s);

}  // namespace vt::io
