#include "virtual_triaxial/io/results_file.h"

#include <sys/stat.h>

#include <stdexcept>

#include "virtual_triaxial/io/hdf5_atomic_file.h"
#include "virtual_triaxial/io/hdf5_group.h"

namespace vt::io {

namespace {

using dem::Measures;

/// A floating-point channel: `cols` values per row (0 = 1-D).
struct Channel {
  const char* name;
  const char* units;
  std::size_t cols;
  void (*get)(const Measures&, double*);
  void (*set)(Measures&, const double*);  ///< nullptr: derived, not restored
};

void get_vec(const dem::Vec3& v, double* out) {
  out[0] = v.x;
  out[1] = v.y;
  out[2] = v.z;
}
dem::Vec3 vec(const double* in) { return {in[0], in[1], in[2]}; }

#define VT_SCALAR(field, units)                                              \
  Channel {                                                                  \
    #field, units, 0, [](const Measures& m, double* o) { *o = m.field; },    \
        [](Measures& m, const double* i) { m.field = *i; }                   \
  }
#define VT_ENERGY(field)                                                              \
  Channel {                                                                           \
    "energy_" #field, "J", 0, [](const Measures& m, double* o) { *o = m.energy.field; }, \
        [](Measures& m, const double* i) { m.energy.field = *i; }                     \
  }

const Channel kChannels[] = {
    VT_SCALAR(time, "s"),
    Channel{"stress", "Pa", 9,
            [](const Measures& m, double* o) {
              for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) o[3 * r + c] = m.stress.m[r][c];
            },
            [](Measures& m, const double* i) {
              for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) m.stress.m[r][c] = i[3 * r + c];
            }},
    VT_SCALAR(p, "Pa"),
    VT_SCALAR(q, "Pa"),
    VT_SCALAR(phi, "rad"),
    Channel{"principal_stress", "Pa", 3, [](const Measures& m, double* o) { get_vec(m.principal_stress, o); },
            [](Measures& m, const double* i) { m.principal_stress = vec(i); }},
    Channel{"strain", "1", 3, [](const Measures& m, double* o) { get_vec(m.strain, o); },
            [](Measures& m, const double* i) { m.strain = vec(i); }},
    VT_SCALAR(volumetric_strain, "1"),
    VT_SCALAR(volume, "m^3"),
    VT_SCALAR(void_ratio, "1"),
    VT_SCALAR(ufr, "1"),
    VT_SCALAR(iuf, "1"),
    VT_SCALAR(moment_index, "1"),
    VT_SCALAR(inertia_index, "1"),
    VT_SCALAR(coordination_number, "1"),
    VT_SCALAR(raw_coordination_number, "1"),
    VT_SCALAR(idle_mass_fraction, "1"),
    VT_SCALAR(max_overlap_ratio, "1"),
    VT_ENERGY(boundary_work),
    VT_ENERGY(damping),
    VT_ENERGY(friction),
    VT_ENERGY(kinetic_translational),
    VT_ENERGY(kinetic_rotational),
    VT_ENERGY(elastic),
    VT_ENERGY(kinetic_reference),
    VT_ENERGY(elastic_reference),
    Channel{"energy_balance_error", "J", 0, [](const Measures& m, double* o) { *o = m.energy.balance_error(); },
            nullptr},
};
#undef VT_SCALAR
#undef VT_ENERGY

/// Integer channels.
struct IntChannel {
  const char* name;
  std::int64_t Measures::*field;
};
const IntChannel kIntChannels[] = {
    {"step", &Measures::step}, {"contacts", &Measures::contacts}, {"sliding_contacts", &Measures::sliding_contacts}};

void check_name(const std::string& what, const std::string& name) {
  if (name.empty() || name == "." || name.find('/') != std::string::npos)
    throw std::runtime_error(what + " '" + name + "': must be non-empty and contain no '/'");
}

/// True when `path` exists and is not empty (an empty file may be replaced).
bool file_exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && st.st_size > 0;
}

/// Open an existing results file; throws if it is not one.
h5::Group open_results(const std::string& path) {
  h5::Group root = h5::Group::open_file_read(path);
  if (!root.has_attr("format") || !root.attr_is_string("format") ||
      root.attr_string("format") != kResultsFormat)
    throw std::runtime_error(path + ": not a virtual_triaxial results file (format attribute is not '" +
                             std::string(kResultsFormat) + "')");
  return root;
}

void write_series(const h5::Group& g, const std::vector<Measures>& series) {
  const std::size_t n = series.size();
  for (const Channel& c : kChannels) {
    const std::size_t width = c.cols == 0 ? 1 : c.cols;
    std::vector<double> data(n * width);
    for (std::size_t i = 0; i < n; ++i) c.get(series[i], &data[i * width]);
    g.write(c.name, data, n, c.cols, c.units);
  }
  for (const IntChannel& c : kIntChannels) {
    std::vector<std::int64_t> data(n);
    for (std::size_t i = 0; i < n; ++i) data[i] = series[i].*c.field;
    g.write(c.name, data, n, 0, "1");
  }
  std::vector<std::uint8_t> has(n);
  for (std::size_t i = 0; i < n; ++i) has[i] = series[i].energy.has_reference ? 1 : 0;
  g.write("energy_has_reference", has, n, 0, "1");
}

}  // namespace

