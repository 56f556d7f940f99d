// triax_snapshot SAMPLE.h5 [--out DIR]
//
// A saved sample (io/sample_file.h) as the VTK snapshot files that runs
// write (io/vtk_snapshot_writer.h), so it opens in ParaView as it is:
// DIR/particles.pvd, contacts.pvd, cell.pvd (one snapshot, index 0). The
// contact forces come from one force evaluation of the saved state at
// dt = 0 (dem::SpecimenSnapshot::from_state). DIR defaults to the sample's
// path without .h5 plus "_vtk". Last stdout line: JSON with the particle and
// contact counts, the total normal force [N] and the mean stress p [Pa] of
// the contact network (Love-Weber, eq. 127).
// Exit codes: 0 written, 2 bad input (unreadable sample, unwritable DIR).
#include <cstdio>
#include <exception>
#include <string>

#include "virtual_triaxial/dem/specimen_snapshot.h"
#include "virtual_triaxial/io/sample_file.h"
#include "virtual_triaxial/io/vtk_snapshot_writer.h"

namespace {

int usage(const char* msg) {
  std::fprintf(stderr, "triax_snapshot: %s\nusage: triax_snapshot SAMPLE.h5 [--out DIR]\n", msg);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string sample, out;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    if (s == "--out" && i + 1 < argc) out = argv[++i];
    else if (s == "-h" || s == "--help") return usage("help"), 0;
    else if (!s.empty() && s[0] == '-') return usage(("unknown option " + s).c_str());
    else if (sample.empty()) sample = s;
    else return usage(("unexpected argument " + s).c_str());
  }
  if (sample.empty()) return usage("missing SAMPLE.h5");
  if (out.empty()) {
    const bool h5 = sample.size() > 3 && sample.compare(sample.size() - 3, 3, ".h5") == 0;
    out = (h5 ? sample.substr(0, sample.size() - 3) : sample) + "_vtk";
  }
  try {
    const vt::dem::SimulationState state = vt::io::read_sample(sample);
    const vt::dem::SpecimenSnapshot snap = vt::dem::SpecimenSnapshot::from_state(state);
    vt::io::VtkSnapshotSeries series(out);
    series.write(snap, "sample " + sample);
    std::fprintf(stderr, "triax_snapshot: %zu particles, %zu contacts -> %s/particles.pvd, contacts.pvd, cell.pvd\n",
                 snap.position.size(), snap.contacts.size(), out.c_str());
    std::printf("{\"particles\": %zu, \"contacts\": %zu, \"total_normal_force\": %.17g, \"p\": %.17g, \"out\": \"%s\"}\n",
                snap.position.size(), snap.contacts.size(), snap.total_normal_force(), snap.stress.trace() / 3.0,
                out.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "triax_snapshot: error: %s\n", e.what());
    return 2;
  }
  return 0;
}
