// triax_import --lammps FILE.data --out sample.h5 [--young-modulus PA]
//              [--poisson-ratio NU] [--friction MU] [--damping-ratio XI]
// triax_import --to-lammps sample.h5 --out FILE.data
// triax_import --sort sample.h5 --out sorted.h5
// triax_import --tile sample.h5 --factors KxKyKz --out tiled.h5
//
// Brings a packing made by LAMMPS (a data file of atom_style sphere, units
// si; io/lammps_data_file.h) into a sample file that triax_run, the rig and
// triax_bench load (`particles: {sample: ...}`), and the reverse (used by
// bench/lammps_side_by_side.sh). The density comes from the data file; E, nu,
// mu default to 70 GPa, 0.3, 0.5; OD damping ratio default 0.02. The
// imported sample has no contact history (a data file holds none); above
// 1536 particles it is stored in slab order (dem::order_new_specimen).
// --sort stores a sample file's state in slab order (dem::spatial_sort,
// at any size): the same packing, contacts and metadata, for samples
// written before session 14 or by other tools (the shipped
// dense_4000.h5 and loose_4000.h5 were re-stored with it). Do not sort a
// state that a protocol is meant to continue bit for bit.
// --tile stores kx x ky x kz periodic copies of a sample (dem::tile_periodic:
// the same state, void ratio, contacts per particle and stress, with the
// contact histories carried over; above 1536 particles in slab order, as any
// new specimen), as a larger sample of the same packing (e.g. 12 000
// spheres from dense_1000.h5 with 3x2x2, for bench/lammps_side_by_side.sh
// --tile); --factors K alone means K x K x K. The metadata are the
// source's, but for who made it and the description, which names the source.
// Prints a summary (particles, void ratio, mean stress, contacts per
// particle of the first step). Exit codes: 0 done, 2 bad input (one line
// naming the file and line, or the flag).
#include <array>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>

#include "virtual_triaxial/dem/periodic_tiling.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/dem/spatial_sort.h"
#include "virtual_triaxial/io/lammps_data_file.h"
#include "virtual_triaxial/io/sample_file.h"

namespace {

int usage(const std::string& msg) {
  if (!msg.empty()) std::cerr << "triax_import: " << msg << "\n";
  std::cerr << "usage: triax_import --lammps FILE.data --out sample.h5 [--young-modulus PA] [--poisson-ratio NU]\n"
               "                    [--friction MU] [--damping-ratio XI]\n"
               "       triax_import --to-lammps sample.h5 --out FILE.data\n"
               "       triax_import --sort sample.h5 --out sorted.h5\n"
               "       triax_import --tile sample.h5 --factors KxKyKz --out tiled.h5\n";
  return 2;
}

/// Particles, void ratio, mean stress and contacts per particle of the
/// first step of a copy of `st` (st itself is stored unstepped); throws when
/// that step fails.
void print_state(const vt::dem::SimulationState& st) {
  vt::dem::Simulation sim(st);
  if (!sim.step(true)) throw std::runtime_error("first step failed: " + sim.failure());
  const vt::dem::Measures m = sim.measures();
  std::printf("particles: %zu\nvoid_ratio: %.4f\nmean_stress_pa: %.1f\ncontacts_per_particle: %.3f\n",
              st.particles.size(), m.void_ratio, m.p,
              static_cast<double>(m.contacts) / static_cast<double>(st.particles.size()));
}

bool number(const char* text, double& out) {
  if (!text) return false;
  char* end = nullptr;
  out = std::strtod(text, &end);
  return *text && *end == '\0';
}

}  // namespace

int main(int argc, char** argv) {
  std::string lammps, to_lammps, sort, tile, out;
  std::optional<std::array<int, 3>> factors;
  vt::dem::Material mat;
  double xi = 0.02;
  for (int a = 1; a < argc; ++a) {
    const std::string k = argv[a];
    const char* v = a + 1 < argc ? argv[a + 1] : nullptr;
    double x = 0;
    if (k == "--lammps" && v) lammps = v;
    else if (k == "--to-lammps" && v) to_lammps = v;
    else if (k == "--sort" && v) sort = v;
    else if (k == "--tile" && v) tile = v;
    else if (k == "--factors") {
      factors = v ? vt::dem::parse_tile_factors(v) : std::nullopt;
      if (!factors)
        return usage(vt::dem::tile_factors_usage("--factors") + ", " +
                     (v ? "not '" + std::string(v) + "'" : std::string("and got no value")));
    }
    else if (k == "--out" && v) out = v;
    else if (k == "--young-modulus" && number(v, x)) mat.young = x;
    else if (k == "--poisson-ratio" && number(v, x)) mat.poisson = x;
    else if (k == "--friction" && number(v, x)) mat.friction = x;
    else if (k == "--damping-ratio" && number(v, x) && x >= 0) xi = x;
    else if (k == "-h" || k == "--help") return usage("");
    else return usage(k + ": unknown flag or missing/invalid value");
    ++a;
  }
  if (out.empty() || (!lammps.empty()) + (!to_lammps.empty()) + (!sort.empty()) + (!tile.empty()) != 1)
    return usage("give --out and exactly one of --lammps, --to-lammps, --sort, --tile");
  if (tile.empty() == factors.has_value()) return usage("--factors goes with --tile, and --tile needs it");
  const std::string bad = mat.validate();
  if (!bad.empty()) return usage(bad);
  try {
    if (!to_lammps.empty()) {
      vt::io::write_lammps_data(out, vt::io::read_sample(to_lammps));
      std::cout << "triax_import: wrote " << out << "\n";
      return 0;
    }
    if (!sort.empty()) {
      vt::io::SampleMetadata meta;
      vt::dem::SimulationState st = vt::io::read_sample(sort, &meta);
      vt::dem::spatial_sort(st);
      vt::io::write_sample(out, st, meta);
      std::printf("particles: %zu\nsorted: slab order\nwrote: %s\n", st.particles.size(), out.c_str());
      return 0;
    }
    if (!tile.empty()) {
      vt::io::SampleMetadata meta;
      const auto& k = *factors;
      vt::dem::SimulationState st = vt::dem::tile_periodic(vt::io::read_sample(tile, &meta), k[0], k[1], k[2]);
      vt::dem::order_new_specimen(st);  // a new specimen: slab order above 1536 particles
      const std::string by = std::to_string(k[0]) + "x" + std::to_string(k[1]) + "x" + std::to_string(k[2]);
      meta.created_by = "triax_import --tile " + tile + " --factors " + by;
      meta.description = "periodic copies " + by + " of " + tile + (meta.description.empty() ? "" : ": ") +
                         meta.description;
      print_state(st);
      vt::io::write_sample(out, st, meta);
      std::printf("tile: %s\nwrote: %s\n", by.c_str(), out.c_str());
      return 0;
    }
    vt::dem::SimulationSettings settings;
    settings.damping = vt::dem::MassDamping(vt::dem::DampingModel::OD, xi);
    vt::dem::SimulationState st = vt::io::read_lammps_data(lammps, mat, settings);
    vt::dem::order_new_specimen(st);  // a new specimen
    print_state(st);
    vt::io::SampleMetadata meta;
    meta.software_version = "virtual_triaxial 0.1.0";
    meta.created_by = "triax_import --lammps " + lammps;
    meta.description = "imported from a LAMMPS data file (no contact history)";
    vt::io::write_sample(out, st, meta);
    std::printf("wrote: %s\n", out.c_str());
  } catch (const std::exception& e) {
    std::cerr << "triax_import: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
