#include "virtual_triaxial/io/lammps_data_file.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <unordered_map>
#include <vector>

namespace vt::io {

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Reader {
  std::string path;
  std::ifstream in;
  long line_no = 0;
  std::string comment;  ///< the comment of the last line read (after '#')

  [[noreturn]] void fail(const std::string& why) const {
    throw std::runtime_error(path + ":" + std::to_string(line_no) + ": " + why);
  }
  /// Next line without its comment, trimmed; false at the end of the file.
  bool next(std::string& out) {
    if (!std::getline(in, out)) return false;
    ++line_no;
    const std::size_t hash = out.find('#');
    comment = hash == std::string::npos ? std::string() : out.substr(hash + 1);
    if (hash != std::string::npos) out.erase(hash);
    const std::size_t b = out.find_first_not_of(" \t\r"), e = out.find_last_not_of(" \t\r");
    out = b == std::string::npos ? std::string() : out.substr(b, e - b + 1);
    return true;
  }
};

std::vector<std::string> words(const std::string& s) {
  std::istringstream is(s);
  std::vector<std::string> w;
  for (std::string t; is >> t;) w.push_back(t);
  return w;
}

double to_number(const Reader& r, const std::string& w, const char* what) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(w.c_str(), &end);
  if (w.empty() || *end != '\0' || errno != 0 || !std::isfinite(v))
    r.fail(std::string(what) + ": '" + w + "' is not a finite number");
  return v;
}

long long to_integer(const Reader& r, const std::string& w, const char* what) {
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(w.c_str(), &end, 10);
  if (w.empty() || *end != '\0' || errno != 0) r.fail(std::string(what) + ": '" + w + "' is not an integer");
  return v;
}

struct Atom {
  long line = 0;
  double diameter = 0, density = 0;
  dem::Vec3 x;
};

}  // namespace

