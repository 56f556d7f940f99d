// YAML scene parser: config/scenes/*.yaml -> vt::io::SceneConfig.
//
// The schema (every key, unit and default) is documented in
// config/scenes/README.md; config/scenes/default.yaml is the reference scene.
// Everything is SI; strain rates and strains are compression positive.
//
// Validation is complete and strict: unknown keys, wrong types, non-finite
// numbers, out-of-range values and inconsistent combinations are all rejected
// with a vt::io::SceneError whose field() is the dotted path of the offending
// value (e.g. `stages[1].stop.axial_strain`, `particles.list[3].radius`; list
// indices are 0-based) and whose reason() says what is wrong. File-level
// problems (cannot open, YAML syntax error with its line, empty document) use
// the field "scene". Nothing is silently ignored or clamped; the one soft
// check is time_step_ratio >= 1, which is accepted with
// SceneConfig::time_step_warning set (the caller reports it).
//
// Decisions beyond the written schema:
//   - cell.lengths is allowed only with particles.list and cell.aspect only
//     with particles.distribution (otherwise they would be silently unused);
//   - axial_axis is allowed only on undrained_shear stages;
//   - strain rates must be > 0 (compression); stage types and axial_axis are
//     matched case-insensitively, like the damping model;
//   - integer fields also accept exactly-integral decimal forms (2.0e4);
//   - an absent or empty (null) optional section means "all defaults".
#pragma once

#include <string>

#include "virtual_triaxial/io/scene_config.h"
#include "virtual_triaxial/io/scene_error.h"

namespace vt::io {

/// Reads and validates the scene file at `path`. A relative
/// particles.sample_file is resolved against the folder of `path`.
/// Throws SceneError (field "scene", reason naming the path and "cannot
/// open") when the file cannot be read.
SceneConfig load_scene(const std::string& path);

/// Parses and validates scene YAML text. `source_path` is stored in
/// SceneConfig::source_path and its folder is the base for a relative
/// particles.sample_file (the current directory when `source_path` is empty).
/// SceneConfig::sample_file is stored as an absolute, normalised path.
SceneConfig parse_scene(const std::string& yaml_text, const std::string& source_path = "");

}  // namespace vt::io
