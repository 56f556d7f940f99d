#include "virtual_triaxial/io/sample_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <unordered_set>
#include <vector>

#include "virtual_triaxial/io/hdf5_atomic_file.h"
#include "virtual_triaxial/io/hdf5_group.h"

namespace vt::io {

namespace {

using dem::Mat3;
using dem::Quaternion;
using dem::Vec3;

// ---- flattening -------------------------------------------------------------------

std::vector<double> flat(const std::vector<Vec3>& v) {
  std::vector<double> out;
  out.reserve(3 * v.size());
  for (const Vec3& a : v) out.insert(out.end(), {a.x, a.y, a.z});
  return out;
}

std::vector<double> flat(const std::vector<Quaternion>& v) {
  std::vector<double> out;
  out.reserve(4 * v.size());
  for (const Quaternion& q : v) out.insert(out.end(), {q.w, q.x, q.y, q.z});
  return out;
}

std::vector<double> flat(const Mat3& m) {
  std::vector<double> out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out.push_back(m.m[r][c]);
  return out;
}

std::vector<Vec3> vec3s(const std::vector<double>& f) {
  std::vector<Vec3> out(f.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {f[3 * i], f[3 * i + 1], f[3 * i + 2]};
  return out;
}

std::vector<Quaternion> quats(const std::vector<double>& f) {
  std::vector<Quaternion> out(f.size() / 4);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {f[4 * i], f[4 * i + 1], f[4 * i + 2], f[4 * i + 3]};
  return out;
}

Mat3 mat3(const std::vector<double>& f) {
  Mat3 m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m.m[r][c] = f[static_cast<std::size_t>(3 * r + c)];
  return m;
}

// ---- writing -------------------------------------------------------------------------

void check_length(const std::string& path, const char* field, std::size_t n, std::size_t expected,
                  const char* reference) {
  if (n != expected)
    throw std::runtime_error(path + ": cannot write sample: " + field + " has " + std::to_string(n) +
                             " entries, expected " + std::to_string(expected) + " (size of " + reference + ")");
}

void check_state(const std::string& path, const dem::SimulationState& s) {
  const dem::Particles& p = s.particles;
  const std::size_t n = p.id.size();
  check_length(path, "particles.shape", p.shape.size(), n, "particles.id");
  check_length(path, "particles.radius", p.radius.size(), n, "particles.id");
  check_length(path, "particles.semi_axes", p.semi_axes.size(), n, "particles.id");
  check_length(path, "particles.mass", p.mass.size(), n, "particles.id");
  check_length(path, "particles.inertia", p.inertia.size(), n, "particles.id");
  check_length(path, "particles.frac", p.frac.size(), n, "particles.id");
  check_length(path, "particles.velocity", p.velocity.size(), n, "particles.id");
  check_length(path, "particles.omega", p.omega.size(), n, "particles.id");
  check_length(path, "particles.orientation", p.orientation.size(), n, "particles.id");
  check_length(path, "particles.material", p.material.size(), n, "particles.id");
}

void write_particles(const h5::Group& root, const dem::SimulationState& s) {
  const dem::Particles& p = s.particles;
  const std::size_t n = p.size();
  h5::Group g = root.create_group("particles");
  g.write("id", p.id, n, 0, "1");
  std::vector<std::uint8_t> shape(n);
  for (std::size_t i = 0; i < n; ++i) shape[i] = static_cast<std::uint8_t>(p.shape[i]);
  g.write("shape", shape, n, 0, "1");
  g.write("radius", p.radius, n, 0, "m");
  g.write("semi_axes", flat(p.semi_axes), n, 3, "m");
  g.write("mass", p.mass, n, 0, "kg");
  g.write("inertia", flat(p.inertia), n, 3, "kg m^2");
  std::vector<Vec3> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = s.h * p.frac[i];
  g.write("position", flat(x), n, 3, "m");
  g.write("position_fractional", flat(p.frac), n, 3, "1");
  g.write("velocity", flat(p.velocity), n, 3, "m/s");
  g.write("angular_velocity", flat(p.omega), n, 3, "rad/s");
  g.write("orientation", flat(p.orientation), n, 4, "1");
  g.write("material", p.material, n, 0, "1");
}

void write_contacts(const h5::Group& root, const std::vector<dem::ContactHistory>& c) {
  const std::size_t m = c.size();
  std::vector<std::int64_t> a(m), b(m);
  std::vector<Vec3> spring(m), normal(m), previous(m);
  std::vector<std::uint8_t> history(m);
  bool cached = false;
  for (std::size_t k = 0; k < m; ++k) {
    a[k] = c[k].id_a;
    b[k] = c[k].id_b;
    spring[k] = c[k].spring;
    const dem::SpheroidContactCache& cache = c[k].cache;
    history[k] = cache.valid ? (cache.has_previous ? 2 : 1) : 0;
    cached = cached || cache.valid;
    if (cache.valid) normal[k] = cache.normal;
    if (cache.valid && cache.has_previous) previous[k] = cache.previous;
  }
  h5::Group g = root.create_group("contacts");
  g.write("id_a", a, m, 0, "1");
  g.write("id_b", b, m, 0, "1");
  g.write("spring", flat(spring), m, 3, "N");
  if (cached) {
    g.write("normal_history", history, m, 0, "1");
    g.write("normal", flat(normal), m, 3, "1");
    g.write("normal_previous", flat(previous), m, 3, "1");
  }
}

void write_rest(const h5::Group& root, const dem::SimulationState& s, const SampleMetadata& meta) {
  {
    h5::Group g = root.create_group("cell");
    g.write("h", flat(s.h), 3, 3, "m");
    g.write("h_reference", flat(s.h_reference), 3, 3, "m");
    g.write("velocity_gradient", flat(s.velocity_gradient), 3, 3, "1/s");
    g.write_scalar("time", s.time, "s");
    g.write_scalar("step", s.step, "1");
  }
  {
    const dem::Material& m = s.settings.material;
    h5::Group g = root.create_group("material");
    g.write_scalar("density", m.density, "kg/m^3");
    g.write_scalar("young_modulus", m.young, "Pa");
    g.write_scalar("poisson_ratio", m.poisson, "1");
    g.write_scalar("friction", m.friction, "1");
  }
  {
    const dem::SimulationSettings& st = s.settings;
    h5::Group g = root.create_group("settings");
    g.set_attr("damping_model", dem::to_string(st.damping.model()));
    g.write_scalar("damping_ratio", st.damping.ratio(), "1");
    g.write_scalar("time_step_ratio", st.time_step_ratio, "1");
    if (st.time_step_basis != dem::TimeStepBasis::ReferenceTime) {  // absent = reference (older files)
      g.set_attr("time_step_basis", dem::to_string(st.time_step_basis));
      g.write_scalar("time_step_safety", st.time_step_safety, "1");
      g.write_scalar("time_step_max_ratio", st.time_step_max_ratio, "1");
      g.write_scalar("time_step", s.time_step, "s");
      g.write_scalar("contact_critical_step", s.contact_critical_step, "s");  // +inf: no contacts
      g.write_scalar("contact_refresh_virial", s.contact_refresh_virial, "N m");
    }
    g.write_scalar("skin_ratio", st.skin_ratio, "1");
    g.write_scalar("check_interval", st.check_interval, "1");
    g.write_scalar("max_overlap_ratio", st.limits.max_overlap_ratio, "1");
    g.write_scalar("max_energy_error", st.limits.max_energy_error, "1");
  }
  {
    const dem::EnergyBudget& e = s.energy;
    h5::Group g = root.create_group("energy");
    g.write_scalar("boundary_work", e.boundary_work, "J");
    g.write_scalar("damping", e.damping, "J");
    g.write_scalar("friction", e.friction, "J");
    g.write_scalar("kinetic_translational", e.kinetic_translational, "J");
    g.write_scalar("kinetic_rotational", e.kinetic_rotational, "J");
    g.write_scalar("elastic", e.elastic, "J");
    g.write_scalar("kinetic_reference", e.kinetic_reference, "J");
    g.write_scalar("elastic_reference", e.elastic_reference, "J");
    g.write_scalar("has_reference", static_cast<std::uint8_t>(e.has_reference ? 1 : 0), "1");
  }
  {
    h5::Group g = root.create_group("preparation");
    g.write_scalar("seed", meta.seed, "1");
    g.write_scalar("friction_during_shrinkage", meta.friction_during_shrinkage, "1");
    g.write_scalar("target_pressure", meta.target_pressure, "Pa");
    g.write_scalar("initial_void_ratio", meta.initial_void_ratio, "1");
    g.set_attr("software_version", meta.software_version);
    g.set_attr("created_by", meta.created_by);
    g.set_attr("description", meta.description);
  }
}

// ---- reading ---------------------------------------------------------------------------

std::string number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string entry(std::size_t i, std::size_t cols) {
  if (cols == 0) return "entry [" + std::to_string(i) + "]";
  return "entry [" + std::to_string(i / cols) + ", " + std::to_string(i % cols) + "]";
}

template <class Ok>
void check_each(const h5::Group& g, const std::string& name, const std::vector<double>& v, std::size_t cols,
                Ok ok, const char* requirement) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!ok(v[i])) g.fail(name, entry(i, cols) + " is " + number(v[i]) + ", must be " + requirement);
}

bool finite(double v) { return std::isfinite(v); }
bool positive(double v) { return std::isfinite(v) && v > 0.0; }
bool non_negative(double v) { return std::isfinite(v) && v >= 0.0; }

double read_checked(const h5::Group& g, const std::string& name, bool (*ok)(double), const char* requirement) {
  const double v = g.read_scalar<double>(name);
  if (!ok(v)) g.fail(name, "is " + number(v) + ", must be " + requirement);
  return v;
}

void check_format(const h5::Group& root) {
  const std::string& file = root.file();
  if (!root.has_attr("format") || !root.attr_is_string("format"))
    throw std::runtime_error(file + ": not a virtual_triaxial sample file (no `format` attribute)");
  const std::string format = root.attr_string("format");
  if (format != kSampleFormat)
    throw std::runtime_error(file + ": not a virtual_triaxial sample file (format is '" + format + "', expected '" +
                             kSampleFormat + "')");
  if (!root.has_attr("format_version")) throw std::runtime_error(file + ": /: attribute format_version: missing");
  const std::int64_t version = root.attr_int("format_version");
  if (version != kSampleFormatVersion)
    throw std::runtime_error(file + ": /: attribute format_version: unsupported version " + std::to_string(version) +
                             " (this reader understands " + std::to_string(kSampleFormatVersion) + ")");
}

void read_particles(const h5::Group& root, dem::Particles& p) {
  const h5::Group g = root.open_group("particles");
  const std::size_t n = g.rows("id");
  const std::string ref = g.child_path("id");
  p.id = g.read<std::int64_t>("id", n, 0);
  {
    std::vector<std::int64_t> sorted = p.id;
    std::sort(sorted.begin(), sorted.end());
    const auto dup = std::adjacent_find(sorted.begin(), sorted.end());
    if (dup != sorted.end()) g.fail("id", "duplicate id " + std::to_string(*dup));
  }
  const std::vector<std::uint8_t> shape = g.read<std::uint8_t>("shape", n, 0, ref);
  p.shape.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (shape[i] > 1)
      g.fail("shape", entry(i, 0) + " is " + std::to_string(shape[i]) + ", must be 0 (sphere) or 1 (spheroid)");
    p.shape[i] = static_cast<dem::Shape>(shape[i]);
  }
  p.radius = g.read<double>("radius", n, 0, ref);
  check_each(g, "radius", p.radius, 0, positive, "finite and > 0");
  const std::vector<double> axes = g.read<double>("semi_axes", n, 3, ref);
  check_each(g, "semi_axes", axes, 3, positive, "finite and > 0");
  p.semi_axes = vec3s(axes);
  p.mass = g.read<double>("mass", n, 0, ref);
  check_each(g, "mass", p.mass, 0, positive, "finite and > 0");
  const std::vector<double> inertia = g.read<double>("inertia", n, 3, ref);
  check_each(g, "inertia", inertia, 3, positive, "finite and > 0");
  p.inertia = vec3s(inertia);
  // Cartesian positions are informative; only their presence and shape are checked.
  (void)g.read<double>("position", n, 3, ref);
  const std::vector<double> frac = g.read<double>("position_fractional", n, 3, ref);
  check_each(g, "position_fractional", frac, 3, finite, "finite");
  p.frac = vec3s(frac);
  const std::vector<double> vel = g.read<double>("velocity", n, 3, ref);
  check_each(g, "velocity", vel, 3, finite, "finite");
  p.velocity = vec3s(vel);
  const std::vector<double> omega = g.read<double>("angular_velocity", n, 3, ref);
  check_each(g, "angular_velocity", omega, 3, finite, "finite");
  p.omega = vec3s(omega);
  const std::vector<double> q = g.read<double>("orientation", n, 4, ref);
  check_each(g, "orientation", q, 4, finite, "finite");
  p.orientation = quats(q);
  for (std::size_t i = 0; i < n; ++i) {
    const Quaternion& o = p.orientation[i];
    const double norm = std::sqrt(o.w * o.w + o.x * o.x + o.y * o.y + o.z * o.z);
    if (!(std::fabs(norm - 1.0) <= 1e-6))
      g.fail("orientation", "row " + std::to_string(i) + " has norm " + number(norm) + ", must be a unit quaternion");
  }
  p.material = g.read<std::int32_t>("material", n, 0, ref);
  for (std::size_t i = 0; i < n; ++i)
    if (p.material[i] < 0) g.fail("material", entry(i, 0) + " is " + std::to_string(p.material[i]) + ", must be >= 0");
}