dem::SimulationState read_lammps_data(const std::string& path, const dem::Material& material,
                                      const dem::SimulationSettings& settings) {
  Reader r{path, std::ifstream(path), 0, {}};
  if (!r.in) throw std::runtime_error(path + ": cannot open");
  std::string line;
  if (!r.next(line)) throw std::runtime_error(path + ": empty file");  // line 1: comment
  long long n_atoms = -1;
  double lo[3] = {0, 0, 0}, len[3] = {-1, -1, -1}, tilt[3] = {0, 0, 0};
  bool have_axis[3] = {false, false, false};
  const char* axis_words[3][2] = {{"xlo", "xhi"}, {"ylo", "yhi"}, {"zlo", "zhi"}};
  std::string section, section_comment;
  // Header: until the first section keyword.
  while (r.next(line)) {
    if (line.empty()) continue;
    const std::vector<std::string> w = words(line);
    if (w.size() == 2 && w[1] == "atoms") {
      n_atoms = to_integer(r, w[0], "atoms");
      if (n_atoms < 2) r.fail("atoms: at least 2 are needed, got " + w[0]);
    } else if (w.size() == 3 && w[1] == "atom" && w[2] == "types") {
      if (to_integer(r, w[0], "atom types") < 1) r.fail("atom types: must be >= 1");
    } else if (w.size() == 4 && (w[2] == "xlo" || w[2] == "ylo" || w[2] == "zlo")) {
      const int a = w[2][0] - 'x';
      if (w[3] != axis_words[a][1]) r.fail("expected '" + std::string(axis_words[a][0]) + " " + axis_words[a][1] + "'");
      lo[a] = to_number(r, w[0], axis_words[a][0]);
      len[a] = to_number(r, w[1], axis_words[a][1]) - lo[a];
      if (!(len[a] > 0)) r.fail(std::string(axis_words[a][1]) + " must exceed " + axis_words[a][0]);
      have_axis[a] = true;
    } else if (w.size() == 6 && w[3] == "xy" && w[4] == "xz" && w[5] == "yz") {
      for (int k = 0; k < 3; ++k) tilt[k] = to_number(r, w[k], "tilt factor");
    } else if (w.size() >= 2 && (w[1] == "bonds" || w[1] == "angles" || w[1] == "dihedrals" || w[1] == "impropers")) {
      if (to_integer(r, w[0], w[1].c_str()) != 0) r.fail(w[1] + ": not supported (granular samples have none)");
    } else if (w[0] == "Atoms" || w[0] == "Velocities" || w[0] == "Masses") {
      section = line;
      section_comment = r.comment;
      break;
    } else {
      r.fail("unknown header line '" + line + "'");
    }
  }
  if (n_atoms < 0) throw std::runtime_error(path + ": header: 'N atoms' missing");
  for (int a = 0; a < 3; ++a)
    if (!have_axis[a])
      throw std::runtime_error(path + ": header: '" + axis_words[a][0] + " " + axis_words[a][1] + "' missing");

  std::unordered_map<long long, Atom> atoms;
  std::unordered_map<long long, std::pair<dem::Vec3, dem::Vec3>> velocities;
  std::vector<long long> order;
  bool have_atoms = false;
  while (!section.empty()) {
    const std::vector<std::string> head = words(section);
    const long head_line = r.line_no;
    const bool is_atoms = head[0] == "Atoms", is_vel = head[0] == "Velocities";
    if (!is_atoms && !is_vel) r.fail("section '" + head[0] + "' not supported (atom_style sphere: Atoms, Velocities)");
    if (is_atoms && words(section_comment).size() > 0 && words(section_comment)[0] != "sphere")
      r.fail("Atoms section of another atom style ('" + words(section_comment)[0] + "'); atom_style sphere is needed");
    if ((is_atoms && have_atoms) || (is_vel && !velocities.empty())) r.fail("section '" + head[0] + "' twice");
    long long count = 0;
    section.clear();
    while (r.next(line)) {
      if (line.empty()) continue;
      const std::vector<std::string> w = words(line);
      if (!std::isdigit(static_cast<unsigned char>(w[0][0])) && w[0][0] != '-') {
        section = line;
        section_comment = r.comment;
        break;
      }
      const long long id = to_integer(r, w[0], "atom-ID");
      if (id < 1) r.fail("atom-ID: must be >= 1, got " + w[0]);
      if (is_atoms) {
        if (w.size() != 7 && w.size() != 10)
          r.fail("Atoms (sphere) line needs 7 or 10 columns (id type diameter density x y z [ix iy iz]), got " +
                 std::to_string(w.size()));
        Atom at;
        at.line = r.line_no;
        to_integer(r, w[1], "atom-type");
        at.diameter = to_number(r, w[2], "diameter");
        if (!(at.diameter > 0)) r.fail("diameter: must be > 0 (point particles are not granular)");
        at.density = to_number(r, w[3], "density");
        if (!(at.density > 0)) r.fail("density: must be > 0");
        at.x = {to_number(r, w[4], "x"), to_number(r, w[5], "y"), to_number(r, w[6], "z")};
        if (!atoms.emplace(id, at).second) r.fail("atom-ID " + w[0] + " appears twice");
        order.push_back(id);
      } else {
        if (w.size() != 7) r.fail("Velocities (sphere) line needs 7 columns (id vx vy vz wx wy wz)");
        dem::Vec3 v{to_number(r, w[1], "vx"), to_number(r, w[2], "vy"), to_number(r, w[3], "vz")};
        dem::Vec3 om{to_number(r, w[4], "wx"), to_number(r, w[5], "wy"), to_number(r, w[6], "wz")};
        if (!velocities.emplace(id, std::make_pair(v, om)).second) r.fail("atom-ID " + w[0] + " appears twice");
      }
      ++count;
    }
    if (count != n_atoms) {
      r.line_no = head_line;
      r.fail("section '" + head[0] + "' holds " + std::to_string(count) + " lines, the header says " +
             std::to_string(n_atoms) + " atoms");
    }
    have_atoms = have_atoms || is_atoms;
  }
  if (!have_atoms) throw std::runtime_error(path + ": no Atoms section");

  dem::SimulationState s;
  s.settings = settings;
  s.settings.material = material;
  s.settings.material.density = atoms.at(order.front()).density;
  dem::Mat3 h;
  h.m[0][0] = len[0];
  h.m[0][1] = tilt[0];
  h.m[1][1] = len[1];
  h.m[0][2] = tilt[1];
  h.m[1][2] = tilt[2];
  h.m[2][2] = len[2];
  s.h = s.h_reference = h;
  const dem::PeriodicCell cell(h, h);
  dem::Particles& p = s.particles;
  p.reserve(order.size());
  for (long long id : order) {
    const Atom& at = atoms.at(id);
    if (at.density != s.settings.material.density) {
      r.line_no = at.line;
      r.fail("density: every atom needs the same density (one material), here " + std::to_string(at.density) +
             " against " + std::to_string(s.settings.material.density));
    }
    const dem::Vec3 frac = dem::PeriodicCell::wrap(cell.to_fractional(at.x - dem::Vec3{lo[0], lo[1], lo[2]}));
    dem::Vec3 v, om;
    const auto vel = velocities.find(id);
    if (vel != velocities.end()) std::tie(v, om) = vel->second;
    p.add_sphere(id - 1, 0.5 * at.diameter, at.density, frac, v, om);
  }
  if (!velocities.empty())
    for (const auto& kv : velocities)
      if (!atoms.count(kv.first))
        throw std::runtime_error(path + ": Velocities: atom-ID " + std::to_string(kv.first) + " has no Atoms line");
  return s;
}

