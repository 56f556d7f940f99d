// Sample file (io/sample_file.h): bit-exact round trip, units on every
// dataset, atomic writes, validation errors that name the dataset, and a
// restart through the file that continues bit for bit.
#include <gtest/gtest.h>

#include <dirent.h>
#include <hdf5.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "support/scenes.h"
#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/io/sample_file.h"

using namespace vt::dem;
using vt::io::read_sample;
using vt::io::SampleMetadata;
using vt::io::write_sample;

namespace {

// ---- helpers ---------------------------------------------------------------------

bool same(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }
bool same(const Vec3& a, const Vec3& b) { return same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z); }
bool same(const Quaternion& a, const Quaternion& b) {
  return same(a.w, b.w) && same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z);
}
bool same(const Mat3& a, const Mat3& b) { return std::memcmp(&a, &b, sizeof(Mat3)) == 0; }

class TempDir {
 public:
  TempDir() {
    std::string tmpl = ::testing::TempDir() + "vt_sample_XXXXXX";
    std::vector<char> buf(tmpl.begin(), tmpl.end());
    buf.push_back('\0');
    const char* d = ::mkdtemp(buf.data());
    if (d == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = d;
  }
  ~TempDir() {
    for (const std::string& f : files()) {
      const std::string p = path_ + "/" + f;
      struct stat st {};
      if (::stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
        ::rmdir(p.c_str());
      else
        ::unlink(p.c_str());
    }
    ::rmdir(path_.c_str());
  }
  std::string file(const std::string& name) const { return path_ + "/" + name; }
  std::set<std::string> files() const {
    std::set<std::string> out;
    if (DIR* d = ::opendir(path_.c_str())) {
      while (dirent* e = ::readdir(d))
        if (std::strcmp(e->d_name, ".") != 0 && std::strcmp(e->d_name, "..") != 0) out.insert(e->d_name);
      ::closedir(d);
    }
    return out;
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

/// A small hand-made state with awkward doubles in every field.
SimulationState make_state(std::size_t n_contacts = 2) {
  SimulationState s;
  Particles& p = s.particles;
  const double rho = 2650.0;
  p.add_sphere(10, 1e-3, rho, {0.1, 0.2, 0.3}, {0.1 + 0.2, -1e-7, 3.3e-300}, {1.0 / 3.0, 0, -2.5});
  p.add_sphere(11, 1.1e-3, rho, {0.7, 0.1 + 0.2, 0.9}, {}, {}, 0);
  p.add_sphere(15, 0.9e-3, rho, {std::nextafter(1.0, 0.0), 0.0, 0.5}, {1e-9, 2e-9, 3e-9}, {}, 2);
  p.add_sphere(3, 1.2e-3 / 3.0, rho, {0.33, 0.66, 0.99}, {-0.0, 0, 0}, {std::sqrt(2.0), 0, 0});
  p.add_sphere(42, 0.95e-3, rho, {4.9e-324, 0.25, 0.75});
  // Make one particle a spheroid with a non-trivial orientation.
  p.shape[3] = Shape::Spheroid;
  p.semi_axes[3] = {1.2e-3, 0.4e-3 * 1.1, 0.4e-3 * 1.1};
  const double t = 0.3;
  p.orientation[3] = {std::cos(t), std::sin(t) / std::sqrt(3.0), std::sin(t) / std::sqrt(3.0),
                      std::sin(t) / std::sqrt(3.0)};
  p.inertia[3] = {1.0 / 7.0 * 1e-12, 2.0 / 7.0 * 1e-12, 2.0 / 7.0 * 1e-12};

  s.h = Mat3::identity();
  s.h.m[0][0] = 0.01 + 1e-17;
  s.h.m[0][1] = 1e-4 / 3.0;
  s.h.m[1][1] = 0.011;
  s.h.m[2][0] = -2e-5;
  s.h.m[2][2] = 0.1 + 0.2 - 0.29;
  s.h_reference = Mat3::diagonal({0.012, 0.012, 0.012 + 1e-16});
  s.velocity_gradient = Mat3::diagonal({0.5e-3, 0.5e-3, -1e-3 / 3.0});
  s.velocity_gradient.m[0][1] = 1e-300;

  const std::vector<ContactHistory> c = {{10, 11, {0.1 + 0.2, -1e-12, 7.0 / 3.0}}, {3, 42, {1e-310, 0.0, -0.0}}};
  s.contacts.assign(c.begin(), c.begin() + static_cast<std::ptrdiff_t>(n_contacts));

  s.time = 1.0 / 3.0 * 1e-3;
  s.step = 123456789012LL;
  s.energy.boundary_work = 0.1 + 0.2;
  s.energy.damping = 1e-20 / 3.0;
  s.energy.friction = 2.0 / 3.0;
  s.energy.kinetic_translational = 5e-9;
  s.energy.kinetic_rotational = 7e-11 / 9.0;
  s.energy.elastic = std::sqrt(2.0) * 1e-6;
  s.energy.kinetic_reference = 1e-15;
  s.energy.elastic_reference = 3e-7 / 7.0;
  s.energy.has_reference = true;

  s.settings.material = {2650.0 + 1.0 / 3.0, 70e9 / 3.0, 0.3 - 1e-17, 0.5 + 1e-16};
  s.settings.damping = MassDamping(DampingModel::ND, 0.1 + 0.2);
  s.settings.time_step_ratio = 0.3 / 3.0;
  s.settings.skin_ratio = 0.15 + 1e-16;
  s.settings.check_interval = 77;
  s.settings.limits.max_overlap_ratio = 0.1 / 3.0;
  s.settings.limits.max_energy_error = 0.5 + 0.1;
  return s;
}

SampleMetadata make_meta() {
  SampleMetadata m;
  m.seed = 0xFFFFFFFFFFFFFFF1ULL;
  m.friction_during_shrinkage = 0.1 / 3.0;
  m.target_pressure = std::numeric_limits<double>::quiet_NaN();
  m.initial_void_ratio = 0.6 + 1e-16;
  m.software_version = "0.1.0";
  m.created_by = "test_sample_file (ünïcode)";
  m.description = "";
  return m;
}

void expect_same_state(const SimulationState& a, const SimulationState& b) {
  const Particles& p = a.particles;
  const Particles& q = b.particles;
  ASSERT_EQ(p.size(), q.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    SCOPED_TRACE("particle " + std::to_string(i));
    EXPECT_EQ(p.id[i], q.id[i]);
    EXPECT_EQ(p.shape[i], q.shape[i]);
    EXPECT_TRUE(same(p.radius[i], q.radius[i]));
    EXPECT_TRUE(same(p.semi_axes[i], q.semi_axes[i]));
    EXPECT_TRUE(same(p.mass[i], q.mass[i]));
    EXPECT_TRUE(same(p.inertia[i], q.inertia[i]));
    EXPECT_TRUE(same(p.frac[i], q.frac[i]));
    EXPECT_TRUE(same(p.velocity[i], q.velocity[i]));
    EXPECT_TRUE(same(p.omega[i], q.omega[i]));
    EXPECT_TRUE(same(p.orientation[i], q.orientation[i]));
    EXPECT_EQ(p.material[i], q.material[i]);
  }
  ASSERT_EQ(a.contacts.size(), b.contacts.size());
  for (std::size_t k = 0; k < a.contacts.size(); ++k) {
    EXPECT_EQ(a.contacts[k].id_a, b.contacts[k].id_a);
    EXPECT_EQ(a.contacts[k].id_b, b.contacts[k].id_b);
    EXPECT_TRUE(same(a.contacts[k].spring, b.contacts[k].spring));
  }
  EXPECT_TRUE(same(a.h, b.h));
  EXPECT_TRUE(same(a.h_reference, b.h_reference));
  EXPECT_TRUE(same(a.velocity_gradient, b.velocity_gradient));
  EXPECT_TRUE(same(a.time, b.time));
  EXPECT_EQ(a.step, b.step);
  for (double EnergyBudget::*f : {&EnergyBudget::boundary_work, &EnergyBudget::damping, &EnergyBudget::friction,
                                  &EnergyBudget::kinetic_translational, &EnergyBudget::kinetic_rotational,
                                  &EnergyBudget::elastic, &EnergyBudget::kinetic_reference,
                                  &EnergyBudget::elastic_reference})
    EXPECT_TRUE(same(a.energy.*f, b.energy.*f));
  EXPECT_EQ(a.energy.has_reference, b.energy.has_reference);
  for (double Material::*f : {&Material::density, &Material::young, &Material::poisson, &Material::friction})
    EXPECT_TRUE(same(a.settings.material.*f, b.settings.material.*f));
  const SimulationSettings& s = a.settings;
  const SimulationSettings& t = b.settings;
  EXPECT_EQ(s.damping.model(), t.damping.model());
  EXPECT_TRUE(same(s.damping.ratio(), t.damping.ratio()));
  EXPECT_TRUE(same(s.time_step_ratio, t.time_step_ratio) && same(s.skin_ratio, t.skin_ratio));
  EXPECT_EQ(s.check_interval, t.check_interval);
  EXPECT_TRUE(same(s.limits.max_overlap_ratio, t.limits.max_overlap_ratio));
  EXPECT_TRUE(same(s.limits.max_energy_error, t.limits.max_energy_error));
}

/// Error message of read_sample(path), "" if it succeeds.
std::string read_error(const std::string& path) {
  try {
    read_sample(path);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

/// Open the file read-write and apply `fn` to it (raw HDF5, to damage files).
void edit(const std::string& path, const std::function<void(hid_t)>& fn) {
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  fn(f);
  ASSERT_GE(H5Fclose(f), 0);
}

/// Replace dataset `name` by a 1-D float64 dataset holding `values`.
void replace_doubles(hid_t f, const char* name, const std::vector<double>& values) {
  ASSERT_GE(H5Ldelete(f, name, H5P_DEFAULT), 0);
  const hsize_t n = values.size();
  const hid_t space = H5Screate_simple(1, &n, nullptr);
  const hid_t ds = H5Dcreate2(f, name, H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(ds, 0);
  ASSERT_GE(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
  H5Dclose(ds);
  H5Sclose(space);
}

/// Every dataset of a file and its `units` attribute ("<none>" if absent).
std::map<std::string, std::string> scan_units(const std::string& path) {
  std::map<std::string, std::string> out;
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(f, 0);
  const H5L_iterate_t visit = [](hid_t group, const char* name, const H5L_info_t*, void* data) -> herr_t {
    const hid_t obj = H5Oopen(group, name, H5P_DEFAULT);
    if (obj < 0) return -1;
    if (H5Iget_type(obj) == H5I_DATASET) {
      std::string units = "<none>";
      if (H5Aexists(obj, "units") > 0) {
        const hid_t attr = H5Aopen(obj, "units", H5P_DEFAULT);
        const hid_t type = H5Aget_type(attr);
        char* p = nullptr;
        if (H5Tis_variable_str(type) > 0 && H5Aread(attr, type, &p) >= 0 && p) units = p;
        H5free_memory(p);
        H5Tclose(type);
        H5Aclose(attr);
      }
      (*static_cast<std::map<std::string, std::string>*>(data))[std::string("/") + name] = units;
    }
    H5Oclose(obj);
    return 0;
  };
  EXPECT_GE(H5Lvisit(f, H5_INDEX_NAME, H5_ITER_INC, visit, &out), 0);
  H5Fclose(f);
  return out;
}

}  // namespace

// ---- round trip ----------------------------------------------------------------------

TEST(SampleFile, RoundTripIsBitExact) {
  TempDir dir;
  const std::string path = dir.file("sample.h5");
  const SimulationState s = make_state();
  const SampleMetadata meta = make_meta();
  write_sample(path, s, meta);
  SampleMetadata got;
  const SimulationState r = read_sample(path, &got);
  expect_same_state(s, r);
  EXPECT_EQ(got.seed, meta.seed);
  EXPECT_TRUE(same(got.friction_during_shrinkage, meta.friction_during_shrinkage));
  EXPECT_TRUE(same(got.target_pressure, meta.target_pressure));  // NaN, bit for bit
  EXPECT_TRUE(std::isnan(got.target_pressure));
  EXPECT_TRUE(same(got.initial_void_ratio, meta.initial_void_ratio));
  EXPECT_EQ(got.software_version, meta.software_version);
  EXPECT_EQ(got.created_by, meta.created_by);
  EXPECT_EQ(got.description, meta.description);
  // Writing the read state again gives the same state again.
  write_sample(path, r, got);
  expect_same_state(s, read_sample(path));
}

TEST(SampleFile, ReaderUsesFractionalPositionsNotCartesian) {
  TempDir dir;
  const std::string path = dir.file("sample.h5");
  const SimulationState s = make_state();
  write_sample(path, s, make_meta());
  // Zero the Cartesian positions: the restart must not notice.
  edit(path, [](hid_t f) {
    const hid_t ds = H5Dopen2(f, "/particles/position", H5P_DEFAULT);
    const std::vector<double> zeros(15, 0.0);
    ASSERT_GE(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, zeros.data()), 0);
    H5Dclose(ds);
  });
  const SimulationState r = read_sample(path);
  for (std::size_t i = 0; i < s.particles.size(); ++i) EXPECT_TRUE(same(s.particles.frac[i], r.particles.frac[i]));
}

TEST(SampleFile, EmptyContactsWork) {
  TempDir dir;
  const std::string path = dir.file("sample.h5");
  const SimulationState s = make_state(0);
  write_sample(path, s, SampleMetadata{});
  SampleMetadata got;
  const SimulationState r = read_sample(path, &got);
  EXPECT_TRUE(r.contacts.empty());
  expect_same_state(s, r);
  EXPECT_TRUE(std::isnan(got.target_pressure));  // defaults are NaN = not applicable
  EXPECT_EQ(got.seed, 0u);
}

TEST(SampleFile, RootAttributesAndLayout) {
  TempDir dir;
  const std::string path = dir.file("sample.h5");
  write_sample(path, make_state(), make_meta());
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const hid_t a = H5Aopen(f, "format_version", H5P_DEFAULT);
  std::int64_t version = 0;
  H5Aread(a, H5T_NATIVE_INT64, &version);
  H5Aclose(a);
  EXPECT_EQ(version, 1);
  // Cartesian positions are H s.
  const hid_t ds = H5Dopen2(f, "/particles/position", H5P_DEFAULT);
  std::vector<double> x(15);
  H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, x.data());
  H5Dclose(ds);
  H5Fclose(f);
  const SimulationState s = make_state();
  const Vec3 x1 = s.h * s.particles.frac[1];
  EXPECT_TRUE(same(x[3], x1.x) && same(x[4], x1.y) && same(x[5], x1.z));
  const std::map<std::string, std::string> u = scan_units(path);
  EXPECT_EQ(u.at("/particles/radius"), "m");
  EXPECT_EQ(u.at("/particles/inertia"), "kg m^2");
  EXPECT_EQ(u.at("/contacts/spring"), "N");
  EXPECT_EQ(u.at("/cell/velocity_gradient"), "1/s");
  EXPECT_EQ(u.at("/material/young_modulus"), "Pa");
  EXPECT_EQ(u.at("/energy/elastic"), "J");
  EXPECT_EQ(u.at("/preparation/target_pressure"), "Pa");
}

TEST(SampleFile, EveryDatasetHasUnits) {
  TempDir dir;
  const std::string path = dir.file("sample.h5");
  write_sample(path, make_state(), make_meta());
  const std::map<std::string, std::string> u = scan_units(path);
  // 12 particle + 3 contact + 5 cell + 4 material + 6 settings + 9 energy + 4 preparation
  EXPECT_EQ(u.size(), 43u);
  for (const auto& kv : u) EXPECT_TRUE(kv.second != "<none>" && !kv.second.empty()) << kv.first << " has no units";
}

// ---- atomic writes ----------------------------------------------------------------------

TEST(SampleFile, WriteLeavesNoTemporaryFile) {
  TempDir dir;
  write_sample(dir.file("sample.h5"), make_state(), make_meta());
  EXPECT_EQ(dir.files(), std::set<std::string>{"sample.h5"});
}

TEST(SampleFile, ExistingFileIsReplacedWhole) {
  TempDir dir;
  const std::string path = dir.file("sample.h5");
  write_sample(path, make_state(), make_meta());
  SimulationState small = make_state(0);
  small.particles.resize(2);
  small.step = 7;
  SampleMetadata meta2 = make_meta();
  meta2.description = "second";
  write_sample(path, small, meta2);
  SampleMetadata got;
  const SimulationState r = read_sample(path, &got);
  EXPECT_EQ(r.particles.size(), 2u);
  EXPECT_EQ(r.step, 7);
  EXPECT_EQ(got.description, "second");
  EXPECT_EQ(dir.files(), std::set<std::string>{"sample.h5"});
}

TEST(SampleFile, MissingDirectoryThrowsNamingThePath) {
  TempDir dir;
  const std::string path = dir.file("no/such/dir/sample.h5");
  try {
    write_sample(path, make_state(), make_meta());
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_TRUE(dir.files().empty());
}

TEST(SampleFile, FailedRenameRemovesTemporaryAndKeepsTarget) {
  TempDir dir;
  const std::string path = dir.file("target");
  ASSERT_EQ(::mkdir(path.c_str(), 0755), 0);  // rename onto a directory fails
  ASSERT_EQ(::mkdir((path + "/keep").c_str(), 0755), 0);
  try {
    write_sample(path, make_state(), make_meta());
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_EQ(dir.files(), std::set<std::string>{"target"});
  ::rmdir((path + "/keep").c_str());
}

TEST(SampleFile, InconsistentStateIsRefusedBeforeTouchingTheFile) {
  TempDir dir;
  const std::string path = dir.file("sample.h5");
  write_sample(path, make_state(), make_meta());
  SimulationState bad = make_state();
  bad.particles.radius.pop_back();
  try {
    write_sample(path, bad, make_meta());
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("particles.radius"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_sample(path).particles.size(), 5u);  // old file intact
  EXPECT_EQ(dir.files(), std::set<std::string>{"sample.h5"});
}

// ---- validation ----------------------------------------------------------------------------

TEST(SampleFile, MissingDatasetIsNamed) {
  TempDir dir;
  const std::string path = dir.file("sample.h5");
  for (const char* name : {"/particles/radius", "/particles/position_fractional", "/particles/orientation",
                           "/contacts/spring", "/cell/h", "/cell/step", "/material/density", "/settings/skin_ratio",
                           "/energy/elastic", "/preparation/seed"}) {
    SCOPED_TRACE(name);
    write_sample(path, make_state(), make_meta());
    edit(path, [&](hid_t f) { ASSERT_GE(H5Ldelete(f, name, H5P_DEFAULT), 0); });
    const std::string err = read_error(path);
    EXPECT_NE(err.find(path + ": " + name + ": missing"), std::string::npos) << err;
  }
  // A whole group.
  write_sample(path, make_state(), make_meta());
  edit(path, [](hid_t f) { ASSERT_GE(H5Ldelete(f, "/contacts", H5P_DEFAULT), 0); });
  EXPECT_NE(read_error(path).find("/contacts: missing"), std::string::npos) << read_error(path);
}

TEST(SampleFile, InconsistentLengthIsNamed) {
  TempDir dir;
  const std::string path = dir.file("sample.h5");
  write_sample(path, make_state(), make_meta());
  edit(path, [](hid_t f) { replace_doubles(f, "/particles/mass", {1, 2, 3, 4}); });
  const std::string err = read_error(path);
  EXPECT_NE(err.find("/particles/mass"), std::string::npos) << err;
  EXPECT_NE(err.find("/particles/id"), std::string::npos) << err;  // says where 5 came from
}

TEST(SampleFile, NegativeRadiusIsRejected) {
  TempDir dir;
  const std::string path = dir.file("sample.h5");
  write_sample(path, make_state(), make_meta());
  edit(path, [](hid_t f) { replace_doubles(f, "/particles/radius", {1e-3, 1e-3, -1e-3, 1e-3, 1e-3}); });
  const std::string err = read_error(path);
  EXPECT_NE(err.find("/particles/radius: entry [2]"), std::string::npos) << err;
}

TEST(SampleFile, WrongTypeIsRejected) {
  TempDir dir;
  const std::string path = dir.file("sample.h5");
  write_sample(path, make_state(), make_meta());
  edit(path, [](hid_t f) { replace_doubles(f, "/particles/id", {1, 2, 3, 4, 5}); });
  const std::string err = read_error(path);
  EXPECT_NE(err.find("/particles/id: wrong type"), std::string::npos) << err;
}

TEST(SampleFile, ContactWithUnknownParticleIsRejected) {
  TempDir dir;
  const std::string path = dir.file("sample.h5");
  SimulationState s = make_state();
  s.contacts[1].id_b = 99;
  write_sample(path, s, make_meta());
  const std::string err = read_error(path);
  EXPECT_NE(err.find("/contacts/id_b: entry [1] is 99"), std::string::npos) << err;
}

TEST(SampleFile, BadMaterialAndSettingsAreNamed) {
  TempDir dir;
  const std::string path = dir.file("sample.h5");
  SimulationState s = make_state();
  s.settings.material.poisson = 0.7;
  write_sample(path, s, make_meta());
  EXPECT_NE(read_error(path).find("/material/poisson_ratio"), std::string::npos) << read_error(path);
  s = make_state();
  s.settings.check_interval = 0;
  write_sample(path, s, make_meta());
  EXPECT_NE(read_error(path).find("/settings/check_interval"), std::string::npos) << read_error(path);
}

TEST(SampleFile, NotASampleFileIsRejected) {
  TempDir dir;
  const std::string path = dir.file("sample.h5");
  write_sample(path, make_state(), make_meta());
  edit(path, [](hid_t f) {
    ASSERT_GE(H5Adelete(f, "format"), 0);
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, 8);
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate2(f, "format", type, space, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(H5Awrite(a, type, "results"), 0);
    H5Aclose(a);
    H5Sclose(space);
    H5Tclose(type);
  });
  std::string err = read_error(path);
  EXPECT_NE(err.find("not a virtual_triaxial sample file"), std::string::npos) << err;
  EXPECT_NE(err.find("'results'"), std::string::npos) << err;

  const std::string text = dir.file("notes.txt");
  std::ofstream(text) << "hello\n";
  err = read_error(text);
  EXPECT_NE(err.find(text + ": not an HDF5 file"), std::string::npos) << err;

  const std::string missing = dir.file("missing.h5");
  err = read_error(missing);
  EXPECT_NE(err.find(missing), std::string::npos) << err;
}

TEST(SampleFile, NoHdf5HandlesLeakOnErrorPaths) {
  TempDir dir;
  const std::string path = dir.file("sample.h5");
  write_sample(path, make_state(), make_meta());
  edit(path, [](hid_t f) { replace_doubles(f, "/particles/radius", {1e-3, 1e-3, -1e-3, 1e-3, 1e-3}); });
  EXPECT_FALSE(read_error(path).empty());
  edit(path, [](hid_t f) { ASSERT_GE(H5Ldelete(f, "/cell/h", H5P_DEFAULT), 0); });
  EXPECT_FALSE(read_error(path).empty());
  EXPECT_ANY_THROW(write_sample(dir.file("no/dir/x.h5"), make_state(), make_meta()));
  // Every file and object opened by the library (and by this test) is closed.
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
}

// ---- restart through the file ----------------------------------------------------------------

TEST(SampleFile, RestartThroughFileContinuesBitForBit) {
  // Same recipe as test_restart: compress a cloud, then shear at constant volume.
  vt::test::CloudScene sc = vt::test::polydisperse_cloud(400, 1.8, 5);
  SimulationSettings settings = vt::test::undamped(0.3, 0.5);
  settings.damping = MassDamping(DampingModel::ND, 0.02);
  Simulation sim(std::move(sc.particles), sc.cell, settings);
  sim.set_strain_rates(Vec3{-1, -1, -1} * (4e-4 / sim.time_scale().t0));
  ASSERT_EQ(sim.run(1200), 1200) << sim.failure();
  const double rate = 2e-4 / sim.time_scale().t0;
  sim.set_strain_rates({0.5 * rate, 0.5 * rate, -rate});
  const SimulationState start = sim.state();
  ASSERT_GT(start.contacts.size(), 300u) << "the test needs a loaded contact network";

  TempDir dir;
  const std::string path = dir.file("checkpoint.h5");
  write_sample(path, start, SampleMetadata{});
  Simulation from_memory(start);
  Simulation from_file(read_sample(path));
  ASSERT_EQ(from_memory.run(300), 300) << from_memory.failure();
  ASSERT_EQ(from_file.run(300), 300) << from_file.failure();
  expect_same_state(from_memory.state(), from_file.state());
}
