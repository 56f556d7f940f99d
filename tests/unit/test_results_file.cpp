// Results file (io/results_file.h): series and summary round trip bit for
// bit, units on every dataset, atomic rewrite on flush, other tests' groups
// kept, foreign files never clobbered.
#include <gtest/gtest.h>

#include <dirent.h>
#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "virtual_triaxial/io/results_file.h"
#include "virtual_triaxial/io/sample_file.h"

using namespace vt::dem;
using vt::io::read_results_series;
using vt::io::read_summary_numbers;
using vt::io::read_summary_texts;
using vt::io::ResultsWriter;

namespace {

bool same(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }
bool same(const Vec3& a, const Vec3& b) { return same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z); }

class TempDir {
 public:
  TempDir() {
    std::string tmpl = ::testing::TempDir() + "vt_results_XXXXXX";
    std::vector<char> buf(tmpl.begin(), tmpl.end());
    buf.push_back('\0');
    const char* d = ::mkdtemp(buf.data());
    if (d == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = d;
  }
  ~TempDir() {
    for (const std::string& f : files()) ::unlink((path_ + "/" + f).c_str());
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

 private:
  std::string path_;
};

/// Measures with awkward, distinct values in every field.
Measures make_measures(int k) {
  const double f = 1.0 + k / 3.0;
  Measures m;
  m.time = 1e-6 * f + 1e-22;
  m.step = 1000LL * k + 7;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m.stress.m[r][c] = (0.1 + 0.2) * 1e5 * f + r * 1e3 / 7.0 + c * 1e-9;
  m.principal_stress = {3e5 * f, 2e5 / 3.0, 1e5 / 7.0};
  m.p = 2e5 * f / 3.0;
  m.q = 1e5 * f / 9.0;
  m.phi = std::asin(1.0 / 3.0) + k * 1e-17;
  m.strain = {-1e-3 / 3.0 * f, -1e-3 / 3.0 * f, 2e-3 / 3.0 * f};
  m.volumetric_strain = 1e-4 / 7.0 * f;
  m.volume = 1e-6 * (0.1 + 0.2) * f;
  m.void_ratio = 0.6 + 1e-16 * k;
  m.ufr = 1e-3 / 3.0;
  m.iuf = 2e-3 / 3.0 * f;
  m.moment_index = 1e-5 / 7.0;
  m.inertia_index = 4.9e-324 * (k + 1);
  m.coordination_number = 4.0 + 1.0 / 3.0;
  m.raw_coordination_number = 4.5 - 1.0 / 7.0;
  m.idle_mass_fraction = 0.05 / 3.0;
  m.contacts = 1234 + k;
  m.sliding_contacts = 56 - k;
  m.max_overlap_ratio = 1e-3 * std::sqrt(2.0) * f;
  m.energy.boundary_work = 1e-3 * f / 3.0;
  m.energy.damping = 1e-5 / 7.0 * f;
  m.energy.friction = 1e-4 / 9.0;
  m.energy.kinetic_translational = 1e-9 * f;
  m.energy.kinetic_rotational = 1e-10 / 3.0;
  m.energy.elastic = 1e-4 * (0.1 + 0.2);
  m.energy.kinetic_reference = k == 0 ? 0.0 : 1e-12;
  m.energy.elastic_reference = 1e-6 / 3.0;
  m.energy.has_reference = k != 0;
  return m;
}

void expect_same(const Measures& a, const Measures& b) {
  EXPECT_TRUE(same(a.time, b.time));
  EXPECT_EQ(a.step, b.step);
  EXPECT_EQ(0, std::memcmp(&a.stress, &b.stress, sizeof(Mat3)));
  EXPECT_TRUE(same(a.principal_stress, b.principal_stress));
  EXPECT_TRUE(same(a.p, b.p));
  EXPECT_TRUE(same(a.q, b.q));
  EXPECT_TRUE(same(a.phi, b.phi));
  EXPECT_TRUE(same(a.strain, b.strain));
  EXPECT_TRUE(same(a.volumetric_strain, b.volumetric_strain));
  EXPECT_TRUE(same(a.volume, b.volume));
  EXPECT_TRUE(same(a.void_ratio, b.void_ratio));
  EXPECT_TRUE(same(a.ufr, b.ufr));
  EXPECT_TRUE(same(a.iuf, b.iuf));
  EXPECT_TRUE(same(a.moment_index, b.moment_index));
  EXPECT_TRUE(same(a.inertia_index, b.inertia_index));
  EXPECT_TRUE(same(a.coordination_number, b.coordination_number));
  EXPECT_TRUE(same(a.raw_coordination_number, b.raw_coordination_number));
  EXPECT_TRUE(same(a.idle_mass_fraction, b.idle_mass_fraction));
  EXPECT_EQ(a.contacts, b.contacts);
  EXPECT_EQ(a.sliding_contacts, b.sliding_contacts);
  EXPECT_TRUE(same(a.max_overlap_ratio, b.max_overlap_ratio));
  EXPECT_TRUE(same(a.energy.boundary_work, b.energy.boundary_work));
  EXPECT_TRUE(same(a.energy.damping, b.energy.damping));
  EXPECT_TRUE(same(a.energy.friction, b.energy.friction));
  EXPECT_TRUE(same(a.energy.kinetic_translational, b.energy.kinetic_translational));
  EXPECT_TRUE(same(a.energy.kinetic_rotational, b.energy.kinetic_rotational));
  EXPECT_TRUE(same(a.energy.elastic, b.energy.elastic));
  EXPECT_TRUE(same(a.energy.kinetic_reference, b.energy.kinetic_reference));
  EXPECT_TRUE(same(a.energy.elastic_reference, b.energy.elastic_reference));
  EXPECT_EQ(a.energy.has_reference, b.energy.has_reference);
}

struct DatasetUnits {
  std::vector<std::string> datasets;
  std::vector<std::string> without_units;
};

herr_t visit_link(hid_t group, const char* name, const H5L_info_t*, void* data) {
  auto* out = static_cast<DatasetUnits*>(data);
  const hid_t obj = H5Oopen(group, name, H5P_DEFAULT);
  if (obj < 0) return -1;
  if (H5Iget_type(obj) == H5I_DATASET) {
    out->datasets.push_back(std::string("/") + name);
    if (H5Aexists(obj, "units") <= 0) out->without_units.push_back(std::string("/") + name);
  }
  H5Oclose(obj);
  return 0;
}

DatasetUnits scan_units(const std::string& path) {
  DatasetUnits out;
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(f, 0);
  EXPECT_GE(H5Lvisit(f, H5_INDEX_NAME, H5_ITER_INC, &visit_link, &out), 0);
  H5Fclose(f);
  return out;
}

std::vector<double> read_doubles(const std::string& path, const char* dataset, std::vector<hsize_t>* dims) {
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t ds = H5Dopen2(f, dataset, H5P_DEFAULT);
  const hid_t space = H5Dget_space(ds);
  dims->assign(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)), 0);
  H5Sget_simple_extent_dims(space, dims->data(), nullptr);
  std::vector<double> out(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
  H5Sclose(space);
  H5Dclose(ds);
  H5Fclose(f);
  return out;
}

std::string message_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(ResultsFile, SeriesRoundTripIsBitExact) {
  TempDir dir;
  const std::string path = dir.file("results.h5");
  ResultsWriter w(path, "drained_100kPa");
  for (int k = 0; k < 3; ++k) w.append(make_measures(k));
  EXPECT_EQ(w.size(), 3u);
  w.flush();
  const std::vector<Measures> r = read_results_series(path, "drained_100kPa");
  ASSERT_EQ(r.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE(k);
    expect_same(make_measures(k), r[static_cast<std::size_t>(k)]);
  }
  w.close();
}

TEST(ResultsFile, LayoutShapesAndDerivedBalanceError) {
  TempDir dir;
  const std::string path = dir.file("results.h5");
  {
    ResultsWriter w(path);
    for (int k = 0; k < 3; ++k) w.append(make_measures(k));
    w.close();
  }
  std::vector<hsize_t> dims;
  const std::vector<double> stress = read_doubles(path, "/test/series/stress", &dims);
  EXPECT_EQ(dims, (std::vector<hsize_t>{3, 9}));
  const Measures m1 = make_measures(1);
  EXPECT_TRUE(same(stress[9 + 5], m1.stress.m[1][2]));  // row-major
  read_doubles(path, "/test/series/principal_stress", &dims);
  EXPECT_EQ(dims, (std::vector<hsize_t>{3, 3}));
  read_doubles(path, "/test/series/p", &dims);
  EXPECT_EQ(dims, (std::vector<hsize_t>{3}));
  const std::vector<double> err = read_doubles(path, "/test/series/energy_balance_error", &dims);
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(same(err[static_cast<std::size_t>(k)], make_measures(k).energy.balance_error()));
}

TEST(ResultsFile, EveryDatasetHasUnits) {
  TempDir dir;
  const std::string path = dir.file("results.h5");
  {
    ResultsWriter w(path);
    for (int k = 0; k < 3; ++k) w.append(make_measures(k));
    w.set_summary({{"phi_peak", 0.6}}, {{"verdict", "quasi-static"}});
    w.close();
  }
  const DatasetUnits u = scan_units(path);
  const std::set<std::string> names(u.datasets.begin(), u.datasets.end());
  for (const char* c :
       {"time", "step", "stress", "p", "q", "phi", "principal_stress", "strain", "volumetric_strain", "volume",
        "void_ratio", "ufr", "iuf", "moment_index", "inertia_index", "coordination_number",
        "raw_coordination_number", "idle_mass_fraction", "contacts", "sliding_contacts", "max_overlap_ratio",
        "energy_boundary_work", "energy_damping", "energy_friction", "energy_kinetic_translational",
        "energy_kinetic_rotational", "energy_elastic", "energy_balance_error"})
    EXPECT_TRUE(names.count(std::string("/test/series/") + c)) << c;
  EXPECT_TRUE(u.without_units.empty()) << "first dataset without units: " << u.without_units.front();
}

TEST(ResultsFile, SummaryRoundTrip) {
  TempDir dir;
  const std::string path = dir.file("results.h5");
  const std::map<std::string, double> numbers = {{"phi_peak", std::asin(1.0 / 3.0)},
                                                 {"eps_peak", 0.1 + 0.2},
                                                 {"e0", 0.6 + 1e-16},
                                                 {"runtime", 12.5},
                                                 {"phi_end", std::numeric_limits<double>::quiet_NaN()}};
  const std::map<std::string, std::string> texts = {{"verdict", "quasi-static"}, {"stop_reason", ""}};
  {
    ResultsWriter w(path, "t");
    w.append(make_measures(0));
    w.set_summary({{"old", 1.0}}, {});
    w.set_summary(numbers, texts);  // replaces
    w.close();
  }
  const std::map<std::string, double> n = read_summary_numbers(path, "t");
  ASSERT_EQ(n.size(), numbers.size());
  for (const auto& kv : numbers) {
    ASSERT_TRUE(n.count(kv.first)) << kv.first;
    EXPECT_TRUE(same(n.at(kv.first), kv.second)) << kv.first;
  }
  EXPECT_EQ(read_summary_texts(path, "t"), texts);
}

TEST(ResultsFile, FlushRewritesAtomicallyAndKeepsOtherGroups) {
  TempDir dir;
  const std::string path = dir.file("results.h5");
  {
    ResultsWriter a(path, "a");
    a.append(make_measures(0));
    a.close();
  }
  ResultsWriter b(path, "b");
  b.append(make_measures(1));
  b.flush();
  b.append(make_measures(2));
  b.flush();
  EXPECT_EQ(dir.files(), std::set<std::string>{"results.h5"});
  ASSERT_EQ(read_results_series(path, "a").size(), 1u);
  expect_same(read_results_series(path, "a")[0], make_measures(0));
  const std::vector<Measures> rb = read_results_series(path, "b");
  ASSERT_EQ(rb.size(), 2u);
  expect_same(rb[1], make_measures(2));
  // Rewriting group "a" replaces it and keeps "b".
  {
    ResultsWriter a2(path, "a");
    a2.close();
  }
  EXPECT_TRUE(read_results_series(path, "a").empty());
  EXPECT_EQ(read_results_series(path, "b").size(), 2u);
}

TEST(ResultsFile, EmptySeriesAndDestructorFlush) {
  TempDir dir;
  const std::string path = dir.file("results.h5");
  { ResultsWriter w(path); }
  EXPECT_TRUE(read_results_series(path).empty());
  {
    ResultsWriter w(path);
    w.append(make_measures(0));
  }  // not closed: the destructor flushes
  EXPECT_EQ(read_results_series(path).size(), 1u);
}

TEST(ResultsFile, ErrorsNameThePathAndTheField) {
  TempDir dir;
  const std::string missing_dir = dir.file("no/such/dir/results.h5");
  ResultsWriter w(missing_dir);
  w.append(make_measures(0));
  EXPECT_NE(message_of([&] { w.flush(); }).find(missing_dir), std::string::npos);
  EXPECT_NE(message_of([&] { ResultsWriter bad(dir.file("r.h5"), "a/b"); }).find("group"), std::string::npos);
  EXPECT_NE(message_of([&] { w.set_summary({{"x", 1.0}}, {{"x", "y"}}); }).find("'x'"), std::string::npos);

  // A file that is not a results file is never overwritten.
  const std::string sample = dir.file("sample.h5");
  vt::dem::SimulationState s;
  s.particles.add_sphere(1, 1e-3, 2650, {0.1, 0.1, 0.1});
  s.h = s.h_reference = Mat3::identity();
  vt::io::write_sample(sample, s, {});
  const std::string err = message_of([&] { ResultsWriter clobber(sample); });
  EXPECT_NE(err.find(sample + ": not a virtual_triaxial results file"), std::string::npos) << err;
  const std::string text = dir.file("notes.txt");
  std::ofstream(text) << "keep me\n";
  EXPECT_NE(message_of([&] { ResultsWriter clobber(text); }).find(text), std::string::npos);

  // Reading a missing group names it.
  const std::string path = dir.file("results.h5");
  {
    ResultsWriter ok(path, "present");
    ok.close();
  }
  const std::string missing = message_of([&] { read_results_series(path, "absent"); });
  EXPECT_NE(missing.find(path + ": /absent: missing"), std::string::npos) << missing;

  // A closed writer refuses appends.
  ResultsWriter closed(dir.file("closed.h5"));
  closed.close();
  EXPECT_NE(message_of([&] { closed.append(make_measures(0)); }).find("closed"), std::string::npos);
  EXPECT_EQ(dir.files(), (std::set<std::string>{"closed.h5", "notes.txt", "results.h5", "sample.h5"}));
}

TEST(ResultsFile, NoHdf5HandlesLeak) {
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
}
