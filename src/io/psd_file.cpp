#include "virtual_triaxial/io/psd_file.h"
#include "virtual_triaxial/io/number_text.h"

#include "virtual_triaxial/dem/cloud_generator.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "virtual_triaxial/io/yaml_fields.h"

namespace vt::io {
namespace {

namespace fs = std::filesystem;
using yaml_fields::Section;
using yaml_fields::require;

constexpr double kSumTolerance = 1e-6;
const char* const kFileField = "psd";

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string num(double v, int precision = 10) { return number_text(v, precision); }

double positive(const Section& s, const std::string& key) {
  const double v = s.number(key);
  require(v > 0.0, s.path(key), "must be > 0, got " + num(v));
  return v;
}

enum class Basis { Number, Mass };

Basis parse_basis(const Section& top) {
  const std::string field = "fraction_basis";
  require(top.has(field), field, "required: number or mass");
  const std::string given = top.string(field);
  const std::string l = lower(given);
  if (l == "number") return Basis::Number;
  if (l == "mass") return Basis::Mass;
  throw SceneError(field, "must be 'number' or 'mass', got '" + given + "'");
}

PsdType parse_type(const YAML::Node& node, const std::string& path) {
  require(node.IsDefined() && node.IsMap(), path,
          "expected a mapping {major_semi_axis, minor_semi_axis, fraction} or {radius, fraction}, got " +
              yaml_fields::describe(node));
  const Section t(node, path, {"major_semi_axis", "minor_semi_axis", "radius", "fraction"});
  const bool has_major = t.has("major_semi_axis");
  const bool has_minor = t.has("minor_semi_axis");
  PsdType out;
  if (t.has("radius")) {
    require(!has_major && !has_minor, t.path("radius"),
            "give either radius (a sphere) or major_semi_axis and minor_semi_axis (a spheroid), "
            "not both");
    out.major_semi_axis = out.minor_semi_axis = positive(t, "radius");
  } else {
    require(has_major || has_minor, path,
            "give radius (a sphere) or major_semi_axis and minor_semi_axis (a spheroid)");
    require(has_major, t.path("major_semi_axis"), "required together with minor_semi_axis");
    require(has_minor, t.path("minor_semi_axis"), "required together with major_semi_axis");
    out.major_semi_axis = positive(t, "major_semi_axis");
    out.minor_semi_axis = positive(t, "minor_semi_axis");
    require(out.minor_semi_axis <= out.major_semi_axis, t.path("minor_semi_axis"),
            "must be <= major_semi_axis (" + num(out.major_semi_axis) + "), got " +
                num(out.minor_semi_axis));
  }
  out.fraction = positive(t, "fraction");
  return out;
}

// Volume of `t` relative to `ref` (both ~ a b^2), computed as a product of
// ratios so that no unit choice can underflow.
double relative_volume(const PsdType& t, const PsdType& ref) {
  const double rb = t.minor_semi_axis / ref.minor_semi_axis;
  return (t.major_semi_axis / ref.major_semi_axis) * rb * rb;
}

// Converts the fractions in place to number fractions summing to 1.
void to_number_fractions(std::vector<PsdType>& types, Basis basis) {
  if (basis == Basis::Mass) {
    for (auto& t : types) t.fraction /= relative_volume(t, types.front());
  }
  double sum = 0.0;
  for (const auto& t : types) sum += t.fraction;
  for (auto& t : types) t.fraction /= sum;
}

Psd parse_document(const YAML::Node& doc, const std::string& source) {
  require(doc.IsMap(), kFileField,
          "expected a mapping with `fraction_basis` and `types`, got " + yaml_fields::describe(doc));
  for (auto it = doc.begin(); it != doc.end(); ++it)
    require(it->first.IsScalar(), kFileField,
            "keys must be plain names, got " + yaml_fields::describe(it->first));
  const Section top(doc, "", {"name", "fraction_basis", "types"});

  Psd psd;
  psd.name = top.string_or("name", source.empty() ? std::string() : fs::path(source).stem().string());
  const Basis basis = parse_basis(top);

  require(top.has("types"), "types", "required: a non-empty list of particle types");
  const YAML::Node types = top.get("types");
  require(!types.IsNull() && !(types.IsSequence() && types.size() == 0), "types",
          "empty; list at least one particle type");
  yaml_fields::expect_list(types, "types");

  double sum = 0.0;
  for (std::size_t i = 0; i < types.size(); ++i) {
    psd.types.push_back(parse_type(types[i], yaml_fields::index("types", i)));
    sum += psd.types.back().fraction;
  }
  require(std::fabs(sum - 1.0) <= kSumTolerance, "types",
          std::string(basis == Basis::Mass ? "mass" : "number") + " fractions sum to " +
              num(sum, 12) + "; they must sum to 1 (within 1e-6)");
  to_number_fractions(psd.types, basis);
  return psd;
}

void check_type(const PsdType& t, std::size_t i) {
  const auto bad = [](double v) { return !(std::isfinite(v) && v > 0.0); };
  if (bad(t.major_semi_axis) || bad(t.minor_semi_axis))
    throw std::invalid_argument("dispersity_index: type " + std::to_string(i) +
                                " has a non-positive or non-finite semi-axis");
  if (!(std::isfinite(t.fraction) && t.fraction >= 0.0))
    throw std::invalid_argument("dispersity_index: type " + std::to_string(i) +
                                " has a negative or non-finite fraction");
}

}  // namespace

Psd parse_psd(const std::string& yaml, const std::string& source) {
  const std::string in = source.empty() ? "" : " in '" + source + "'";
  std::vector<YAML::Node> docs;
  try {
    docs = YAML::LoadAll(yaml);
  } catch (const YAML::ParserException& e) {
    throw SceneError(kFileField, "YAML syntax error" + in + " at line " + std::to_string(e.mark.line + 1) +
                                     ", column " + std::to_string(e.mark.column + 1) + ": " + e.msg);
  } catch (const YAML::Exception& e) {
    throw SceneError(kFileField, "cannot parse YAML" + in + ": " + e.what());
  }
  require(!docs.empty() && !docs[0].IsNull(), kFileField,
          "empty document" + in + "; expected a mapping with `fraction_basis` and `types`");
  require(docs.size() == 1, kFileField,
          "holds " + std::to_string(docs.size()) + " YAML documents" + in + "; expected one");
  try {
    return parse_document(docs[0], source);
  } catch (const YAML::Exception& e) {  // should not happen: fields are read without as<>()
    throw SceneError(kFileField, std::string("unexpected YAML error") + in + ": " + e.what());
  }
}

Psd load_psd(const std::string& path) {
  std::error_code ec;
  require(!fs::is_directory(path, ec), kFileField, "cannot open '" + path + "': is a directory");
  errno = 0;
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    const int err = errno;
    throw SceneError(kFileField, "cannot open '" + path + "'" +
                                     (err != 0 ? std::string(": ") + std::strerror(err) : std::string()));
  }
  std::ostringstream text;
  text << file.rdbuf();
  require(!file.bad(), kFileField, "cannot read '" + path + "'");
  return parse_psd(text.str(), path);
}

