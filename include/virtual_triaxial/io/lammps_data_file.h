// LAMMPS data files (atom_style sphere) <-> samples (issue 13), so that users
// bring packings made by LAMMPS and the side-by-side benchmark hands ours to
// LAMMPS. Format facts from the LAMMPS manual (read_data, atom_style sphere):
//   line 1: a comment (skipped); then header lines "N atoms", "T atom types",
//   "xlo xhi", "ylo yhi", "zlo zhi" (both numbers first) and for a
//   triclinic box "xy xz yz"; then sections, each a keyword line followed by
//   a blank line and one line per atom:
//     Atoms # sphere   atom-ID atom-type diameter density x y z [ix iy iz]   (SI here)
//     Velocities       atom-ID vx vy vz wx wy wz
//   '#' starts a comment anywhere. Units: SI (LAMMPS `units si`).
// The box H has the columns a = (lx, 0, 0), b = (xy, ly, 0), c = (xz, yz, lz);
// positions are stored as s = H^-1 (x - lo) wrapped into [0, 1)^3 (image
// flags are ignored: the cell is periodic). Every atom must have the same
// density (one material per sample); mass = density 4/3 pi R^3. Contact
// histories are not part of a data file: an imported sample starts without
// tangential springs (the first step rebuilds the normal forces exactly).
// Velocities are the fluctuating ones (the imported cell is at rest).
// LAMMPS atom-IDs start at 1, ours at 0: particle id = atom-ID - 1 both ways.
// Reading refuses anything else with "FILE:LINE: reason" (or "FILE: reason").
#pragma once

#include <string>

#include "virtual_triaxial/dem/material.h"
#include "virtual_triaxial/dem/simulation.h"

namespace vt::io {

/// Read a data file into a state (material density from the file, the rest
/// of `material` and `settings` as given). Throws std::runtime_error.
dem::SimulationState read_lammps_data(const std::string& path, const dem::Material& material,
                                      const dem::SimulationSettings& settings = {});

/// Write the state as a data file (spheres only; positions x = H s + 0,
/// total velocities v + L x). Throws std::runtime_error naming the path.
void write_lammps_data(const std::string& path, const dem::SimulationState& s);

}  // namespace vt::io
