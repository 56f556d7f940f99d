#include "virtual_triaxial/io/yaml_fields.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <set>
#include <system_error>

namespace vt::io::yaml_fields {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string quoted(const std::string& s) {
  constexpr std::size_t kMax = 40;
  if (s.size() <= kMax) return "'" + s + "'";
  return "'" + s.substr(0, kMax) + "...'";
}

enum class NumStatus { Ok, NotANumber, NotFinite, OutOfRange };

// Locale-independent, full-consumption parse of a decimal floating literal.
// YAML's .inf/.nan spellings are "not finite"; overflow/underflow "out of range".
NumStatus parse_double(const std::string& text, double& out) {
  const std::string s = trim(text);
  const std::string l = lower(s);
  if (l.find("inf") != std::string::npos || l.find("nan") != std::string::npos) {
    // Still "not a number" if it is garbage that merely contains the letters.
    static const std::set<std::string> kSpecial = {
        ".inf", "+.inf", "-.inf", ".nan", "inf", "+inf", "-inf", "nan",
        "infinity", "+infinity", "-infinity"};
    return kSpecial.count(l) ? NumStatus::NotFinite : NumStatus::NotANumber;
  }
  const char* b = s.data();
  const char* e = s.data() + s.size();
  if (b != e && *b == '+') {
    ++b;
    if (b != e && (*b == '+' || *b == '-')) return NumStatus::NotANumber;
  }
  if (b == e) return NumStatus::NotANumber;
  double v = 0.0;
  const auto res = std::from_chars(b, e, v, std::chars_format::general);
  if (res.ec == std::errc::result_out_of_range && res.ptr == e) return NumStatus::OutOfRange;
  if (res.ec != std::errc() || res.ptr != e) return NumStatus::NotANumber;
  if (!std::isfinite(v)) return NumStatus::NotFinite;
  out = v;
  return NumStatus::Ok;
}

}  // namespace

