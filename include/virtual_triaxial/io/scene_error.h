// Error raised while reading a scene file (config/scenes/*.yaml).
//
// Carries the dotted path of the offending field, e.g.
// `stages[1].stop.axial_strain`, `material.poisson_ratio`,
// `particles.list[3].radius` (list indices are 0-based, as in the YAML
// sequence), and the reason. Errors about the file as a whole (cannot open,
// YAML syntax error, empty document) use the field "scene".
// what() is "<field>: <reason>".
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace vt::io {

class SceneError : public std::runtime_error {
 public:
  SceneError(std::string field, std::string reason)
      : std::runtime_error(field + ": " + reason),
        field_(std::move(field)),
        reason_(std::move(reason)) {}

  /// Dotted path of the offending field ("scene" for file-level errors).
  const std::string& field() const { return field_; }
  /// Human-readable reason, without the field.
  const std::string& reason() const { return reason_; }

 private:
  std::string field_;
  std::string reason_;
};

}  // namespace vt::io
