// Specimen snapshots (dem/specimen_snapshot.h) and their VTK series
// (io/vtk_snapshot_writer.h): the contact network read from the core's pair
// states reproduces the run's own measures; a saved state gives the same
// normal forces as the run's first evaluation of it (to the rounding of F - F_t); the files are complete,
// round-trip every double and replace an earlier series.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/dem/specimen_snapshot.h"
#include "virtual_triaxial/io/sample_file.h"
#include "virtual_triaxial/io/vtk_snapshot_writer.h"

namespace fs = std::filesystem;
using namespace vt::dem;

namespace {

const std::string kSpheres = std::string(VT_SOURCE_DIR) + "/tests/data/sample_200_100kPa.h5";
const std::string kSpheroids = std::string(VT_SOURCE_DIR) + "/config/samples/dense_1000_spheroid.h5";

/// A sheared sphere sample, last step measured. The last step has no
/// affine motion, so the branch vectors move by |v| dt only after the
/// force evaluation.
Simulation sheared_spheres() {
  Simulation sim(vt::io::read_sample(kSpheres));
  const double rate = 2e-5 / sim.time_scale().t0;  // eps' = 2e-5: contacts slide, the packing stays jammed
  sim.set_strain_rates({0.5 * rate, 0.5 * rate, -rate});
  sim.run(300);
  sim.set_strain_rates({0, 0, 0});
  sim.step(true);
  return sim;
}

/// Values of the DataArray `name` in a VTK XML document.
std::vector<double> data_array(const std::string& doc, const std::string& name) {
  const std::string key = "Name=\"" + name + "\"";
  const std::size_t at = doc.find(key);
  if (at == std::string::npos) return {};
  const std::size_t start = doc.find('>', at) + 1, end = doc.find("</DataArray>", start);
  std::istringstream in(doc.substr(start, end - start));
  std::vector<double> v;
  for (std::string tok; in >> tok;) v.push_back(std::strtod(tok.c_str(), nullptr));
  return v;
}

}  // namespace

TEST(SpecimenSnapshot, ContactNetworkReproducesTheRunsMeasures) {
  const Simulation sim = sheared_spheres();
  const Measures m = sim.measures();
  const SpecimenSnapshot s = SpecimenSnapshot::of(sim);
  ASSERT_EQ(s.position.size(), sim.particles().size());
  EXPECT_EQ(static_cast<std::int64_t>(s.contacts.size()), m.contacts);
  std::int64_t sliding = 0;
  for (const SnapshotContact& c : s.contacts) sliding += c.sliding ? 1 : 0;
  EXPECT_GT(m.sliding_contacts, 0);
  EXPECT_EQ(sliding, m.sliding_contacts);
  // Contact counts and idle flags: the measures' coordination number and idle mass fraction.
  std::int64_t ends = 0, active = 0;
  double idle_mass = 0, mass = 0;
  for (std::size_t i = 0; i < s.position.size(); ++i) {
    ends += s.contact_count[i];
    mass += sim.particles().mass[i];
    if (s.idle[i]) idle_mass += sim.particles().mass[i];
    else ++active;
  }
  EXPECT_EQ(ends, 2 * m.contacts);
  EXPECT_DOUBLE_EQ(idle_mass / mass, m.idle_mass_fraction);
  EXPECT_GT(active, 0) << m.contacts << " contacts, Z " << m.raw_coordination_number << ", p " << m.p;
  // Love-Weber (eq. 127) from the snapshot: the run's stress. The branch
  // vectors are one step newer than the forces: a relative difference of
  // order |v| dt / R.
  Mat3 lw;
  for (const SnapshotContact& c : s.contacts) {
    const Vec3 f = c.normal_force + c.tangential_force;
    const double b[3] = {c.branch.x, c.branch.y, c.branch.z}, fv[3] = {f.x, f.y, f.z};
    for (int a = 0; a < 3; ++a)
      for (int k = 0; k < 3; ++k) lw.m[a][k] += b[a] * fv[k];
  }
  const double v = sim.cell().volume();
  for (int a = 0; a < 3; ++a)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(0.5 * (lw.m[a][k] + lw.m[k][a]) / v, m.stress.m[a][k], 1e-5 * m.p) << a << k;
  // Spheres: the normal force lies along the branch vector (of one step
  // later: measured angles up to 1.6e-6 rad).
  for (const SnapshotContact& c : s.contacts)
    EXPECT_LT(norm(cross(c.normal_force, c.branch)), 1e-5 * norm(c.normal_force) * norm(c.branch));
}