void write_lammps_data(const std::string& path, const dem::SimulationState& s) {
  const dem::Particles& p = s.particles;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.id[i] < 0) throw std::runtime_error(path + ": particle ids must be >= 0 (atom-ID = id + 1)");
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.shape[i] != dem::Shape::Sphere)
      throw std::runtime_error(path + ": atom_style sphere holds spheres only (particle " + std::to_string(p.id[i]) +
                               " is a spheroid)");
  const dem::Mat3& h = s.h;
  if (h.m[1][0] != 0 || h.m[2][0] != 0 || h.m[2][1] != 0)
    throw std::runtime_error(path + ": the cell must be upper triangular (LAMMPS restricted triclinic)");
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "w");
  if (!f) throw std::runtime_error(path + ": cannot write");
  std::fprintf(f, "LAMMPS data file (atom_style sphere, units si) written by virtual_triaxial\n\n");
  std::fprintf(f, "%zu atoms\n1 atom types\n\n", p.size());
  std::fprintf(f, "0 %.17g xlo xhi\n0 %.17g ylo yhi\n0 %.17g zlo zhi\n", h.m[0][0], h.m[1][1], h.m[2][2]);
  if (h.m[0][1] != 0 || h.m[0][2] != 0 || h.m[1][2] != 0)
    std::fprintf(f, "%.17g %.17g %.17g xy xz yz\n", h.m[0][1], h.m[0][2], h.m[1][2]);
  std::fprintf(f, "\nAtoms # sphere\n\n");
  const dem::PeriodicCell cell(s.h, s.h_reference);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double volume = 4.0 / 3.0 * kPi * p.radius[i] * p.radius[i] * p.radius[i];
    const dem::Vec3 x = cell.to_cartesian(p.frac[i]);
    std::fprintf(f, "%lld 1 %.17g %.17g %.17g %.17g %.17g\n", static_cast<long long>(p.id[i]) + 1, 2.0 * p.radius[i],
                 p.mass[i] / volume, x.x, x.y, x.z);
  }
  std::fprintf(f, "\nVelocities\n\n");
  for (std::size_t i = 0; i < p.size(); ++i) {
    const dem::Vec3 v = p.velocity[i] + s.velocity_gradient * cell.to_cartesian(p.frac[i]);
    const dem::Vec3& w = p.omega[i];
    std::fprintf(f, "%lld %.17g %.17g %.17g %.17g %.17g %.17g\n", static_cast<long long>(p.id[i]) + 1, v.x, v.y, v.z,
                 w.x, w.y, w.z);
  }
  const bool ok = std::fclose(f) == 0;
  if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) throw std::runtime_error(path + ": cannot write");
}

}  // namespace vt::io
