// LAMMPS data files (io/lammps_data_file.h): a shipped packing round-trips
// through a data file (ids, radii and cell exactly, positions to round-off of
// the cell size), a triclinic box is read as its H, and malformed files are
// refused with the file and the line named.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "virtual_triaxial/io/lammps_data_file.h"
#include "virtual_triaxial/io/sample_file.h"

namespace fs = std::filesystem;
using namespace vt;

namespace {

std::string temp_path(const std::string& name) {
  return (fs::temp_directory_path() / ("vt_lammps_" + std::to_string(::getpid()) + "_" + name)).string();
}

std::string write_text(const std::string& name, const std::string& text) {
  const std::string p = temp_path(name);
  std::ofstream(p) << text;
  return p;
}

/// The message of the exception read_lammps_data throws ("" if none).
std::string refusal(const std::string& text) {
  const std::string p = write_text("bad.data", text);
  try {
    io::read_lammps_data(p, dem::Material{});
  } catch (const std::runtime_error& e) {
    fs::remove(p);
    return e.what();
  }
  fs::remove(p);
  return "";
}

const char* kHeader =
    "comment\n\n2 atoms\n1 atom types\n0 0.01 xlo xhi\n0 0.01 ylo yhi\n0 0.01 zlo zhi\n\nAtoms # sphere\n\n";

}  // namespace

TEST(LammpsDataFile, ShippedPackingRoundTrips) {
  const dem::SimulationState s = io::read_sample((fs::path(VT_SOURCE_DIR) / "config/samples/dense_1000.h5").string());
  const std::string p = temp_path("roundtrip.data");
  io::write_lammps_data(p, s);
  const dem::SimulationState r = io::read_lammps_data(p, s.settings.material, s.settings);
  fs::remove(p);
  ASSERT_EQ(r.particles.size(), s.particles.size());
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) EXPECT_EQ(r.h.m[a][b], s.h.m[a][b]);
  const dem::PeriodicCell cs(s.h, s.h), cr(r.h, r.h);
  const double edge = s.h.m[0][0];
  double worst = 0;
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    EXPECT_EQ(r.particles.id[i], s.particles.id[i]);
    EXPECT_EQ(r.particles.radius[i], s.particles.radius[i]);
    EXPECT_NEAR(r.particles.mass[i], s.particles.mass[i], 1e-14 * s.particles.mass[i]);
    // the same point of the periodic cell (minimum image of the difference)
    worst = std::max(worst, dem::norm(cs.branch(s.particles.frac[i], r.particles.frac[i])));
  }
  EXPECT_LT(worst, 1e-14 * edge);
  EXPECT_EQ(r.settings.material.density, s.settings.material.density);
}

TEST(LammpsDataFile, TriclinicBoxAndVelocities) {
  const std::string p = write_text("tri.data", std::string("c\n2 atoms\n1 atom types\n-1 1 xlo xhi\n0 3 ylo yhi\n"
                                                           "0 4 zlo zhi\n0.5 0.25 -0.5 xy xz yz\n\nAtoms # sphere\n\n"
                                                           "7 1 0.2 2000 0 1 1 0 0 0\n9 1 0.4 2000 1.5 2 3\n\n"
                                                           "Velocities\n\n9 1 2 3 4 5 6\n7 0 0 0 0 0 0\n"));
  const dem::SimulationState s = io::read_lammps_data(p, dem::Material{});
  fs::remove(p);
  EXPECT_EQ(s.h.m[0][0], 2.0);
  EXPECT_EQ(s.h.m[0][1], 0.5);
  EXPECT_EQ(s.h.m[0][2], 0.25);
  EXPECT_EQ(s.h.m[1][2], -0.5);
  EXPECT_EQ(s.particles.id[1], 8);  // atom-ID - 1
  EXPECT_EQ(s.particles.radius[1], 0.2);
  EXPECT_EQ(s.particles.velocity[1].y, 2.0);
  EXPECT_EQ(s.particles.omega[1].z, 6.0);
  const dem::PeriodicCell c(s.h, s.h);
  const dem::Vec3 x = c.to_cartesian(s.particles.frac[0]) + dem::Vec3{-1, 0, 0};
  EXPECT_NEAR(x.x, 0.0, 1e-15);
  EXPECT_NEAR(x.y, 1.0, 1e-15);
  EXPECT_NEAR(x.z, 1.0, 1e-15);
}

TEST(LammpsDataFile, MalformedFilesAreRefusedNamingTheLine) {
  EXPECT_NE(refusal(std::string(kHeader) + "1 1 0.002 2650 0 0 0\n2 1 0.002 2650 0.005 0\n").find(":12: Atoms (sphere) line needs 7 or 10 columns"),
            std::string::npos);
  EXPECT_NE(refusal(std::string(kHeader) + "1 1 0.002 2650 0 0 0\n2 1 -0.002 2650 0.005 0 0\n").find(":12: diameter: must be > 0"),
            std::string::npos);
  EXPECT_NE(refusal(std::string(kHeader) + "1 1 0.002 2650 0 0 0\n2 1 0.002 2650 0.005 zero 0\n").find(":12: y: 'zero' is not a finite number"),
            std::string::npos);
  EXPECT_NE(refusal(std::string(kHeader) + "1 1 0.002 2650 0 0 0\n1 1 0.002 2650 0.005 0 0\n").find(":12: atom-ID 1 appears twice"),
            std::string::npos);
  EXPECT_NE(refusal(std::string(kHeader) + "1 1 0.002 2650 0 0 0\n").find(":9: section 'Atoms' holds 1 lines, the header says 2"),
            std::string::npos);
  EXPECT_NE(refusal(std::string(kHeader) + "1 1 0.002 2650 0 0 0\n2 1 0.002 2000 0.005 0 0\n").find(":12: density: every atom"),
            std::string::npos);
  EXPECT_NE(refusal("c\n2 atoms\n0 0.01 xlo xhi\n0 0.01 ylo yhi\n0 0.01 zlo zhi\nAtoms # atomic\n").find(":6: Atoms section of another atom style"),
            std::string::npos);
  EXPECT_NE(refusal("c\n2 atoms\n0 0.01 xlo xhi\n0.01 0 ylo yhi\n").find(":4: yhi must exceed ylo"), std::string::npos);
  EXPECT_NE(refusal("c\n2 atoms\n5 bonds\n").find(":3: bonds: not supported"), std::string::npos);
  EXPECT_NE(refusal("c\n2 atoms\n0 0.01 xlo xhi\n0 0.01 ylo yhi\n\nAtoms # sphere\n").find(": header: 'zlo zhi' missing"),
            std::string::npos);
  EXPECT_NE(refusal("c\n2 atoms\nextra stuff here\n").find(":3: unknown header line"), std::string::npos);
}