std::vector<dem::ContactHistory> read_contacts(const h5::Group& root, const std::vector<std::int64_t>& ids) {
  const h5::Group g = root.open_group("contacts");
  const std::size_t m = g.rows("id_a");
  const std::string ref = g.child_path("id_a");
  const std::vector<std::int64_t> a = g.read<std::int64_t>("id_a", m, 0);
  const std::vector<std::int64_t> b = g.read<std::int64_t>("id_b", m, 0, ref);
  const std::vector<double> spring = g.read<double>("spring", m, 3, ref);
  check_each(g, "spring", spring, 3, finite, "finite");
  const std::unordered_set<std::int64_t> known(ids.begin(), ids.end());
  std::vector<dem::ContactHistory> out(m);
  for (std::size_t k = 0; k < m; ++k) {
    if (!known.count(a[k])) g.fail("id_a", entry(k, 0) + " is " + std::to_string(a[k]) + ", not a particle id");
    if (!known.count(b[k])) g.fail("id_b", entry(k, 0) + " is " + std::to_string(b[k]) + ", not a particle id");
    if (!(a[k] < b[k]))
      g.fail("id_b", entry(k, 0) + " is " + std::to_string(b[k]) + ", must be greater than id_a (" +
                         std::to_string(a[k]) + ")");
    out[k].id_a = a[k];
    out[k].id_b = b[k];
    out[k].spring = {spring[3 * k], spring[3 * k + 1], spring[3 * k + 2]};
  }
  if (g.has("normal_history")) {  // spheroid samples: the contact solver's warm start
    const std::vector<std::uint8_t> history = g.read<std::uint8_t>("normal_history", m, 0, ref);
    const std::vector<double> normal = g.read<double>("normal", m, 3, ref);
    const std::vector<double> previous = g.read<double>("normal_previous", m, 3, ref);
    check_each(g, "normal", normal, 3, finite, "finite");
    check_each(g, "normal_previous", previous, 3, finite, "finite");
    for (std::size_t k = 0; k < m; ++k) {
      if (history[k] > 2)
        g.fail("normal_history", entry(k, 0) + " is " + std::to_string(history[k]) + ", must be 0, 1 or 2");
      dem::SpheroidContactCache& cache = out[k].cache;
      cache.valid = history[k] >= 1;
      cache.has_previous = history[k] == 2;
      cache.normal = {normal[3 * k], normal[3 * k + 1], normal[3 * k + 2]};
      cache.previous = {previous[3 * k], previous[3 * k + 1], previous[3 * k + 2]};
    }
  }
  return out;
}

