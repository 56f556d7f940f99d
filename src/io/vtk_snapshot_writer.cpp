#include "virtual_triaxial/io/vtk_snapshot_writer.h"

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <stdexcept>
#include <system_error>

#include "virtual_triaxial/io/atomic_text_file.h"

namespace fs = std::filesystem;

namespace vt::io {

namespace {

using dem::Mat3;
using dem::SpecimenSnapshot;
using dem::Vec3;

/// Appends numbers, shortest round-trip form, separated by spaces.
class Text {
 public:
  std::string s;
  void num(double v) {
    v += 0.0;  // -0 -> 0
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    s.append(buf, r.ptr);
    s += ' ';
  }
  void num(std::int64_t v) {
    char buf[24];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    s.append(buf, r.ptr);
    s += ' ';
  }
  void vec(const Vec3& v) {
    num(v.x);
    num(v.y);
    num(v.z);
  }
  void mat(const Mat3& m) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) num(m.m[a][b]);
  }
  /// <DataArray ...> values </DataArray>; emit(i) appends the values of tuple i.
  template <class Emit>
  void array(const char* type, const char* name, int components, std::size_t n, Emit&& emit) {
    s += "<DataArray type=\"";
    s += type;
    s += "\" Name=\"";
    s += name;
    s += "\" NumberOfComponents=\"" + std::to_string(components) + "\" NumberOfTuples=\"" + std::to_string(n) +
         "\" format=\"ascii\">\n";
    for (std::size_t i = 0; i < n; ++i) {
      emit(i);
      if (i % 8 == 7) s += '\n';
    }
    s += "\n</DataArray>\n";
  }
  /// Connectivity and offsets of n cells of `per` consecutive points each.
  void cells(const char* tag, std::size_t n, int per) {
    s += std::string("<") + tag + ">\n";
    array("Int64", "connectivity", 1, n * static_cast<std::size_t>(per),
          [&](std::size_t i) { num(static_cast<std::int64_t>(i)); });
    array("Int64", "offsets", 1, n, [&](std::size_t i) { num(static_cast<std::int64_t>((i + 1) * static_cast<std::size_t>(per))); });
    s += std::string("</") + tag + ">\n";
  }
};

void field_data(Text& t, const SpecimenSnapshot& s);

/// Header, the dataset's field data (which VTK reads only here, before the
/// piece) and the piece's start.
void open_poly(Text& t, const SpecimenSnapshot& s, std::size_t points, std::size_t verts, std::size_t lines) {
  t.s += "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
         "<PolyData>\n";
  field_data(t, s);
  t.s += "<Piece NumberOfPoints=\"" + std::to_string(points) + "\" NumberOfVerts=\"" + std::to_string(verts) +
         "\" NumberOfLines=\"" + std::to_string(lines) + "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n";
}

void close_poly(Text& t) { t.s += "</Piece>\n</PolyData>\n</VTKFile>\n"; }

void field_data(Text& t, const SpecimenSnapshot& s) {
  t.s += "<FieldData>\n";
  t.array("Float64", "TimeValue", 1, 1, [&](std::size_t) { t.num(s.time); });
  t.array("Int64", "step", 1, 1, [&](std::size_t) { t.num(s.step); });
  t.array("Float64", "cell_matrix", 9, 1, [&](std::size_t) { t.mat(s.h); });
  t.array("Float64", "strain", 3, 1, [&](std::size_t) { t.vec(s.strain); });
  t.array("Float64", "stress", 9, 1, [&](std::size_t) { t.mat(s.stress); });
  t.s += "</FieldData>\n";
}

std::string index_name(const char* stem, std::size_t k) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s_%06zu.vtp", stem, k);
  return buf;
}

std::string clean_label(std::string label) {
  for (char& c : label)
    if (c == ',' || c == '\n' || c == '\r' || c == '"') c = ' ';
  return label;
}

}  // namespace

