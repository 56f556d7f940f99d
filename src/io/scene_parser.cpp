#include "virtual_triaxial/io/scene_parser.h"
#include "virtual_triaxial/io/number_text.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "virtual_triaxial/control/servo_strategy.h"
#include "virtual_triaxial/io/yaml_fields.h"

namespace vt::io {
namespace {

namespace fs = std::filesystem;
using yaml_fields::Section;
using yaml_fields::index;
using yaml_fields::require;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string num(double v) { return number_text(v, 10); }

double positive(const Section& s, const std::string& key, double fallback) {
  const double v = s.number_or(key, fallback);
  require(v > 0.0, s.path(key), "must be > 0, got " + num(v));
  return v;
}

double positive(const Section& s, const std::string& key) {
  const double v = s.number(key);
  require(v > 0.0, s.path(key), "must be > 0, got " + num(v));
  return v;
}

double non_negative(const Section& s, const std::string& key, double fallback) {
  const double v = s.number_or(key, fallback);
  require(v >= 0.0, s.path(key), "must be >= 0, got " + num(v));
  return v;
}

void require_positive_components(const dem::Vec3& v, const std::string& path) {
  for (int i = 0; i < 3; ++i)
    require(v[i] > 0.0, index(path, static_cast<std::size_t>(i)), "must be > 0, got " + num(v[i]));
}

// ---- material ------------------------------------------------------------------

void parse_material(const YAML::Node& node, dem::Material& m, MaterialKeysGiven& given) {
  const Section s(node, "material", {"density", "young_modulus", "poisson_ratio", "friction"});
  given.density = s.has("density");
  given.young_modulus = s.has("young_modulus");
  given.poisson_ratio = s.has("poisson_ratio");
  m.density = positive(s, "density", m.density);
  m.young = positive(s, "young_modulus", m.young);
  m.poisson = s.number_or("poisson_ratio", m.poisson);
  require(m.poisson > -1.0 && m.poisson < 0.5, s.path("poisson_ratio"),
          "must lie in the open interval (-1, 0.5), got " + num(m.poisson));
  m.friction = non_negative(s, "friction", m.friction);
  const std::string err = m.validate();  // backstop; the checks above are stricter
  require(err.empty(), "material", err);
}

// ---- particles -----------------------------------------------------------------

void parse_distribution(const YAML::Node& node, DistributionSpec& d) {
  const Section s(node, "particles.distribution",
                  {"count", "radius_min", "radius_max", "types", "seed", "initial_void_ratio", "aspect_ratio"});
  d.aspect_ratio = s.number_or("aspect_ratio", d.aspect_ratio);
  require(d.aspect_ratio >= 1.0, s.path("aspect_ratio"),
          "must be >= 1 (a/b of prolate spheroids; 1 = spheres), got " + num(d.aspect_ratio));
  d.count = s.integer("count");
  require(d.count >= 2, s.path("count"), "must be an integer >= 2, got " + std::to_string(d.count));

  const bool has_range = s.has("radius_min") || s.has("radius_max");
  const bool has_types = s.has("types");
  require(!(has_range && has_types), s.path(),
          "give either radius_min/radius_max (uniform in radius) or types, not both");
  require(has_range || has_types, s.path(),
          "give either radius_min and radius_max (uniform in radius) or a types table");
  if (has_range) {
    d.radius_min = positive(s, "radius_min");
    d.radius_max = positive(s, "radius_max");
    require(d.radius_min <= d.radius_max, s.path("radius_max"),
            "must be >= radius_min (" + num(d.radius_min) + "), got " + num(d.radius_max));
  } else {
    const YAML::Node types = s.get("types");
    yaml_fields::expect_list(types, s.path("types"));
    require(types.size() > 0, s.path("types"), "must hold at least one {radius, fraction} entry");
    double sum = 0.0;
    for (std::size_t i = 0; i < types.size(); ++i) {
      const Section t(types[i], index(s.path("types"), i), {"radius", "fraction"});
      ParticleType pt;
      pt.radius = positive(t, "radius");
      pt.fraction = positive(t, "fraction");
      sum += pt.fraction;
      d.types.push_back(pt);
    }
    require(std::fabs(sum - 1.0) <= 1e-6, s.path("types"),
            "fractions sum to " + num(sum) + "; they must sum to 1 (within 1e-6)");
  }
  const std::int64_t seed = s.integer_or("seed", static_cast<std::int64_t>(d.seed));
  require(seed >= 0, s.path("seed"), "must be a non-negative integer, got " + std::to_string(seed));
  d.seed = static_cast<std::uint64_t>(seed);
  d.initial_void_ratio = positive(s, "initial_void_ratio", d.initial_void_ratio);
}

void parse_list(const YAML::Node& node, std::vector<ParticleSpec>& list) {
  const std::string path = "particles.list";
  yaml_fields::expect_list(node, path);
  require(node.size() > 0, path, "must hold at least one particle");
  std::map<std::int64_t, std::size_t> first_use;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const Section s(node[i], index(path, i),
                    {"id", "radius", "position", "velocity", "angular_velocity"});
    ParticleSpec p;
    p.id = s.integer("id");
    require(p.id >= 0, s.path("id"), "must be a non-negative integer, got " + std::to_string(p.id));
    const auto [it, fresh] = first_use.emplace(p.id, i);
    require(fresh, s.path("id"),
            "duplicate id " + std::to_string(p.id) + " (already used by " + index(path, it->second) + ")");
    p.radius = positive(s, "radius");
    p.position = s.vec3("position");
    p.velocity = s.vec3_or("velocity", {});
    p.angular_velocity = s.vec3_or("angular_velocity", {});
    list.push_back(p);
  }
}

std::string resolve_sample_file(const Section& s, const std::string& source_path) {
  const std::string field = s.path("sample_file");
  const std::string given = s.string("sample_file");
  require(!given.empty(), field, "must be a non-empty path");
  std::error_code ec;
  fs::path base = source_path.empty() ? fs::path(".") : fs::path(source_path).parent_path();
  if (base.empty()) base = ".";
  fs::path abs_base = fs::absolute(base, ec);
  if (ec) abs_base = base;
  abs_base = abs_base.lexically_normal();
  const fs::path p(given);
  const fs::path abs = p.is_absolute() ? p.lexically_normal() : (abs_base / p).lexically_normal();
  const std::string where = (source_path.empty() ? "the current directory '"
                                                 : "the scene file's folder '") +
                            abs_base.string() + "'";
  require(fs::exists(abs, ec), field,
          "file not found: '" + abs.string() + "' (relative paths are taken from " + where + ")");
  require(fs::is_regular_file(abs, ec), field, "not a regular file: '" + abs.string() + "'");
  return abs.string();
}

void parse_particles(const YAML::Node& node, const std::string& source_path, SceneConfig& cfg) {
  const Section s(node, "particles", {"distribution", "list", "sample_file"});
  const int given = int(s.has("distribution")) + int(s.has("list")) + int(s.has("sample_file"));
  require(given == 1, "particles",
          std::string(given == 0 ? "missing particle source" : "more than one particle source") +
              ": give exactly one of distribution, list, sample_file");
  if (s.has("distribution")) {
    cfg.source = ParticleSource::Distribution;
    parse_distribution(s.get("distribution"), cfg.distribution);
  } else if (s.has("list")) {
    cfg.source = ParticleSource::List;
    parse_list(s.get("list"), cfg.list);
  } else {
    cfg.source = ParticleSource::SampleFile;
    cfg.sample_file = resolve_sample_file(s, source_path);
  }
}

// ---- cell, damping, stability, output ------------------------------------------

void parse_cell(const YAML::Node& node, SceneConfig& cfg) {
  const Section s(node, "cell", {"lengths", "aspect"});
  switch (cfg.source) {
    case ParticleSource::List:
      require(s.has("lengths"), s.path("lengths"), "required with particles.list");
      cfg.cell_lengths = s.vec3("lengths");
      require_positive_components(cfg.cell_lengths, s.path("lengths"));
      require(!s.has("aspect"), s.path("aspect"),
              "not allowed with particles.list (cell.lengths fixes the cell)");
      break;
    case ParticleSource::SampleFile:
      require(!s.has("lengths"), s.path("lengths"),
              "not allowed with particles.sample_file (the sample file defines the cell)");
      require(!s.has("aspect"), s.path("aspect"),
              "not allowed with particles.sample_file (the sample file defines the cell)");
      break;
    case ParticleSource::Distribution:
      require(!s.has("lengths"), s.path("lengths"),
              "not allowed with particles.distribution (the cell volume follows from "
              "initial_void_ratio; use cell.aspect for its shape)");
      cfg.cell_aspect = s.vec3_or("aspect", cfg.cell_aspect);
      require_positive_components(cfg.cell_aspect, s.path("aspect"));
      break;
  }
}

/// damping: {model, and the model's one parameter: ratio (OD, ND),
/// restitution (viscous) or coefficient (local)}; the other parameters are
/// refused, and the parameter is required when the model changes.
void parse_damping(const YAML::Node& node, dem::MassDamping& damping) {
  const Section s(node, "damping", {"model", "ratio", "restitution", "coefficient"});
  dem::DampingModel model = damping.model();
  if (s.has("model")) {
    const std::string m = s.string("model");
    require(dem::parse_damping_model(m, model), s.path("model"),
            "expected OD (global, eq. 101), ND (size-dependent, eq. 63), viscous (contact dashpots from a "
            "restitution coefficient) or local (Cundall), got '" + m + "'");
  }
  const std::string key = dem::damping_parameter_name(model);
  for (const char* other : {"ratio", "restitution", "coefficient"})
    require(other == key || !s.has(other), s.path(other),
            std::string("not a parameter of damping model ") + dem::to_string(model) + " (it takes " + key + ")");
  const bool same_kind = dem::damping_parameter_name(damping.model()) == key;
  require(s.has(key) || same_kind, s.path(key), std::string("required with damping model ") + dem::to_string(model));
  const double value = s.has(key) ? s.number(key) : damping.ratio();
  const std::string bad = dem::damping_parameter_error(model, value);
  require(bad.empty(), s.path(key), bad + ", got " + num(value));
  damping = dem::MassDamping(model, value);
}

void parse_stability(const YAML::Node& node, dem::StabilityLimits& lim) {
  const Section s(node, "stability", {"max_overlap_ratio", "max_energy_error"});
  lim.max_overlap_ratio = positive(s, "max_overlap_ratio", lim.max_overlap_ratio);
  lim.max_energy_error = positive(s, "max_energy_error", lim.max_energy_error);
}

void parse_output(const YAML::Node& node, OutputSpec& out) {
  const Section s(node, "output",
                  {"interval", "progress_seconds", "snapshot_interval", "checkpoint_ticks", "checkpoint_seconds"});
  out.interval = s.integer_or("interval", out.interval);
  require(out.interval > 0, s.path("interval"),
          "must be an integer > 0, got " + std::to_string(out.interval));
  out.progress_seconds = positive(s, "progress_seconds", out.progress_seconds);
  out.snapshot_interval = s.integer_or("snapshot_interval", out.snapshot_interval);
  require(out.snapshot_interval >= 0 && out.snapshot_interval % out.interval == 0, s.path("snapshot_interval"),
          "must be 0 (no snapshots) or a multiple of output.interval (" + std::to_string(out.interval) +
              ") so that snapshots fall on samples, got " + std::to_string(out.snapshot_interval));
  out.checkpoint_ticks = s.integer_or("checkpoint_ticks", out.checkpoint_ticks);
  require(out.checkpoint_ticks >= 0, s.path("checkpoint_ticks"),
          "must be an integer >= 0 (0: no tick trigger), got " + std::to_string(out.checkpoint_ticks));
  out.checkpoint_seconds = s.number_or("checkpoint_seconds", out.checkpoint_seconds);
  require(std::isfinite(out.checkpoint_seconds) && out.checkpoint_seconds >= 0, s.path("checkpoint_seconds"),
          "must be >= 0 wall seconds (0: no time trigger), got " + num(out.checkpoint_seconds));
}

void parse_control(const YAML::Node& node, ControlSpec& c) {
  const Section s(node, "control", {"interval", "servo", "quasi_static_threshold"});
  c.interval = s.integer_or("interval", c.interval);
  require(c.interval >= 1, s.path("interval"), "must be an integer >= 1, got " + std::to_string(c.interval));
  c.quasi_static_threshold = positive(s, "quasi_static_threshold", c.quasi_static_threshold);
  const Section v(s.get("servo"), s.path("servo"),
                  {"strategy", "gain", "max_dimensionless_rate", "ki", "kd", "max_rate_change"});
  protocol::ServoSettings& sv = c.servo;
  sv.strategy = v.string_or("strategy", sv.strategy);
  sv.parameters.gain = positive(v, "gain", sv.parameters.gain);
  require(sv.parameters.gain <= 1.0, v.path("gain"), "must be in (0, 1], got " + num(sv.parameters.gain));
  sv.max_dimensionless_rate = positive(v, "max_dimensionless_rate", sv.max_dimensionless_rate);
  sv.parameters.ki = non_negative(v, "ki", sv.parameters.ki);
  sv.parameters.kd = non_negative(v, "kd", sv.parameters.kd);
  sv.max_dimensionless_rate_change = non_negative(v, "max_rate_change", sv.max_dimensionless_rate_change);
  sv.parameters.max_strain_rate = 1.0;  // placeholder for the check below; set from T0 per stage
  try {
    control::make_servo(sv.strategy, sv.parameters);
  } catch (const std::invalid_argument& e) {
    throw SceneError(v.path(), e.what());
  }
}

// ---- stages ----------------------------------------------------------------------

StageType parse_type(const Section& s) {
  const std::string t = s.string("type");
  StageType type;
  require(protocol::parse_stage_type(lower(t), type), s.path("type"),
          "unknown stage type '" + t + "'; allowed: " + protocol::stage_type_names());
  return type;
}

void parse_balanced(const Section& stop, StopCriteria& c) {
  const Section s(stop.get("balanced"), stop.path("balanced"), {"stress_tolerance", "ufr_below"});
  protocol::BalanceCriterion b;
  b.stress_tolerance = positive(s, "stress_tolerance", b.stress_tolerance);
  b.ufr_below = positive(s, "ufr_below", b.ufr_below);
  c.balanced = b;
}

void parse_stop(const Section& stage, StageType type, StopCriteria& stop) {
  const char* all = "mean_stress, axial_strain, steps, ufr_below, softening, balanced, deviator_below";
  require(stage.has("stop"), stage.path("stop"), std::string("required: give at least one of ") + all);
  const Section s(stage.get("stop"), stage.path("stop"),
                  {"mean_stress", "axial_strain", "steps", "ufr_below", "softening", "balanced", "deviator_below"});
  if (s.has("deviator_below")) stop.deviator_below = s.number("deviator_below");
  if (s.has("softening")) {
    stop.softening = s.number("softening");
    require(*stop.softening > 0.0 && *stop.softening < 1.0, s.path("softening"),
            "must be a fraction in (0, 1) (drop of q below its peak), got " + num(*stop.softening));
  }
  if (s.has("balanced")) {
    require(protocol::uses_servo(type), s.path("balanced"),
            "only for servo stages (isotropic_consolidation, drained_shear, drained_unload)");
    parse_balanced(s, stop);
  }
  if (s.has("mean_stress")) stop.mean_stress = positive(s, "mean_stress");
  if (s.has("axial_strain")) stop.axial_strain = positive(s, "axial_strain");
  if (s.has("ufr_below")) stop.ufr_below = positive(s, "ufr_below");
  if (s.has("steps")) {
    stop.steps = s.integer("steps");
    require(*stop.steps > 0, s.path("steps"),
            "must be an integer > 0, got " + std::to_string(*stop.steps));
  }
  require(stop.mean_stress || stop.axial_strain || stop.steps || stop.ufr_below || stop.softening ||
              stop.balanced || stop.deviator_below,
          s.path(), std::string("needs at least one of ") + all);
}

/// `rate: {strategy: fixed|predicted|adaptive, target, min, max, max_change,
/// smoothing_ticks, response_ticks, sensitivity}` (control/rate_strategy.h).
void parse_rate(const Section& stage, StageType type, control::RateSpec& rate) {
  const Section s(stage.get("rate"), stage.path("rate"),
                  {"strategy", "target", "min", "max", "max_change", "smoothing_ticks", "response_ticks",
                   "sensitivity"});
  const std::string name = lower(s.string_or("strategy", "fixed"));
  require(control::parse_rate_strategy(name, rate.strategy), s.path("strategy"),
          "unknown rate strategy '" + name + "'; allowed: fixed, predicted, adaptive");
  require(rate.strategy == control::RateStrategyKind::Fixed || type == StageType::DrainedShear, s.path("strategy"),
          "'" + name + "' only on drained_shear stages (it follows the moment index while the servo holds "
          "the lateral stress)");
  control::AdaptiveRateParameters& a = rate.adaptive;
  const bool adaptive = rate.strategy == control::RateStrategyKind::Adaptive;
  for (const char* key : {"min", "max", "max_change", "smoothing_ticks", "response_ticks", "sensitivity"})
    require(adaptive || !s.has(key), s.path(key), "only for strategy adaptive");
  require(rate.strategy != control::RateStrategyKind::Fixed || !s.has("target"), s.path("target"),
          "only for strategies predicted and adaptive");
  a.target = s.number_or("target", adaptive ? a.target : 1.0);
  a.min_dimensionless = s.number_or("min", a.min_dimensionless);
  a.max_dimensionless = s.number_or("max", a.max_dimensionless);
  a.max_change = s.number_or("max_change", a.max_change);
  a.smoothing_ticks = s.number_or("smoothing_ticks", a.smoothing_ticks);
  a.response_ticks = s.number_or("response_ticks", a.response_ticks);
  a.sensitivity = s.number_or("sensitivity", a.sensitivity);
  control::AdaptiveRateParameters check = a;
  check.t0 = 1.0;  // T0 is the sample's, known at the run
  const std::string bad = control::validate(check);  // "<field>: <reason>"
  if (!bad.empty()) throw SceneError(s.path(bad.substr(0, bad.find(':'))), bad.substr(bad.find(':') + 2));
}

StageSpec parse_stage(const YAML::Node& node, std::size_t i) {
  const Section s(node, index("stages", i),
                  {"name", "type", "strain_rate_dimensionless", "strain_rate", "confining_pressure", "axial_axis",
                   "stop", "rate"});
  StageSpec st;
  st.name = s.string_or("name", "stage" + std::to_string(i));
  require(!st.name.empty(), s.path("name"), "must be a non-empty string");
  st.type = parse_type(s);
  if (protocol::uses_servo(st.type)) {
    require(s.has("confining_pressure"), s.path("confining_pressure"),
            std::string("required for a ") + protocol::to_string(st.type) + " stage (servo target, Pa)");
    st.confining_pressure = positive(s, "confining_pressure");
  } else {
    require(!s.has("confining_pressure"), s.path("confining_pressure"),
            "only for servo stages (isotropic_consolidation, drained_shear, drained_unload)");
  }

  const bool has_dimless = s.has("strain_rate_dimensionless");
  const bool has_rate = s.has("strain_rate");
  if (s.has("rate")) parse_rate(s, st.type, st.rate_spec);
  if (st.rate_spec.strategy != control::RateStrategyKind::Fixed) {
    for (const char* key : {"strain_rate_dimensionless", "strain_rate"})
      require(!s.has(key), s.path(key),
              std::string("not used with rate.strategy ") + control::to_string(st.rate_spec.strategy) +
                  " (the rate starts from the eq. 84 prediction of the specimen); remove it");
  } else if (st.type == StageType::Relax || st.type == StageType::IsotropicConsolidation) {
    for (const char* key : {"strain_rate_dimensionless", "strain_rate"})
      require(!s.has(key), s.path(key),
              std::string("not allowed for a ") + protocol::to_string(st.type) +
                  " stage (no open-loop strain rate is applied)");
  } else {
    require(!(has_dimless && has_rate), s.path("strain_rate"),
            "give exactly one of strain_rate_dimensionless and strain_rate, not both");
    require(has_dimless || has_rate, s.path("strain_rate_dimensionless"),
            "required: give strain_rate_dimensionless (eps' = eps_dot T0) or strain_rate [1/s]");
    const char* key = has_dimless ? "strain_rate_dimensionless" : "strain_rate";
    const double rate = positive(s, key);  // compression positive
    (has_dimless ? st.strain_rate_dimensionless : st.strain_rate) = rate;
  }

  if (s.has("axial_axis")) {
    require(protocol::is_shear(st.type) || st.type == StageType::DrainedUnload, s.path("axial_axis"),
            "only allowed for drained_shear, undrained_shear and drained_unload stages");
    const std::string a = s.string("axial_axis");
    const std::string l = lower(a);
    require(l == "x" || l == "y" || l == "z", s.path("axial_axis"),
            "expected x, y or z, got '" + a + "'");
    st.axial_axis = l == "x" ? 0 : (l == "y" ? 1 : 2);
  }
  parse_stop(s, st.type, st.stop);
  return st;
}

void parse_stages(const YAML::Node& node, std::vector<StageSpec>& stages) {
  yaml_fields::expect_list(node, "stages");
  require(node.size() > 0, "stages", "must hold at least one stage");
  for (std::size_t i = 0; i < node.size(); ++i) stages.push_back(parse_stage(node[i], i));
}

SceneConfig parse_document(const YAML::Node& doc, const std::string& source_path) {
  SceneConfig cfg;
  cfg.source_path = source_path;
  const Section top(doc, "",
                    {"material", "particles", "cell", "damping", "time_step_ratio", "time_step_basis",
                     "time_step_safety", "time_step_max_ratio", "stability", "stages", "output", "control"});
  parse_material(top.get("material"), cfg.material, cfg.material_given);
  parse_particles(top.required("particles"), source_path, cfg);
  parse_cell(top.get("cell"), cfg);
  parse_damping(top.get("damping"), cfg.damping);
  cfg.time_step_ratio = top.number_or("time_step_ratio", cfg.time_step_ratio);
  require(cfg.time_step_ratio > 0.0, "time_step_ratio",
          "must be > 0 (time step = c_t x critical time step), got " + num(cfg.time_step_ratio));
  // The default basis (issue 13): the time step from the contacts
  // (dem/contact_time_step.h), as fast as the contacts allow and, measured
  // on eight dense samples, the same answer within the sample's scatter
  // (README "The time step: from the contacts by default"); a file
  // that sets c_t without a basis keeps dt = c_t T0 (eq. 132).
  const std::string basis = top.string_or(
      "time_step_basis", dem::to_string(top.has("time_step_ratio") ? dem::TimeStepBasis::ReferenceTime
                                                                   : dem::TimeStepBasis::Contacts));
  require(dem::parse_time_step_basis(basis, cfg.time_step_basis), "time_step_basis",
          "must be reference (dt = c_t T0) or contacts (dt from the contact stiffnesses), got '" + basis + "'");
  cfg.time_step_safety = top.number_or("time_step_safety", cfg.time_step_safety);
  require(cfg.time_step_safety > 0.0 && cfg.time_step_safety <= 1.0, "time_step_safety",
          "must lie in (0, 1] (dt = safety x critical step of the contacts), got " + num(cfg.time_step_safety));
  cfg.time_step_max_ratio = top.number_or("time_step_max_ratio", cfg.time_step_max_ratio);
  require(cfg.time_step_max_ratio > 0.0 && std::isfinite(cfg.time_step_max_ratio), "time_step_max_ratio",
          "must be finite and > 0 (largest dt / T0), got " + num(cfg.time_step_max_ratio));
  cfg.time_step_warning = cfg.time_step_basis == dem::TimeStepBasis::ReferenceTime && cfg.time_step_ratio >= 1.0;
  parse_stability(top.get("stability"), cfg.stability);
  parse_stages(top.required("stages"), cfg.stages);
  parse_output(top.get("output"), cfg.output);
  parse_control(top.get("control"), cfg.control);
  require(cfg.output.interval % cfg.control.interval == 0, "output.interval",
          "must be a multiple of control.interval (" + std::to_string(cfg.control.interval) +
              ") so that samples fall on control ticks, got " + std::to_string(cfg.output.interval));
  return cfg;
}

}  // namespace