Mat3 read_cell_matrix(const h5::Group& g, const std::string& name, bool invertible) {
  const std::vector<double> f = g.read<double>(name, 3, 3);
  check_each(g, name, f, 3, finite, "finite");
  const Mat3 m = mat3(f);
  if (invertible && !(std::fabs(determinant(m)) > 0.0)) g.fail(name, "is singular (zero volume)");
  return m;
}

void read_cell(const h5::Group& root, dem::SimulationState& s) {
  const h5::Group g = root.open_group("cell");
  s.h = read_cell_matrix(g, "h", true);
  s.h_reference = read_cell_matrix(g, "h_reference", true);
  s.velocity_gradient = read_cell_matrix(g, "velocity_gradient", false);
  s.time = read_checked(g, "time", finite, "finite");
  s.step = g.read_scalar<std::int64_t>("step");
  if (s.step < 0) g.fail("step", "is " + std::to_string(s.step) + ", must be >= 0");
}

void read_settings(const h5::Group& root, dem::SimulationSettings& st, double& time_step, double& critical,
                   double& virial) {
  {
    const h5::Group g = root.open_group("material");
    st.material.density = g.read_scalar<double>("density");
    st.material.young = g.read_scalar<double>("young_modulus");
    st.material.poisson = g.read_scalar<double>("poisson_ratio");
    st.material.friction = g.read_scalar<double>("friction");
    const std::string problem = st.material.validate();  // "field: reason"
    if (!problem.empty()) throw std::runtime_error(g.where("") + "/" + problem);
  }
  const h5::Group g = root.open_group("settings");
  if (!g.has_attr("damping_model")) g.fail("", "attribute damping_model: missing");
  const std::string model_text = g.attr_string("damping_model");
  dem::DampingModel model;
  if (!dem::parse_damping_model(model_text, model))
    g.fail("", "attribute damping_model: is '" + model_text + "', must be " + dem::damping_model_names());
  // damping_ratio holds the model's parameter (xi, e or a; mass_damping.h)
  const double ratio = read_checked(g, "damping_ratio", finite, "finite");
  const std::string bad = dem::damping_parameter_error(model, ratio);
  if (!bad.empty()) g.fail("damping_ratio", bad + " for damping model " + model_text);
  st.damping = dem::MassDamping(model, ratio);
  st.time_step_ratio = read_checked(g, "time_step_ratio", positive, "finite and > 0");
  if (g.has_attr("time_step_basis")) {
    const std::string basis = g.attr_string("time_step_basis");
    if (!dem::parse_time_step_basis(basis, st.time_step_basis))
      g.fail("", "attribute time_step_basis: is '" + basis + "', must be reference or contacts");
    st.time_step_safety = read_checked(g, "time_step_safety", positive, "finite and > 0");
    st.time_step_max_ratio = read_checked(g, "time_step_max_ratio", positive, "finite and > 0");
    time_step = read_checked(g, "time_step", positive, "finite and > 0");
    critical = g.read_scalar<double>("contact_critical_step");
    if (!(critical > 0.0)) g.fail("contact_critical_step", "is " + number(critical) + ", must be > 0 (inf allowed)");
    virial = read_checked(g, "contact_refresh_virial", non_negative, "finite and >= 0");
  }
  st.skin_ratio = read_checked(g, "skin_ratio", non_negative, "finite and >= 0");
  st.check_interval = g.read_scalar<std::int64_t>("check_interval");
  if (st.check_interval <= 0) g.fail("check_interval", "is " + std::to_string(st.check_interval) + ", must be > 0");
  st.limits.max_overlap_ratio = read_checked(g, "max_overlap_ratio", positive, "finite and > 0");
  st.limits.max_energy_error = read_checked(g, "max_energy_error", positive, "finite and > 0");
}

