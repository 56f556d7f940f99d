// Unit tests of the YAML scene parser (vt::io::load_scene / parse_scene).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "virtual_triaxial/io/scene_parser.h"

namespace {

namespace fs = std::filesystem;
using vt::io::ParticleSource;
using vt::io::SceneConfig;
using vt::io::SceneError;
using vt::io::StageType;

// A valid minimal scene assembled from parts, so each error case changes one thing.
const char* kDist = "particles:\n  distribution: {count: 10, radius_min: 1.0e-3, radius_max: 1.0e-3}\n";
const char* kRelax = "stages:\n  - {type: relax, stop: {steps: 10}}\n";

std::string scene(const std::string& extra, const std::string& particles = kDist,
                  const std::string& stages = kRelax) {
  return particles + stages + extra;
}

std::string list_particles(const std::string& fourth_radius) {
  return "particles:\n  list:\n"
         "    - {id: 0, radius: 1.0e-3, position: [0, 0, 0]}\n"
         "    - {id: 1, radius: 1.0e-3, position: [0.003, 0, 0]}\n"
         "    - {id: 2, radius: 1.0e-3, position: [0, 0.003, 0]}\n"
         "    - {id: 3, radius: " + fourth_radius + ", position: [0, 0, 0.003]}\n";
}

const char* kListCell = "cell: {lengths: [0.01, 0.01, 0.01]}\n";

// Temp folder owned by one test, removed at the end.
struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& tag) {
    path = fs::temp_directory_path() /
           ("vt_scene_parser_" + tag + "_" + std::to_string(::getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  fs::path write(const std::string& rel, const std::string& text) const {
    const fs::path p = path / rel;
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
    return p;
  }
};

SceneError expect_scene_error(const std::string& yaml) {
  try {
    (void)vt::io::parse_scene(yaml);
  } catch (const SceneError& e) {
    return e;
  }
  ADD_FAILURE() << "no SceneError for:\n" << yaml;
  return SceneError("<none>", "<none>");
}

// ---- valid scenes ------------------------------------------------------------------

TEST(SceneParser, DefaultSceneHasTheExpectedValues) {
  const std::string path = std::string(VT_SOURCE_DIR) + "/config/scenes/default.yaml";
  const SceneConfig c = vt::io::load_scene(path);
  EXPECT_EQ(c.source_path, path);
  EXPECT_EQ(c.material.density, 2650.0);
  EXPECT_EQ(c.material.young, 70e9);
  EXPECT_EQ(c.material.poisson, 0.3);
  EXPECT_EQ(c.material.friction, 0.5);
  ASSERT_EQ(c.source, ParticleSource::Distribution);
  EXPECT_EQ(c.distribution.count, 1000);
  EXPECT_EQ(c.distribution.radius_min, 0.8e-3);
  EXPECT_EQ(c.distribution.radius_max, 1.2e-3);
  EXPECT_TRUE(c.distribution.types.empty());
  EXPECT_EQ(c.distribution.seed, 42u);
  EXPECT_EQ(c.distribution.initial_void_ratio, 1.8);
  EXPECT_EQ(c.cell_aspect.x, 1.0);
  EXPECT_EQ(c.cell_aspect.y, 1.0);
  EXPECT_EQ(c.cell_aspect.z, 1.0);
  EXPECT_EQ(c.damping.model(), vt::dem::DampingModel::OD);
  EXPECT_EQ(c.damping.ratio(), 0.003);
  EXPECT_EQ(c.time_step_ratio, 0.3);
  EXPECT_FALSE(c.time_step_warning);
  EXPECT_EQ(c.stability.max_overlap_ratio, 0.1);
  EXPECT_EQ(c.stability.max_energy_error, 0.5);
  ASSERT_EQ(c.stages.size(), 3u);

  EXPECT_EQ(c.stages[0].type, StageType::IsotropicCompression);
  EXPECT_EQ(c.stages[0].strain_rate_dimensionless, 1.0e-5);
  EXPECT_FALSE(c.stages[0].strain_rate);
  EXPECT_EQ(c.stages[0].stop.mean_stress, 100e3);
  EXPECT_FALSE(c.stages[0].stop.steps);

  EXPECT_EQ(c.stages[1].type, StageType::Relax);
  EXPECT_FALSE(c.stages[1].strain_rate_dimensionless);
  EXPECT_FALSE(c.stages[1].strain_rate);
  EXPECT_EQ(c.stages[1].stop.ufr_below, 0.01);
  EXPECT_EQ(c.stages[1].stop.steps, 20000);
  EXPECT_FALSE(c.stages[1].stop.mean_stress);

  EXPECT_EQ(c.stages[2].type, StageType::UndrainedShear);
  EXPECT_EQ(c.stages[2].strain_rate_dimensionless, 2.0e-5);
  EXPECT_EQ(c.stages[2].axial_axis, 2);
  EXPECT_EQ(c.stages[2].stop.axial_strain, 0.10);

  EXPECT_EQ(c.output.interval, 200);
  EXPECT_EQ(c.output.progress_seconds, 2.0);
  EXPECT_EQ(c.output.snapshot_interval, 0);  // off by default
}

TEST(SceneParser, ListSceneParsesIdsVectorsAndVelocityDefaults) {
  const std::string yaml =
      "particles:\n  list:\n"
      "    - {id: 7, radius: 1.5e-3, position: [0.001, 0.002, 0.003], velocity: [1, -2, 3],"
      " angular_velocity: [0.5, 0, -0.5]}\n"
      "    - id: 3\n      radius: 1.0e-3\n      position: [4.0e-3, 5.0e-3, 6.0e-3]\n" +
      std::string("cell: {lengths: [0.01, 0.02, 0.03]}\n") + kRelax;
  const SceneConfig c = vt::io::parse_scene(yaml);
  ASSERT_EQ(c.source, ParticleSource::List);
  ASSERT_EQ(c.list.size(), 2u);
  EXPECT_EQ(c.list[0].id, 7);
  EXPECT_EQ(c.list[0].radius, 1.5e-3);
  EXPECT_EQ(c.list[0].position.x, 0.001);
  EXPECT_EQ(c.list[0].position.z, 0.003);
  EXPECT_EQ(c.list[0].velocity.y, -2.0);
  EXPECT_EQ(c.list[0].angular_velocity.z, -0.5);
  EXPECT_EQ(c.list[1].id, 3);
  EXPECT_EQ(c.list[1].position.y, 5.0e-3);
  EXPECT_EQ(c.list[1].velocity.x, 0.0);
  EXPECT_EQ(c.list[1].velocity.y, 0.0);
  EXPECT_EQ(c.list[1].velocity.z, 0.0);
  EXPECT_EQ(c.list[1].angular_velocity.x, 0.0);
  EXPECT_EQ(c.list[1].angular_velocity.z, 0.0);
  EXPECT_EQ(c.cell_lengths.x, 0.01);
  EXPECT_EQ(c.cell_lengths.y, 0.02);
  EXPECT_EQ(c.cell_lengths.z, 0.03);
}

TEST(SceneParser, MinimalSceneGetsDefaults) {
  const SceneConfig c = vt::io::parse_scene(scene(""));
  const vt::dem::Material m;
  EXPECT_EQ(c.material.density, m.density);
  EXPECT_EQ(c.material.young, m.young);
  EXPECT_EQ(c.material.poisson, m.poisson);
  EXPECT_EQ(c.material.friction, m.friction);
  EXPECT_EQ(c.distribution.seed, 1u);
  EXPECT_EQ(c.distribution.initial_void_ratio, 3.0);
  EXPECT_EQ(c.damping.model(), vt::dem::DampingModel::OD);
  EXPECT_EQ(c.damping.ratio(), 0.0);
  EXPECT_EQ(c.time_step_ratio, 0.3);
  EXPECT_EQ(c.output.interval, 100);
  EXPECT_EQ(c.output.progress_seconds, 2.0);
  ASSERT_EQ(c.stages.size(), 1u);
  EXPECT_EQ(c.stages[0].name, "stage0");
  EXPECT_EQ(c.stages[0].axial_axis, 2);
}

TEST(SceneParser, TypesTableStrainRateAndCaseInsensitiveNames) {
  const std::string parts =
      "particles:\n  distribution:\n    count: 2.0e1\n    types:\n"
      "      - {radius: 1.0e-3, fraction: 0.25}\n      - {radius: 2.0e-3, fraction: 0.75}\n";
  const std::string stages =
      "stages:\n  - {type: Undrained_Shear, strain_rate: 0.5, axial_axis: X, stop: {steps: 2.0e4}}\n";
  const SceneConfig c = vt::io::parse_scene(scene("damping: {model: nd, ratio: 0.1}\n", parts, stages));
  EXPECT_EQ(c.distribution.count, 20);
  ASSERT_EQ(c.distribution.types.size(), 2u);
  EXPECT_EQ(c.distribution.types[1].radius, 2.0e-3);
  EXPECT_EQ(c.distribution.types[1].fraction, 0.75);
  EXPECT_EQ(c.damping.model(), vt::dem::DampingModel::ND);
  EXPECT_EQ(c.stages[0].type, StageType::UndrainedShear);
  EXPECT_EQ(c.stages[0].strain_rate, 0.5);
  EXPECT_FALSE(c.stages[0].strain_rate_dimensionless);
  EXPECT_EQ(c.stages[0].axial_axis, 0);
  EXPECT_EQ(c.stages[0].stop.steps, 20000);
}

TEST(SceneParser, TimeStepRatioAboveOneIsAcceptedWithAWarning) {
  const SceneConfig hi = vt::io::parse_scene(scene("time_step_ratio: 1.5\n"));
  EXPECT_EQ(hi.time_step_ratio, 1.5);
  EXPECT_TRUE(hi.time_step_warning);
  const SceneConfig lo = vt::io::parse_scene(scene("time_step_ratio: 0.99\n"));
  EXPECT_FALSE(lo.time_step_warning);
}

TEST(SceneParser, TimeStepBasisDefaultsToContactsUnlessTheFileSetsTheRatio) {
  using vt::dem::TimeStepBasis;
  // Neither key: the step from the contacts (issue 13), c_t left at 0.3 unused.
  const SceneConfig plain = vt::io::parse_scene(scene(""));
  EXPECT_EQ(plain.time_step_basis, TimeStepBasis::Contacts);
  EXPECT_FALSE(plain.time_step_warning);
  // c_t alone: dt = c_t T0 as the file says.
  EXPECT_EQ(vt::io::parse_scene(scene("time_step_ratio: 0.3\n")).time_step_basis, TimeStepBasis::ReferenceTime);
  // An explicit basis wins either way.
  EXPECT_EQ(vt::io::parse_scene(scene("time_step_basis: reference\n")).time_step_basis,
            TimeStepBasis::ReferenceTime);
  EXPECT_EQ(vt::io::parse_scene(scene("time_step_ratio: 0.2\ntime_step_basis: contacts\n")).time_step_basis,
            TimeStepBasis::Contacts);
}

// ---- errors: field() names the dotted path ---------------------------------------

struct ErrorCase {
  const char* name;
  std::string yaml;
  const char* field;
};

TEST(SceneParser, ErrorsNameTheField) {
  const std::string types_bad_sum =
      "particles:\n  distribution:\n    count: 10\n    types:\n"
      "      - {radius: 1.0e-3, fraction: 0.5}\n      - {radius: 2.0e-3, fraction: 0.4}\n";
  const std::string range_and_types =
      "particles:\n  distribution:\n    count: 10\n    radius_min: 1.0e-3\n    radius_max: 2.0e-3\n"
      "    types: [{radius: 1.0e-3, fraction: 1.0}]\n";
  const std::string shear = "stages:\n  - {type: undrained_shear, strain_rate_dimensionless: 1.0e-5";
  const std::vector<ErrorCase> cases = {
      {"negative list radius", scene(kListCell, list_particles("-1.0e-3")), "particles.list[3].radius"},
      {"negative radius_min",
       scene("", "particles:\n  distribution: {count: 10, radius_min: -1.0e-3, radius_max: 1.0e-3}\n"),
       "particles.distribution.radius_min"},
      {"nu = 0.5", scene("material: {poisson_ratio: 0.5}\n"), "material.poisson_ratio"},
      {"nu = 0.7", scene("material: {poisson_ratio: 0.7}\n"), "material.poisson_ratio"},
      {"c_t = 0", scene("time_step_ratio: 0\n"), "time_step_ratio"},
      {"c_t = -1", scene("time_step_ratio: -1\n"), "time_step_ratio"},
      {"unknown top-level key", scene("colour: red\n"), "colour"},
      {"unknown nested key", scene("material: {density: 2650, colour: red}\n"), "material.colour"},
      {"unknown stop key", scene("", kDist, "stages:\n  - {type: relax, stop: {stesp: 10}}\n"),
       "stages[0].stop.stesp"},
      {"missing stages", kDist, "stages"},
      {"missing particles", kRelax, "particles"},
      {"fractions not summing to 1", scene("", types_bad_sum), "particles.distribution.types"},
      {"radius range and types", scene("", range_and_types), "particles.distribution"},
      {"count 1.5", scene("", "particles:\n  distribution: {count: 1.5, radius_min: 1.0e-3, radius_max: 1.0e-3}\n"),
       "particles.distribution.count"},
      {"'abc' as number", scene("material: {density: abc}\n"), "material.density"},
      {"2-vector lengths", scene("cell: {lengths: [0.01, 0.01]}\n", list_particles("1.0e-3")), "cell.lengths"},
      {"list without cell.lengths", scene("", list_particles("1.0e-3")), "cell.lengths"},
      {"bad damping model", scene("damping: {model: XD}\n"), "damping.model"},
      {"bad stage type", scene("", kDist, "stages:\n  - {type: shear, stop: {steps: 1}}\n"), "stages[0].type"},
      {"stage without stop", scene("", kDist, "stages:\n  - {type: relax}\n"), "stages[0].stop"},
      {"stage with empty stop", scene("", kDist, "stages:\n  - {type: relax, stop: {}}\n"), "stages[0].stop"},
      {"relax with strain rate",
       scene("", kDist, "stages:\n  - {type: relax, strain_rate_dimensionless: 1.0e-4, stop: {steps: 1}}\n"),
       "stages[0].strain_rate_dimensionless"},
      // more wrong types and ranges
      {"scalar where list expected", scene("", kDist, "stages: 5\n"), "stages"},
      {"scalar position", scene(kListCell, "particles:\n  list:\n    - {id: 0, radius: 1.0e-3, position: 0}\n"),
       "particles.list[0].position"},
      {"non-numeric vector element", scene("cell: {lengths: [0.01, x, 0.01]}\n", list_particles("1.0e-3")),
       "cell.lengths[1]"},
      {"negative cell length", scene("cell: {lengths: [0.01, 0.01, -0.01]}\n", list_particles("1.0e-3")),
       "cell.lengths[2]"},
      {"infinite young modulus", scene("material: {young_modulus: .inf}\n"), "material.young_modulus"},
      {"nan friction", scene("material: {friction: .nan}\n"), "material.friction"},
      {"overflowing density", scene("material: {density: 1e999}\n"), "material.density"},
      {"null value", scene("material:\n  density:\n"), "material.density"},
      {"negative friction", scene("material: {friction: -0.1}\n"), "material.friction"},
      {"duplicate id", scene(kListCell, "particles:\n  list:\n    - {id: 1, radius: 1.0e-3, position: [0, 0, 0]}\n"
                                        "    - {id: 1, radius: 1.0e-3, position: [0.003, 0, 0]}\n"),
       "particles.list[1].id"},
      {"negative id", scene(kListCell, "particles:\n  list:\n    - {id: -1, radius: 1.0e-3, position: [0, 0, 0]}\n"),
       "particles.list[0].id"},
      {"two particle sources", scene(kListCell, "particles:\n  sample_file: x.h5\n  list: []\n"), "particles"},
      {"count 1", scene("", "particles:\n  distribution: {count: 1, radius_min: 1.0e-3, radius_max: 1.0e-3}\n"),
       "particles.distribution.count"},
      {"radius_min > radius_max",
       scene("", "particles:\n  distribution: {count: 10, radius_min: 2.0e-3, radius_max: 1.0e-3}\n"),
       "particles.distribution.radius_max"},
      {"negative seed", scene("", "particles:\n  distribution: {count: 10, radius_min: 1.0e-3, radius_max: 1.0e-3,"
                                  " seed: -1}\n"),
       "particles.distribution.seed"},
      {"lengths with distribution", scene("cell: {lengths: [0.01, 0.01, 0.01]}\n"), "cell.lengths"},
      {"zero aspect", scene("cell: {aspect: [1, 0, 1]}\n"), "cell.aspect[1]"},
      {"negative damping ratio", scene("damping: {ratio: -0.1}\n"), "damping.ratio"},
      {"zero overlap limit", scene("stability: {max_overlap_ratio: 0}\n"), "stability.max_overlap_ratio"},
      {"output interval 0", scene("output: {interval: 0}\n"), "output.interval"},
      {"output interval 2.5", scene("output: {interval: 2.5}\n"), "output.interval"},
      {"snapshot interval not a multiple", scene("output: {interval: 100, snapshot_interval: 150}\n"),
       "output.snapshot_interval"},
      {"negative snapshot interval", scene("output: {snapshot_interval: -100}\n"), "output.snapshot_interval"},
      {"no strain rate", scene("", kDist, "stages:\n  - {type: isotropic_compression, stop: {steps: 1}}\n"),
       "stages[0].strain_rate_dimensionless"},
      {"both strain rates", scene("", kDist, shear + ", strain_rate: 1.0, stop: {steps: 1}}\n"),
       "stages[0].strain_rate"},
      {"bad axial axis", scene("", kDist, shear + ", axial_axis: w, stop: {steps: 1}}\n"), "stages[0].axial_axis"},
      {"axial axis on compression",
       scene("", kDist, "stages:\n  - {type: isotropic_compression, strain_rate: 1.0, axial_axis: x,"
                        " stop: {steps: 1}}\n"),
       "stages[0].axial_axis"},
      {"second stage bad stop", scene("", kDist, std::string(kRelax) + shear.substr(8) + ", stop: {axial_strain: -0.1}}\n"),
       "stages[1].stop.axial_strain"},
      {"steps 1.5", scene("", kDist, "stages:\n  - {type: relax, stop: {steps: 1.5}}\n"), "stages[0].stop.steps"},
      {"empty stages", scene("", kDist, "stages: []\n"), "stages"},
      {"duplicate key", scene("material:\n  density: 1\n  density: 2\n"), "material.density"},
      {"list instead of mapping", scene("material: [1, 2]\n"), "material"},
      {"empty document", "# nothing\n", "scene"},
      {"scalar document", "hello\n", "scene"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const SceneError e = expect_scene_error(c.yaml);
    EXPECT_EQ(e.field(), c.field) << "reason: " << e.reason();
    EXPECT_FALSE(e.reason().empty());
    EXPECT_EQ(std::string(e.what()), e.field() + ": " + e.reason());
  }
}

TEST(SceneParser, UnknownKeyListsTheAllowedKeys) {
  const SceneError e = expect_scene_error(scene("damping: {modle: OD}\n"));
  EXPECT_EQ(e.field(), "damping.modle");
  EXPECT_NE(e.reason().find("model"), std::string::npos) << e.reason();
  EXPECT_NE(e.reason().find("ratio"), std::string::npos) << e.reason();
}

TEST(SceneParser, SyntaxErrorGivesTheLine) {
  const SceneError e = expect_scene_error("material:\n  density: 2650\n  friction: [0.5, 0.6\nstages: []\n");
  EXPECT_EQ(e.field(), "scene");
  EXPECT_NE(e.reason().find("line 4"), std::string::npos) << e.reason();
  const SceneError e2 = expect_scene_error("material:\n  density: 2650\n   friction: 0.5\n");
  EXPECT_EQ(e2.field(), "scene");
  EXPECT_NE(e2.reason().find("line 3"), std::string::npos) << e2.reason();
}

// ---- files -------------------------------------------------------------------------

TEST(SceneParser, MissingFileIsReportedWithItsPath) {
  const TempDir dir("missing");
  const std::string path = (dir.path / "no_such_scene.yaml").string();
  try {
    (void)vt::io::load_scene(path);
    FAIL() << "no SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), "scene");
    EXPECT_NE(e.reason().find(path), std::string::npos) << e.reason();
    EXPECT_NE(e.reason().find("cannot open"), std::string::npos) << e.reason();
  }
}

TEST(SceneParser, SampleFileIsResolvedRelativeToTheSceneFolder) {
  const TempDir dir("sample");
  const fs::path sample = dir.write("scenes/samples/x.h5", "not really hdf5");
  const std::string sample_scene = "particles:\n  sample_file: samples/x.h5\n" + std::string(kRelax);
  const fs::path yaml = dir.write("scenes/s.yaml", sample_scene);
  const SceneConfig c = vt::io::load_scene(yaml.string());
  ASSERT_EQ(c.source, ParticleSource::SampleFile);
  EXPECT_TRUE(fs::path(c.sample_file).is_absolute()) << c.sample_file;
  EXPECT_TRUE(fs::equivalent(c.sample_file, sample)) << c.sample_file;

  // An absolute path is taken as is.
  const std::string abs_scene = "particles:\n  sample_file: " + sample.string() + "\n" + kRelax;
  EXPECT_TRUE(fs::equivalent(vt::io::parse_scene(abs_scene, "/nonexistent/x.yaml").sample_file, sample));

  // Not relative to the current directory: parsing the same text as if it
  // lived elsewhere fails, naming the field and the resolved path.
  try {
    (void)vt::io::parse_scene(sample_scene, (dir.path / "other" / "s.yaml").string());
    FAIL() << "no SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), "particles.sample_file");
    EXPECT_NE(e.reason().find("other/samples/x.h5"), std::string::npos) << e.reason();
  }

  // cell.lengths is forbidden with a sample file.
  const fs::path yaml2 = dir.write("scenes/s2.yaml", sample_scene + "cell: {lengths: [1, 1, 1]}\n");
  try {
    (void)vt::io::load_scene(yaml2.string());
    FAIL() << "no SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), "cell.lengths");
  }
}

TEST(SceneParser, MissingSampleFileIsRejected) {
  const TempDir dir("nosample");
  const fs::path yaml =
      dir.write("s.yaml", "particles:\n  sample_file: samples/missing.h5\n" + std::string(kRelax));
  try {
    (void)vt::io::load_scene(yaml.string());
    FAIL() << "no SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), "particles.sample_file");
    EXPECT_NE(e.reason().find("missing.h5"), std::string::npos) << e.reason();
  }
}

}  // namespace

// Every shipped protocol loads (validation passes, its sample file exists)
// and has at least one stage.
TEST(SceneParser, EveryShippedProtocolLoads) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(VT_SOURCE_DIR "/config/protocols")) {
    if (e.path().extension() != ".yaml") continue;
    SCOPED_TRACE(e.path().string());
    vt::io::SceneConfig sc;
    ASSERT_NO_THROW(sc = vt::io::load_scene(e.path().string()));
    EXPECT_FALSE(sc.stages.empty());
    ++n;
  }
  EXPECT_GE(n, 5) << "config/protocols/ should hold the shipped protocols";
}