double nominal_radius(const PsdType& type) {
  // b cbrt(a/b) == cbrt(a b^2); exact for a sphere and free of under/overflow.
  return type.minor_semi_axis * std::cbrt(type.major_semi_axis / type.minor_semi_axis);
}

std::vector<std::pair<double, double>> nominal_radius_table(const Psd& psd) {
  std::vector<std::pair<double, double>> out;
  out.reserve(psd.types.size());
  for (const auto& t : psd.types) out.emplace_back(nominal_radius(t), t.fraction);
  return out;
}

PsdParticles psd_particles(const Psd& psd, std::int64_t count) {
  PsdParticles out;
  out.radii = dem::table_radii(count, nominal_radius_table(psd));
  out.aspect_ratios.reserve(out.radii.size());
  for (double r : out.radii) {
    double k = 1.0;
    for (const PsdType& t : psd.types)
      if (nominal_radius(t) == r) {  // the same computation as in the table: exact
        k = t.major_semi_axis / t.minor_semi_axis;
        break;
      }
    out.aspect_ratios.push_back(k);
  }
  return out;
}

double dispersity_index(const Psd& psd) {
  if (psd.types.empty()) throw std::invalid_argument("dispersity_index: the PSD has no types");
  for (std::size_t i = 0; i < psd.types.size(); ++i) check_type(psd.types[i], i);
  // d_min over the types that are present (fraction > 0).
  double r_min = 0.0;
  for (const auto& t : psd.types)
    if (t.fraction > 0.0) {
      const double r = nominal_radius(t);
      if (r_min == 0.0 || r < r_min) r_min = r;
    }
  if (r_min == 0.0) throw std::invalid_argument("dispersity_index: every fraction is zero");
  // Delta = sum m_i (d_i/d_min) / sum m_i, m_i ~ x_i (d_i/d_min)^3.
  double mass = 0.0, moment = 0.0;
  for (const auto& t : psd.types) {
    const double s = nominal_radius(t) / r_min;
    const double m = t.fraction * s * s * s;
    mass += m;
    moment += m * s;
  }
  return moment / mass;
}

}  // namespace vt::io