void read_energy(const h5::Group& root, dem::EnergyBudget& e) {
  const h5::Group g = root.open_group("energy");
  e.boundary_work = read_checked(g, "boundary_work", finite, "finite");
  e.damping = read_checked(g, "damping", finite, "finite");
  e.friction = read_checked(g, "friction", finite, "finite");
  e.kinetic_translational = read_checked(g, "kinetic_translational", finite, "finite");
  e.kinetic_rotational = read_checked(g, "kinetic_rotational", finite, "finite");
  e.elastic = read_checked(g, "elastic", finite, "finite");
  e.kinetic_reference = read_checked(g, "kinetic_reference", finite, "finite");
  e.elastic_reference = read_checked(g, "elastic_reference", finite, "finite");
  const std::uint8_t has = g.read_scalar<std::uint8_t>("has_reference");
  if (has > 1) g.fail("has_reference", "is " + std::to_string(has) + ", must be 0 or 1");
  e.has_reference = has == 1;
}

SampleMetadata read_preparation(const h5::Group& root) {
  const h5::Group g = root.open_group("preparation");
  SampleMetadata m;
  m.seed = g.read_scalar<std::uint64_t>("seed");
  m.friction_during_shrinkage = g.read_scalar<double>("friction_during_shrinkage");
  m.target_pressure = g.read_scalar<double>("target_pressure");
  m.initial_void_ratio = g.read_scalar<double>("initial_void_ratio");
  for (const char* name : {"software_version", "created_by", "description"})
    if (!g.has_attr(name)) g.fail("", std::string("attribute ") + name + ": missing");
  m.software_version = g.attr_string("software_version");
  m.created_by = g.attr_string("created_by");
  m.description = g.attr_string("description");
  return m;
}

}  // namespace