// ---- rate strategies (stages[i].rate, control/rate_strategy.h) ----------------------

TEST(SceneParser, RateStrategiesParseWithTheirDefaults) {
  const std::string drained = "stages:\n  - {type: drained_shear, confining_pressure: 1.0e5, stop: {axial_strain: 0.1}, ";
  const vt::io::SceneConfig a = vt::io::parse_scene(
      scene("", kDist, drained + "rate: {strategy: adaptive, target: 0.5, max_change: 0.05, min: 1.0e-8}}\n"));
  const vt::control::RateSpec& ra = a.stages[0].rate_spec;
  EXPECT_EQ(ra.strategy, vt::control::RateStrategyKind::Adaptive);
  EXPECT_EQ(ra.adaptive.target, 0.5);
  EXPECT_EQ(ra.adaptive.max_change, 0.05);
  EXPECT_EQ(ra.adaptive.min_dimensionless, 1e-8);
  EXPECT_EQ(ra.adaptive.max_dimensionless, vt::control::AdaptiveRateParameters{}.max_dimensionless);
  EXPECT_FALSE(a.stages[0].strain_rate_dimensionless);
  // predicted: target 1 by default (eq. 85 at I_QS itself)
  const vt::io::SceneConfig p = vt::io::parse_scene(scene("", kDist, drained + "rate: {strategy: predicted}}\n"));
  EXPECT_EQ(p.stages[0].rate_spec.strategy, vt::control::RateStrategyKind::Predicted);
  EXPECT_EQ(p.stages[0].rate_spec.adaptive.target, 1.0);
  // no rate key: fixed at the stage's rate (today's protocols unchanged)
  const vt::io::SceneConfig f =
      vt::io::parse_scene(scene("", kDist, drained + "strain_rate_dimensionless: 1.0e-5}\n"));
  EXPECT_EQ(f.stages[0].rate_spec.strategy, vt::control::RateStrategyKind::Fixed);
}