std::string vtk_particles_document(const SpecimenSnapshot& s) {
  const std::size_t n = s.position.size();
  Text t;
  t.s.reserve(n * 600 + 4096);
  open_poly(t, s, n, n, 0);
  t.s += "<PointData Scalars=\"radius\" Vectors=\"velocity\">\n";
  t.array("Int64", "id", 1, n, [&](std::size_t i) { t.num(s.id[i]); });
  t.array("UInt8", "shape", 1, n, [&](std::size_t i) { t.num(static_cast<std::int64_t>(s.shape[i])); });
  t.array("Float64", "radius", 1, n, [&](std::size_t i) { t.num(s.radius[i]); });
  t.array("Float64", "diameter", 1, n, [&](std::size_t i) { t.num(2.0 * s.radius[i]); });
  t.array("Float64", "semi_axes", 3, n, [&](std::size_t i) { t.vec(s.semi_axes[i]); });
  t.array("Float64", "orientation", 4, n, [&](std::size_t i) {
    const dem::Quaternion& q = s.orientation[i];
    t.num(q.w);
    t.num(q.x);
    t.num(q.y);
    t.num(q.z);
  });
  t.array("Float64", "symmetry_axis", 3, n, [&](std::size_t i) { t.vec(s.orientation[i].rotate({1, 0, 0})); });
  t.array("Float64", "shape_tensor", 9, n, [&](std::size_t i) {
    // R diag(2a, 2b, 2b) R^T = 2b I + 2(a - b) e e^T, e the symmetry axis.
    const Vec3 e = s.orientation[i].rotate({1, 0, 0});
    const double a = s.semi_axes[i].x, b = s.semi_axes[i].y;
    const double c[3] = {e.x, e.y, e.z};
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) t.num(2.0 * (a - b) * c[r] * c[k] + (r == k ? 2.0 * b : 0.0));
  });
  t.array("Float64", "velocity", 3, n, [&](std::size_t i) { t.vec(s.velocity[i]); });
  t.array("Float64", "spin", 3, n, [&](std::size_t i) { t.vec(s.spin[i]); });
  t.array("Int32", "contact_count", 1, n, [&](std::size_t i) { t.num(static_cast<std::int64_t>(s.contact_count[i])); });
  t.array("UInt8", "idle", 1, n, [&](std::size_t i) { t.num(static_cast<std::int64_t>(s.idle[i])); });
  t.s += "</PointData>\n<Points>\n";
  t.array("Float64", "Points", 3, n, [&](std::size_t i) { t.vec(s.position[i]); });
  t.s += "</Points>\n";
  t.cells("Verts", n, 1);
  close_poly(t);
  return std::move(t.s);
}

std::string vtk_contacts_document(const SpecimenSnapshot& s) {
  const std::size_t m = s.contacts.size();
  const auto& c = s.contacts;
  Text t;
  t.s.reserve(m * 500 + 4096);
  open_poly(t, s, 2 * m, 0, m);
  t.s += "<PointData Scalars=\"normal_force\">\n";
  t.array("Float64", "normal_force", 1, 2 * m, [&](std::size_t k) { t.num(norm(c[k / 2].normal_force)); });
  t.s += "</PointData>\n<CellData Scalars=\"normal_force\">\n";
  t.array("Int64", "id_i", 1, m, [&](std::size_t k) { t.num(s.id[static_cast<std::size_t>(c[k].i)]); });
  t.array("Int64", "id_j", 1, m, [&](std::size_t k) { t.num(s.id[static_cast<std::size_t>(c[k].j)]); });
  t.array("Float64", "branch", 3, m, [&](std::size_t k) { t.vec(c[k].branch); });
  t.array("Float64", "normal_force", 1, m, [&](std::size_t k) { t.num(norm(c[k].normal_force)); });
  t.array("Float64", "normal_force_vector", 3, m, [&](std::size_t k) { t.vec(c[k].normal_force); });
  t.array("Float64", "tangential_force", 3, m, [&](std::size_t k) { t.vec(c[k].tangential_force); });
  t.array("Float64", "tangential_force_magnitude", 1, m, [&](std::size_t k) { t.num(norm(c[k].tangential_force)); });
  t.array("Float64", "overlap", 1, m, [&](std::size_t k) { t.num(c[k].overlap); });
  t.array("UInt8", "sliding", 1, m, [&](std::size_t k) { t.num(static_cast<std::int64_t>(c[k].sliding)); });
  t.s += "</CellData>\n<Points>\n";
  t.array("Float64", "Points", 3, 2 * m, [&](std::size_t k) {
    const dem::SnapshotContact& cc = c[k / 2];
    const Vec3& xi = s.position[static_cast<std::size_t>(cc.i)];
    t.vec(k % 2 == 0 ? xi : xi + cc.branch);
  });
  t.s += "</Points>\n";
  t.cells("Lines", m, 2);
  close_poly(t);
  return std::move(t.s);
}