void write_sample_into(const h5::Group& root, const dem::SimulationState& s, const SampleMetadata& meta) {
  check_state(root.file(), s);
  root.set_attr("format", kSampleFormat);
  root.set_attr("format_version", kSampleFormatVersion);
  write_particles(root, s);
  write_contacts(root, s.contacts);
  write_rest(root, s, meta);
}

void write_sample(const std::string& path, const dem::SimulationState& s, const SampleMetadata& meta) {
  check_state(path, s);
  h5::AtomicFile file(path);  // removes the temporary file unless committed
  write_sample_into(file.root(), s, meta);
  file.commit();
}

dem::SimulationState read_sample_from(const h5::Group& root, SampleMetadata* meta) {
  check_format(root);
  dem::SimulationState s;
  read_particles(root, s.particles);
  s.contacts = read_contacts(root, s.particles.id);
  read_cell(root, s);
  read_settings(root, s.settings, s.time_step, s.contact_critical_step, s.contact_refresh_virial);
  read_energy(root, s.energy);
  const SampleMetadata m = read_preparation(root);
  if (meta != nullptr) *meta = m;
  return s;
}

dem::SimulationState read_sample(const std::string& path, SampleMetadata* meta) {
  return read_sample_from(h5::Group::open_file_read(path), meta);
}

}  // namespace vt::io