TEST(SceneParser, RateStrategyErrorsNameTheField) {
  const std::string drained = "stages:\n  - {type: drained_shear, confining_pressure: 1.0e5, stop: {axial_strain: 0.1}, ";
  const std::vector<ErrorCase> cases = {
      {"unknown strategy", scene("", kDist, drained + "rate: {strategy: fast}}\n"), "stages[0].rate.strategy"},
      {"adaptive with a fixed rate too",
       scene("", kDist, drained + "strain_rate_dimensionless: 1.0e-5, rate: {strategy: adaptive}}\n"),
       "stages[0].strain_rate_dimensionless"},
      {"target above 1", scene("", kDist, drained + "rate: {strategy: adaptive, target: 1.5}}\n"),
       "stages[0].rate.target"},
      {"max below min", scene("", kDist, drained + "rate: {strategy: adaptive, min: 1.0e-6, max: 1.0e-7}}\n"),
       "stages[0].rate.max"},
      {"zero max_change", scene("", kDist, drained + "rate: {strategy: adaptive, max_change: 0}}\n"),
       "stages[0].rate.max_change"},
      {"adaptive key on predicted", scene("", kDist, drained + "rate: {strategy: predicted, min: 1.0e-8}}\n"),
       "stages[0].rate.min"},
      {"target on fixed",
       scene("", kDist, drained + "strain_rate_dimensionless: 1.0e-5, rate: {strategy: fixed, target: 0.5}}\n"),
       "stages[0].rate.target"},
      {"adaptive on isotropic compression",
       scene("", kDist, "stages:\n  - {type: isotropic_compression, stop: {steps: 1}, rate: {strategy: adaptive}}\n"),
       "stages[0].rate.strategy"},
      {"unknown rate key", scene("", kDist, drained + "rate: {strategy: adaptive, gain: 2}}\n"),
       "stages[0].rate.gain"},
  };
  for (const ErrorCase& c : cases) {
    const SceneError e = expect_scene_error(c.yaml);
    EXPECT_EQ(e.field(), c.field) << c.name << ": " << e.what();
  }
}