ResultsWriter::ResultsWriter(const std::string& path, const std::string& group) : path_(path), group_(group) {
  if (path.empty()) throw std::runtime_error("results file: path: must not be empty");
  check_name(path + ": results group", group);
  if (file_exists(path)) open_results(path);  // refuse to clobber a foreign file
}

ResultsWriter::~ResultsWriter() {
  if (closed_) return;
  try {
    flush();
  } catch (...) {
    // A destructor must not throw; call close() to see errors.
  }
}

void ResultsWriter::check_open(const char* what) const {
  if (closed_) throw std::runtime_error(path_ + ": " + what + ": results writer is closed");
}

void ResultsWriter::append(const dem::Measures& m) {
  check_open("append");
  series_.push_back(m);
}

void ResultsWriter::restore_series(std::vector<dem::Measures> rows) {
  check_open("restore_series");
  series_ = std::move(rows);
}

void ResultsWriter::set_summary(const std::map<std::string, double>& numbers,
                                const std::map<std::string, std::string>& texts) {
  check_open("set_summary");
  for (const auto& kv : numbers) check_name(path_ + ": summary key", kv.first);
  for (const auto& kv : texts) {
    check_name(path_ + ": summary key", kv.first);
    if (numbers.count(kv.first))
      throw std::runtime_error(path_ + ": summary key '" + kv.first + "': given both as a number and as a text");
  }
  numbers_ = numbers;
  texts_ = texts;
}

void ResultsWriter::flush() {
  check_open("flush");
  h5::AtomicFile file(path_);
  const h5::Group& root = file.root();
  root.set_attr("format", kResultsFormat);
  root.set_attr("format_version", kResultsFormatVersion);
  if (file_exists(path_)) {
    // Keep the other tests' groups.
    const h5::Group old = open_results(path_);
    h5::ErrorSilencer quiet;
    for (const std::string& name : old.children()) {
      if (name == group_) continue;
      if (H5Ocopy(old.id(), name.c_str(), root.id(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT) < 0)
        throw std::runtime_error(h5::with_reason(path_ + ": /" + name + ": cannot copy existing group"));
    }
  }
  {
    const h5::Group g = root.create_group(group_);
    write_series(g.create_group("series"), series_);
    const h5::Group summary = g.create_group("summary");
    for (const auto& kv : numbers_) summary.set_attr(kv.first, kv.second);
    for (const auto& kv : texts_) summary.set_attr(kv.first, kv.second);
  }
  file.commit();
}

void ResultsWriter::close() {
  if (closed_) return;
  flush();
  closed_ = true;
}

std::vector<dem::Measures> read_results_series(const std::string& path, const std::string& group) {
  const h5::Group root = open_results(path);
  const h5::Group g = root.open_group(group).open_group("series");
  const std::size_t n = g.rows("time");
  const std::string ref = g.child_path("time");
  std::vector<Measures> out(n);
  for (const Channel& c : kChannels) {
    if (c.set == nullptr) continue;
    const std::size_t width = c.cols == 0 ? 1 : c.cols;
    const std::vector<double> data = g.read<double>(c.name, n, c.cols, ref);
    for (std::size_t i = 0; i < n; ++i) c.set(out[i], &data[i * width]);
  }
  for (const IntChannel& c : kIntChannels) {
    const std::vector<std::int64_t> data = g.read<std::int64_t>(c.name, n, 0, ref);
    for (std::size_t i = 0; i < n; ++i) out[i].*c.field = data[i];
  }
  const std::vector<std::uint8_t> has = g.read<std::uint8_t>("energy_has_reference", n, 0, ref);
  for (std::size_t i = 0; i < n; ++i) out[i].energy.has_reference = has[i] != 0;
  return out;
}

std::map<std::string, double> read_summary_numbers(const std::string& path, const std::string& group) {
  const h5::Group root = open_results(path);
  const h5::Group s = root.open_group(group).open_group("summary");
  std::map<std::string, double> out;
  for (const std::string& name : s.attr_names())
    if (s.attr_is_float(name)) out[name] = s.attr_double(name);
  return out;
}

std::map<std::string, std::string> read_summary_texts(const std::string& path, const std::string& group) {
  const h5::Group root = open_results(path);
  const h5::Group s = root.open_group(group).open_group("summary");
  std::map<std::string, std::string> out;
  for (const std::string& name : s.attr_names())
    if (s.attr_is_string(name)) out[name] = s.attr_string(name);
  return out;
}

}  // namespace vt::io