std::string join(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

std::string index(const std::string& parent, std::size_t i) {
  return parent + "[" + std::to_string(i) + "]";
}

std::string describe(const YAML::Node& node) {
  if (!node.IsDefined()) return "nothing";
  switch (node.Type()) {
    case YAML::NodeType::Null: return "no value (null)";
    case YAML::NodeType::Scalar: return quoted(node.Scalar());
    case YAML::NodeType::Sequence: return "a list of " + std::to_string(node.size());
    case YAML::NodeType::Map: return "a mapping";
    default: return "an undefined node";
  }
}

void require(bool ok, const std::string& path, const std::string& reason) {
  if (!ok) throw SceneError(path, reason);
}

double as_number(const YAML::Node& node, const std::string& path) {
  require(node.IsDefined() && node.IsScalar(), path, "expected a number, got " + describe(node));
  double v = 0.0;
  switch (parse_double(node.Scalar(), v)) {
    case NumStatus::Ok: return v;
    case NumStatus::NotFinite:
      throw SceneError(path, "must be a finite number, got " + quoted(node.Scalar()));
    case NumStatus::OutOfRange:
      throw SceneError(path, "must be a finite number within double range, got " + quoted(node.Scalar()));
    default: throw SceneError(path, "expected a number, got " + quoted(node.Scalar()));
  }
}

std::int64_t as_integer(const YAML::Node& node, const std::string& path) {
  require(node.IsDefined() && node.IsScalar(), path, "expected an integer, got " + describe(node));
  const std::string s = trim(node.Scalar());
  const char* b = s.data();
  const char* e = s.data() + s.size();
  if (b != e && *b == '+' && (b + 1 == e || (b[1] != '+' && b[1] != '-'))) ++b;
  std::int64_t i = 0;
  const auto res = std::from_chars(b, e, i, 10);
  if (res.ec == std::errc() && res.ptr == e && b != e) return i;
  if (res.ec == std::errc::result_out_of_range)
    throw SceneError(path, "integer out of range, got " + quoted(s));
  // Exactly-integral decimal forms such as 2.0e4 are accepted.
  double v = 0.0;
  constexpr double kMaxExact = 9007199254740992.0;  // 2^53
  if (parse_double(s, v) == NumStatus::Ok && std::trunc(v) == v) {
    if (std::fabs(v) <= kMaxExact) return static_cast<std::int64_t>(v);
    throw SceneError(path, "integer out of range (written in decimal form, at most 2^53), got " +
                               quoted(s));
  }
  throw SceneError(path, "expected an integer, got " + quoted(node.Scalar()));
}

std::string as_string(const YAML::Node& node, const std::string& path) {
  require(node.IsDefined() && node.IsScalar(), path, "expected a string, got " + describe(node));
  return node.Scalar();
}

void expect_list(const YAML::Node& node, const std::string& path) {
  require(node.IsDefined() && node.IsSequence(), path, "expected a list, got " + describe(node));
}

dem::Vec3 as_vec3(const YAML::Node& node, const std::string& path) {
  require(node.IsDefined() && node.IsSequence() && node.size() == 3, path,
          "expected a list of 3 numbers [x, y, z], got " + describe(node));
  dem::Vec3 v;
  for (std::size_t i = 0; i < 3; ++i) v[static_cast<int>(i)] = as_number(node[i], index(path, i));
  return v;
}

// ---- Section -------------------------------------------------------------------

Section::Section(const YAML::Node& node, std::string path, std::vector<std::string> allowed)
    : path_(std::move(path)) {
  if (!node.IsDefined() || node.IsNull()) return;  // absent / empty section
  require(node.IsMap(), path_.empty() ? "scene" : path_,
          "expected a mapping (key: value), got " + describe(node));
  node_ = node;
  std::set<std::string> seen;
  for (auto it = node.begin(); it != node.end(); ++it) {
    require(it->first.IsScalar(), path_.empty() ? "scene" : path_,
            "keys must be plain names, got " + describe(it->first));
    const std::string key = it->first.Scalar();
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      throw SceneError(join(path_, key),
                       "unknown key; allowed keys" +
                           (path_.empty() ? std::string(" at the top level") : " in " + path_) +
                           ": " + list);
    }
    require(seen.insert(key).second, join(path_, key), "duplicate key");
  }
}

bool Section::has(const std::string& key) const {
  return node_.IsMap() && node_[key].IsDefined();
}

YAML::Node Section::get(const std::string& key) const {
  if (!node_.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
  return node_[key];
}

YAML::Node Section::required(const std::string& key) const {
  require(has(key), path(key), "required");
  return get(key);
}

double Section::number(const std::string& key) const { return as_number(required(key), path(key)); }

double Section::number_or(const std::string& key, double fallback) const {
  return has(key) ? as_number(get(key), path(key)) : fallback;
}

std::optional<double> Section::opt_number(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  return as_number(get(key), path(key));
}

std::int64_t Section::integer(const std::string& key) const {
  return as_integer(required(key), path(key));
}

std::int64_t Section::integer_or(const std::string& key, std::int64_t fallback) const {
  return has(key) ? as_integer(get(key), path(key)) : fallback;
}

std::optional<std::int64_t> Section::opt_integer(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  return as_integer(get(key), path(key));
}

std::string Section::string(const std::string& key) const {
  return as_string(required(key), path(key));
}

std::string Section::string_or(const std::string& key, const std::string& fallback) const {
  return has(key) ? as_string(get(key), path(key)) : fallback;
}

dem::Vec3 Section::vec3(const std::string& key) const { return as_vec3(required(key), path(key)); }

dem::Vec3 Section::vec3_or(const std::string& key, const dem::Vec3& fallback) const {
  return has(key) ? as_vec3(get(key), path(key)) : fallback;
}

}  // namespace vt::io::yaml_fields
