// Typed, path-aware access to yaml-cpp nodes for the scene parser.
//
// Every getter throws vt::io::SceneError naming the dotted path of the field
// (e.g. `particles.list[3].radius`) when the value is missing or has the
// wrong type. Numbers must be finite (.inf / .nan / overflow are rejected);
// integers accept plain integer literals and exactly-integral decimal forms
// such as 2.0e4 (up to 2^53), and reject 1.5. Range checks (> 0, ...) are the
// caller's business; `require()` throws with the path for them.
//
// Only the scene parser (src/io/scene_parser.cpp) uses this header; it is the
// one place in the io library that includes yaml-cpp.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "virtual_triaxial/dem/vec3.h"
#include "virtual_triaxial/io/scene_error.h"

namespace vt::io::yaml_fields {

/// "a" + "b" -> "a.b"; "" + "b" -> "b".
std::string join(const std::string& parent, const std::string& key);
/// "a" + 3 -> "a[3]".
std::string index(const std::string& parent, std::size_t i);
/// Short description of a node for error messages: "'abc'", "a list", ...
std::string describe(const YAML::Node& node);

/// Throws SceneError(path, reason) unless `ok`.
void require(bool ok, const std::string& path, const std::string& reason);

double as_number(const YAML::Node& node, const std::string& path);
std::int64_t as_integer(const YAML::Node& node, const std::string& path);
std::string as_string(const YAML::Node& node, const std::string& path);
/// A list of exactly three numbers.
dem::Vec3 as_vec3(const YAML::Node& node, const std::string& path);
/// Throws unless the node is a (block or flow) sequence.
void expect_list(const YAML::Node& node, const std::string& path);

/// A mapping section of the scene with a closed set of allowed keys.
/// Construction checks that the node is a mapping (absent or null counts as
/// an empty mapping), that every key is a scalar, that no key appears twice
/// and that every key is in `allowed`; an unknown key is reported with its
/// own path and the list of allowed keys.
class Section {
 public:
  Section(const YAML::Node& node, std::string path, std::vector<std::string> allowed);

  const std::string& path() const { return path_; }
  std::string path(const std::string& key) const { return join(path_, key); }
  /// True when the mapping holds `key` (even with a null value).
  bool has(const std::string& key) const;
  /// The value of `key`; an undefined node when absent.
  YAML::Node get(const std::string& key) const;
  /// Throws "<path>.<key>: required" when absent.
  YAML::Node required(const std::string& key) const;

  double number(const std::string& key) const;
  double number_or(const std::string& key, double fallback) const;
  std::optional<double> opt_number(const std::string& key) const;
  std::int64_t integer(const std::string& key) const;
  std::int64_t integer_or(const std::string& key, std::int64_t fallback) const;
  std::optional<std::int64_t> opt_integer(const std::string& key) const;
  std::string string(const std::string& key) const;
  std::string string_or(const std::string& key, const std::string& fallback) const;
  dem::Vec3 vec3(const std::string& key) const;
  dem::Vec3 vec3_or(const std::string& key, const dem::Vec3& fallback) const;

 private:
  YAML::Node node_;
  std::string path_;
};

}  // namespace vt::io::yaml_fields