std::string vtk_cell_document(const SpecimenSnapshot& s) {
  // Corners: bit 0, 1, 2 of the index select the edges H e_x, H e_y, H e_z.
  Vec3 corner[8];
  for (int k = 0; k < 8; ++k) corner[k] = s.h * Vec3{double(k & 1), double((k >> 1) & 1), double((k >> 2) & 1)};
  std::vector<std::pair<int, int>> edges;
  for (int k = 0; k < 8; ++k)
    for (int bit = 0; bit < 3; ++bit)
      if (!(k & (1 << bit))) edges.emplace_back(k, k | (1 << bit));
  Text t;
  open_poly(t, s, 8, 0, edges.size());
  t.s += "<Points>\n";
  t.array("Float64", "Points", 3, 8, [&](std::size_t k) { t.vec(corner[k]); });
  t.s += "</Points>\n<Lines>\n";
  t.array("Int64", "connectivity", 1, edges.size(), [&](std::size_t k) {
    t.num(static_cast<std::int64_t>(edges[k].first));
    t.num(static_cast<std::int64_t>(edges[k].second));
  });
  t.array("Int64", "offsets", 1, edges.size(), [&](std::size_t k) { t.num(static_cast<std::int64_t>(2 * (k + 1))); });
  t.s += "</Lines>\n";
  close_poly(t);
  return std::move(t.s);
}

VtkSnapshotSeries::VtkSnapshotSeries(std::string directory) : dir_(std::move(directory)) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_, ec))
    throw std::runtime_error(dir_ + ": cannot create the snapshot directory" + (ec ? ": " + ec.message() : ""));
  const std::regex ours(R"((particles|contacts|cell)(_\d{6}\.vtp|\.pvd)|snapshots\.csv)");
  for (const auto& e : fs::directory_iterator(dir_, ec))
    if (e.is_regular_file() && std::regex_match(e.path().filename().string(), ours)) fs::remove(e.path(), ec);
}

void VtkSnapshotSeries::write(const SpecimenSnapshot& s, const std::string& label) {
  const std::size_t k = entries_.size();
  write_text_file_atomically(dir_ + "/" + index_name("particles", k), vtk_particles_document(s));
  write_text_file_atomically(dir_ + "/" + index_name("contacts", k), vtk_contacts_document(s));
  write_text_file_atomically(dir_ + "/" + index_name("cell", k), vtk_cell_document(s));
  Entry e;
  e.step = s.step;
  e.time = s.time;
  e.label = clean_label(label);
  e.strain = s.strain;
  e.p = s.stress.trace() / 3.0;
  e.contacts = s.contacts.size();
  entries_.push_back(e);
  write_collections();
}

void VtkSnapshotSeries::write_collections() const {
  for (const char* stem : {"particles", "contacts", "cell"}) {
    Text t;
    t.s += "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
           "<Collection>\n";
    for (std::size_t k = 0; k < entries_.size(); ++k) {
      t.s += "<DataSet timestep=\"";
      t.num(entries_[k].time);
      t.s.pop_back();
      t.s += "\" part=\"0\" file=\"" + index_name(stem, k) + "\"/>\n";
    }
    t.s += "</Collection>\n</VTKFile>\n";
    write_text_file_atomically(dir_ + "/" + stem + ".pvd", t.s);
  }
  Text t;
  t.s += "index,step,time_s,label,strain_x,strain_y,strain_z,p_Pa,contacts\n";
  for (std::size_t k = 0; k < entries_.size(); ++k) {
    const Entry& e = entries_[k];
    t.s += std::to_string(k) + "," + std::to_string(e.step) + ",";
    for (double v : {e.time}) {
      t.num(v);
      t.s.back() = ',';
    }
    t.s += e.label + ",";
    for (double v : {e.strain.x, e.strain.y, e.strain.z, e.p}) {
      t.num(v);
      t.s.back() = ',';
    }
    t.s += std::to_string(e.contacts) + "\n";
  }
  write_text_file_atomically(dir_ + "/snapshots.csv", t.s);
}

}  // namespace vt::io