SceneConfig parse_scene(const std::string& yaml_text, const std::string& source_path) {
  const std::string in = source_path.empty() ? "" : " in '" + source_path + "'";
  std::vector<YAML::Node> docs;
  try {
    docs = YAML::LoadAll(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw SceneError("scene", "YAML syntax error" + in + " at line " + std::to_string(e.mark.line + 1) +
                                  ", column " + std::to_string(e.mark.column + 1) + ": " + e.msg);
  } catch (const YAML::Exception& e) {
    throw SceneError("scene", "cannot parse YAML" + in + ": " + e.what());
  }
  require(!docs.empty() && !docs[0].IsNull(), "scene",
          "empty document" + in + "; expected a mapping with at least `particles` and `stages`");
  require(docs.size() == 1, "scene",
          "holds " + std::to_string(docs.size()) + " YAML documents" + in + "; expected one");
  try {
    return parse_document(docs[0], source_path);
  } catch (const YAML::Exception& e) {  // should not happen: fields are read without as<>()
    throw SceneError("scene", std::string("unexpected YAML error") + in + ": " + e.what());
  }
}

SceneConfig load_scene(const std::string& path) {
  std::error_code ec;
  require(!fs::is_directory(path, ec), "scene", "cannot open '" + path + "': is a directory");
  errno = 0;
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    const int err = errno;
    throw SceneError("scene", "cannot open '" + path + "'" +
                                  (err != 0 ? std::string(": ") + std::strerror(err) : std::string()));
  }
  std::ostringstream text;
  text << file.rdbuf();
  require(!file.bad(), "scene", "cannot read '" + path + "'");
  return parse_scene(text.str(), path);
}

}  // namespace vt::io
