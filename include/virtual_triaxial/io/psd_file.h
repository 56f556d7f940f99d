// Particle-size distribution (PSD) tables: config/psd/*.yaml -> vt::io::Psd.
//
// A PSD is a discrete list of particle types, as in tables 10, 11, 22, 23 and
// 32-38 of Yousefi (2017). Each type is a spheroid with semi-axes
// a = major_semi_axis >= b = c = minor_semi_axis (a sphere has a == b == its
// radius) and a fraction. The file format (all lengths in m, SI):
//
//   name: table33_type1            # optional; default: the file's stem
//   fraction_basis: mass           # required: number | mass (case-insensitive)
//   types:                         # required, non-empty list
//     - {major_semi_axis: 1.2e-3, minor_semi_axis: 1.0e-3, fraction: 0.10}
//     - {radius: 3.0e-3, fraction: 0.90}                  # a sphere
//
// Validation is strict; every problem is a vt::io::SceneError whose field()
// is the dotted path of the offending value (`types[2].minor_semi_axis`,
// `fraction_basis`, ...; list indices 0-based) and whose reason() says what is
// wrong. File-level problems (cannot open, YAML syntax error, empty document)
// use the field "psd". Rejected: unknown keys (top level and per type),
// duplicate keys, an empty or missing `types` list (field `types`, reason
// "empty"), a fraction <= 0, fractions whose sum differs from 1 by more than
// 1e-6 (field `types`, the reason gives the sum), a radius or semi-axis <= 0
// or non-finite, minor_semi_axis > major_semi_axis, `radius` together with a
// semi-axis, only one of the two semi-axes, and a fraction_basis other than
// number/mass.
//
// After loading, Psd::types[i].fraction are NUMBER fractions, renormalised to
// sum to 1: mass fractions w_i are converted with n_i ~ w_i / (a_i b_i^2)
// (equal density for every type, so mass ~ volume ~ a b^2), number fractions
// are only renormalised. The shipped tables (config/psd/README.md) are given
// in mass fractions because the dissertation's dispersity indices follow from
// its weight-ratio columns; the particle counts are kept as comments.
//
// Dispersity index (eq. 80): Delta = d_avg / d_min, d the nominal size (the
// diameter of the sphere of equal volume, 2 cbrt(a b^2)), d_min the smallest
// type's nominal size, d_avg the mass-weighted mean nominal size. Delta = 1
// for a monodisperse PSD and grows with the spread of sizes; it does not
// depend on the length unit or on an overall scale of the sizes.
#pragma once

#include "virtual_triaxial/quasi_static/dispersity_index.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "virtual_triaxial/io/scene_error.h"

namespace vt::io {

/// One particle type of a PSD. A sphere has major == minor == radius.
struct PsdType {
  double major_semi_axis = 0.0;  ///< a [m], the spheroid's symmetry semi-axis
  double minor_semi_axis = 0.0;  ///< b = c [m], b <= a
  double fraction = 0.0;         ///< number fraction after loading
};

/// A discrete particle-size distribution.
struct Psd {
  std::string name;
  /// Non-empty after loading; fractions are NUMBER fractions summing to 1
  /// (mass fractions in the file are converted with particle volume ~ a b^2).
  std::vector<PsdType> types;
};

/// Reads and validates the PSD file at `path`. Throws SceneError (field
/// "psd", reason naming the path and "cannot open") when it cannot be read.
Psd load_psd(const std::string& path);

/// Parses and validates PSD YAML text. `source` (a path) only serves error
/// messages and the default name (its stem).
Psd parse_psd(const std::string& yaml, const std::string& source = "");

/// Equal-volume radius cbrt(a b^2) of a type [m].
double nominal_radius(const PsdType& type);

/// (nominal radius [m], number fraction) for each type, in file order.
std::vector<std::pair<double, double>> nominal_radius_table(const Psd& psd);

/// `count` particles drawn from the PSD exactly as
/// dem::table_radii(count, nominal_radius_table(psd)) does, each with the
/// aspect ratio a/b of its type (1 for spheres), in the same order.
struct PsdParticles {
  std::vector<double> radii;          ///< nominal radius [m]
  std::vector<double> aspect_ratios;  ///< a/b >= 1
};
PsdParticles psd_particles(const Psd& psd, std::int64_t count);

/// Dispersity index (eq. 80) of a PSD, mass of a type ~ number fraction x
/// a b^2. Throws std::invalid_argument for an empty PSD or a type with a
/// non-positive/non-finite size or a negative/non-finite fraction.
double dispersity_index(const Psd& psd);

/// Dispersity index (eq. 80) of an explicit particle list (quasi_static/dispersity_index.h).
using quasi_static::dispersity_index;

}  // namespace vt::io