TEST(SpecimenSnapshot, SavedStateGivesTheNormalForcesOfItsFirstEvaluation) {
  for (const std::string& path : {kSpheres, kSpheroids}) {
    SCOPED_TRACE(path);
    const SimulationState state = vt::io::read_sample(path);
    const SpecimenSnapshot saved = SpecimenSnapshot::from_state(state);
    Simulation sim(state);
    // Not stepped yet: of() falls back to the saved state's evaluation.
    const SpecimenSnapshot before = SpecimenSnapshot::of(sim);
    ASSERT_EQ(before.contacts.size(), saved.contacts.size());
    ASSERT_TRUE(sim.step(true));
    const SpecimenSnapshot run = SpecimenSnapshot::of(sim);
    ASSERT_EQ(run.contacts.size(), saved.contacts.size());
    ASSERT_GT(saved.contacts.size(), saved.position.size());  // a jammed sample: Z > 2
    for (std::size_t k = 0; k < saved.contacts.size(); ++k) {
      const SnapshotContact &a = saved.contacts[k], &b = run.contacts[k];
      ASSERT_EQ(saved.id[static_cast<std::size_t>(a.i)], run.id[static_cast<std::size_t>(b.i)]);
      ASSERT_EQ(saved.id[static_cast<std::size_t>(a.j)], run.id[static_cast<std::size_t>(b.j)]);
      EXPECT_EQ(a.overlap, b.overlap);
      // F_n = F - F_t: exact up to the rounding of that difference (the
      // springs differ by the step's increment).
      const double scale = norm(a.normal_force) + norm(a.tangential_force);
      EXPECT_NEAR(norm(a.normal_force), norm(b.normal_force), 1e-15 * scale);
    }
    // The first step's stress (the run's own number) from the saved state's network.
    EXPECT_NEAR(saved.stress.trace(), sim.current_stress().trace(), 1e-3 * sim.current_stress().trace());
  }
}

TEST(VtkSnapshotSeries, WritesCompleteCollectionsThatRoundTripEveryDouble) {
  const fs::path dir = vt::test::scratch_dir("vtk_series") / "specimen";
  const Simulation sim = sheared_spheres();
  const SpecimenSnapshot s = SpecimenSnapshot::of(sim);
  {
    vt::io::VtkSnapshotSeries series(dir.string());
    series.write(s, "first, with a comma");
    series.write(s, "second");
    EXPECT_EQ(series.count(), 2u);
  }
  for (const char* f : {"particles_000000.vtp", "particles_000001.vtp", "contacts_000001.vtp", "cell_000001.vtp",
                        "particles.pvd", "contacts.pvd", "cell.pvd", "snapshots.csv"})
    EXPECT_TRUE(fs::is_regular_file(dir / f)) << f;
  const std::string pvd = vt::test::slurp(dir / "contacts.pvd");
  EXPECT_NE(pvd.find("file=\"contacts_000000.vtp\""), std::string::npos);
  EXPECT_NE(pvd.find("file=\"contacts_000001.vtp\""), std::string::npos);
  const std::string csv = vt::test::slurp(dir / "snapshots.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3);
  EXPECT_NE(csv.find("first  with a comma"), std::string::npos);
  // Numbers in the files read back to the same doubles.
  const std::string particles = vt::test::slurp(dir / "particles_000001.vtp");
  const std::vector<double> radius = data_array(particles, "radius");
  ASSERT_EQ(radius.size(), s.radius.size());
  for (std::size_t i = 0; i < radius.size(); ++i) EXPECT_EQ(radius[i], s.radius[i]);
  const std::vector<double> fn = data_array(vt::test::slurp(dir / "contacts_000001.vtp"), "normal_force_vector");
  ASSERT_EQ(fn.size(), 3 * s.contacts.size());
  for (std::size_t k = 0; k < s.contacts.size(); ++k) EXPECT_EQ(fn[3 * k + 2], s.contacts[k].normal_force.z);
  // A new series in the same directory replaces the old one.
  {
    vt::io::VtkSnapshotSeries series(dir.string());
    series.write(s, "only");
  }
  EXPECT_FALSE(fs::exists(dir / "particles_000001.vtp"));
  EXPECT_TRUE(fs::exists(dir / "particles_000000.vtp"));
  EXPECT_EQ(vt::test::slurp(dir / "particles.pvd").find("particles_000001"), std::string::npos);
}

TEST(VtkSnapshotSeries, UnwritableDirectoryIsAnErrorNamingIt) {
  try {
    vt::io::VtkSnapshotSeries series("/proc/vt_no_such_dir/specimen");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/proc/vt_no_such_dir/specimen"), std::string::npos) << e.what();
  }
}
