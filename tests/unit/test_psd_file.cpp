// Unit tests of the PSD tables (vt::io::load_psd / parse_psd) and of the
// dispersity index (eq. 80 of Yousefi 2017), plus transcription checks of the
// shipped config/psd/*.yaml against the dissertation's tables 10, 11, 22, 23,
// 32-38 (counts, nominal sizes, Delta in the captions) and tables 39 and 46
// (Delta per sample).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <unistd.h>

#include "virtual_triaxial/io/psd_file.h"

namespace {

namespace fs = std::filesystem;
using vt::io::Psd;
using vt::io::SceneError;
using vt::io::dispersity_index;
using vt::io::load_psd;
using vt::io::nominal_radius_table;
using vt::io::parse_psd;

const fs::path kPsdDir = fs::path(VT_SOURCE_DIR) / "config" / "psd";

Psd shipped(const std::string& stem) { return load_psd((kPsdDir / (stem + ".yaml")).string()); }

// |value - stated| within the rounding of a number printed with `decimals` decimals.
void expect_within_rounding(double value, double stated, int decimals, const std::string& what) {
  const double half_ulp = 0.5 * std::pow(10.0, -decimals) + 1e-9;
  EXPECT_LE(std::fabs(value - stated), half_ulp)
      << what << ": computed " << value << ", the dissertation states " << stated << " (" << decimals
      << " decimals)";
}

// ---- shipped files ---------------------------------------------------------------

TEST(PsdFile, EveryShippedPsdLoadsWithNumberFractionsSummingToOne) {
  ASSERT_TRUE(fs::is_directory(kPsdDir)) << kPsdDir;
  int files = 0;
  for (const auto& entry : fs::directory_iterator(kPsdDir)) {
    if (entry.path().extension() != ".yaml") continue;
    ++files;
    SCOPED_TRACE(entry.path().string());
    Psd psd;
    ASSERT_NO_THROW(psd = load_psd(entry.path().string()));
    EXPECT_EQ(psd.name, entry.path().stem().string()) << "name should match the file name";
    ASSERT_FALSE(psd.types.empty());
    double sum = 0.0;
    for (const auto& t : psd.types) {
      EXPECT_GT(t.fraction, 0.0);
      EXPECT_GT(t.minor_semi_axis, 0.0);
      EXPECT_LE(t.minor_semi_axis, t.major_semi_axis);
      // SI: the dissertation's particles are 0.4 mm .. 17 mm.
      EXPECT_GT(t.minor_semi_axis, 1e-4);
      EXPECT_LT(t.major_semi_axis, 2e-2);
      sum += t.fraction;
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
    EXPECT_GE(dispersity_index(psd), 1.0);
  }
  EXPECT_GE(files, 12) << "expected the 11 dissertation tables and mono_0.48mm";
}

// What each table of the dissertation says, for the transcription checks.
struct TableRef {
  std::string file;
  int table;
  std::vector<int> counts;           // "Number of Particles"
  std::vector<double> nominal_mm;    // "Particle Nominal Size (mm)"
  bool nominal_is_radius;            // tables 32-38 print cbrt(a b^2), 10-23 print 2 cbrt(a b^2)
  double delta = 0.0;                // Delta in the caption (tables 32-38), 0 if not stated
  int delta_decimals = 2;
};

const std::vector<TableRef>& tables() {
  static const std::vector<TableRef> t = {
      {"table10_sample_a", 10, {7284, 498, 150, 68}, {2.13, 6.55, 11.19, 16.03}, false},
      {"table11_sample_b", 11, {1448, 2056, 2252, 2244}, {11.69, 13.10, 14.54, 16.03}, false},
      {"table22_sample_c", 22, {9234, 513, 148, 67, 38}, {1.06, 3.19, 5.31, 7.44, 9.56}, false},
      {"table23_sample_d", 23, {7937, 1565, 364, 102, 32}, {1.59, 2.66, 4.25, 6.38, 9.03}, false},
      {"table32_type0", 32, {10000}, {1.06}, true, 1.0, 0},
      {"table33_type1", 33, {9234, 513, 148, 67, 38}, {1.06, 3.19, 5.31, 7.44, 9.56}, true, 6.00},
      {"table34_type2", 34, {7937, 1565, 364, 102, 32}, {1.59, 2.66, 4.25, 6.38, 9.03}, true, 2.84},
      {"table35_type3", 35, {990, 1488, 2292, 2704, 2526}, {10.63, 11.69, 12.75, 13.81, 14.88}, true, 1.28},
      {"table36_type4", 36, {9186, 588, 144, 55, 27}, {1.06, 2.66, 4.25, 5.84, 7.44}, true, 4.00},
      {"table37_type5", 37, {9843, 107, 28, 13, 9}, {1.06, 3.19, 4.78, 5.84, 6.38}, true, 2.75},
      {"table38_type_t", 38, {9601, 299, 59, 25, 16}, {1.06, 3.72, 6.38, 8.50, 10.63}, true, 6.15},
  };
  return t;
}

// The shipped files hold the tables' weight ratios; converted to number
// fractions they must give back the tables' particle counts (rounded to whole
// particles and adjusted to the total: within 2 particles per type).
TEST(PsdFile, ShippedTablesReproduceTheParticleCounts) {
  for (const auto& ref : tables()) {
    SCOPED_TRACE("Table " + std::to_string(ref.table) + " (" + ref.file + ".yaml)");
    const Psd psd = shipped(ref.file);
    ASSERT_EQ(psd.types.size(), ref.counts.size());
    int total = 0;
    for (int c : ref.counts) total += c;
    for (std::size_t i = 0; i < ref.counts.size(); ++i)
      EXPECT_NEAR(psd.types[i].fraction * total, ref.counts[i], 2.0) << "type " << i + 1;
  }
}

TEST(PsdFile, ShippedTablesReproduceTheNominalSizeColumn) {
  for (const auto& ref : tables()) {
    SCOPED_TRACE("Table " + std::to_string(ref.table) + " (" + ref.file + ".yaml)");
    const auto rows = nominal_radius_table(shipped(ref.file));
    ASSERT_EQ(rows.size(), ref.nominal_mm.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const double size_mm = rows[i].first * 1e3 * (ref.nominal_is_radius ? 1.0 : 2.0);
      expect_within_rounding(size_mm, ref.nominal_mm[i], 2, "nominal size of type " + std::to_string(i + 1));
    }
  }
}

TEST(PsdFile, ShippedTablesReproduceTheDispersityIndexOfTheirCaption) {
  for (const auto& ref : tables()) {
    if (ref.delta == 0.0) continue;
    expect_within_rounding(dispersity_index(shipped(ref.file)), ref.delta, ref.delta_decimals,
                           "Delta in the caption of table " + std::to_string(ref.table));
  }
}

// Table 39, column "Dispersity Index, Delta" (3 decimals), and table 46, row
// "Delta" (1 decimal). The sample name's last digit is the PSD type
// (0..5 -> tables 32..37); TTT uses Type T (table 38).
TEST(PsdFile, ShippedTablesReproduceTheDispersityIndicesOfTables39And46) {
  const std::map<std::string, std::string> type_file = {
      {"0", "table32_type0"}, {"1", "table33_type1"}, {"2", "table34_type2"}, {"3", "table35_type3"},
      {"4", "table36_type4"}, {"5", "table37_type5"}, {"T", "table38_type_t"}};
  struct Row { std::string sample; double delta; };
  const std::vector<Row> table39 = {
      {"121", 6.000}, {"122", 2.837}, {"211", 6.000}, {"212", 2.837}, {"220", 1.000},
      {"221", 6.000}, {"222", 2.837}, {"223", 1.280}, {"224", 4.000}, {"225", 2.750},
      {"231", 6.000}, {"232", 2.837}, {"241", 6.000}, {"242", 2.837}, {"321", 6.000},
      {"322", 2.837}, {"421", 6.000}, {"422", 2.837}, {"TTT", 6.150}};
  const std::vector<Row> table46 = {
      {"121", 6.0}, {"122", 2.8}, {"211", 6.0}, {"212", 2.8}, {"220", 1.0}, {"221", 6.0}, {"222", 2.8},
      {"223", 1.3}, {"224", 4.0}, {"225", 2.8}, {"231", 6.0}, {"232", 2.8}, {"241", 6.0}, {"242", 2.8},
      {"321", 6.0}, {"322", 2.8}, {"421", 6.0}, {"422", 2.8}, {"TTT", 6.2}};
  for (const auto& [rows, table, decimals] :
       {std::make_tuple(&table39, 39, 3), std::make_tuple(&table46, 46, 1)}) {
    for (const auto& r : *rows) {
      const std::string file = type_file.at(r.sample.substr(2));
      expect_within_rounding(dispersity_index(shipped(file)), r.delta, decimals,
                             "table " + std::to_string(table) + ", sample " + r.sample + " (" + file + ")");
    }
  }
}

// PSD-C / PSD-D (tables 22, 23) are Types 1 / 2 (tables 33, 34) at half size:
// the dispersity index does not see the scale.
TEST(PsdFile, DispersityIndexIsScaleFree) {
  EXPECT_NEAR(dispersity_index(shipped("table22_sample_c")), dispersity_index(shipped("table33_type1")), 1e-12);
  EXPECT_NEAR(dispersity_index(shipped("table23_sample_d")), dispersity_index(shipped("table34_type2")), 1e-12);
}

TEST(PsdFile, MonodisperseChapter4Psd) {
  const Psd psd = shipped("mono_0.48mm");
  ASSERT_EQ(psd.types.size(), 1u);
  EXPECT_DOUBLE_EQ(psd.types[0].major_semi_axis, 0.48e-3);
  EXPECT_DOUBLE_EQ(psd.types[0].minor_semi_axis, 0.40e-3);
  EXPECT_DOUBLE_EQ(psd.types[0].major_semi_axis / psd.types[0].minor_semi_axis, 1.2);
  EXPECT_EQ(psd.types[0].fraction, 1.0);
}

// ---- dispersity index ---------------------------------------------------------------

TEST(DispersityIndex, MonodisperseIsExactlyOne) {
  EXPECT_EQ(dispersity_index(shipped("mono_0.48mm")), 1.0);
  EXPECT_EQ(dispersity_index(shipped("table32_type0")), 1.0);
  // Same size listed twice, and a sphere.
  EXPECT_EQ(dispersity_index(parse_psd("fraction_basis: number\ntypes:\n"
                                       "  - {major_semi_axis: 1.2e-3, minor_semi_axis: 1.0e-3, fraction: 0.3}\n"
                                       "  - {major_semi_axis: 1.2e-3, minor_semi_axis: 1.0e-3, fraction: 0.7}\n")),
            1.0);
  EXPECT_EQ(dispersity_index(parse_psd("fraction_basis: mass\ntypes: [{radius: 7.3e-4, fraction: 1}]\n")), 1.0);
  EXPECT_EQ(dispersity_index(std::vector<double>(1000, 0.37e-3)), 1.0);
  EXPECT_EQ(dispersity_index(std::vector<double>{2.5e-3}), 1.0);
}

// Radii 1 and 2 mm at number fractions 1/2: masses 1:8, d_avg = (2*1 + 4*8)/9 mm
// = 34/9 mm, d_min = 2 mm -> Delta = 17/9.
TEST(DispersityIndex, HandComputedTwoTypeExample) {
  const double expected = 17.0 / 9.0;
  EXPECT_DOUBLE_EQ(dispersity_index(parse_psd("fraction_basis: number\ntypes:\n"
                                              "  - {radius: 1.0e-3, fraction: 0.5}\n"
                                              "  - {radius: 2.0e-3, fraction: 0.5}\n")),
                   expected);
  // Order does not matter; a spheroid with a b^2 = (2 mm)^3 has the same nominal size.
  EXPECT_DOUBLE_EQ(dispersity_index(parse_psd("fraction_basis: number\ntypes:\n"
                                              "  - {major_semi_axis: 8.0e-3, minor_semi_axis: 1.0e-3, fraction: 0.5}\n"
                                              "  - {radius: 1.0e-3, fraction: 0.5}\n")),
                   expected);
  // The same as explicit particle lists (any count, any order, any unit).
  EXPECT_DOUBLE_EQ(dispersity_index(std::vector<double>{1.0e-3, 2.0e-3}), expected);
  EXPECT_DOUBLE_EQ(dispersity_index(std::vector<double>{2.0, 1.0, 1.0, 2.0}), expected);
  // Radii 1, 1, 2: masses 1, 1, 8 -> d_avg = (2 + 2 + 4*8)/10 = 3.6, Delta = 1.8.
  EXPECT_DOUBLE_EQ(dispersity_index(std::vector<double>{1.0, 1.0, 2.0}), 1.8);
  // Given as mass fractions (1/9, 8/9) the same PSD gives the same Delta.
  EXPECT_NEAR(dispersity_index(parse_psd("fraction_basis: mass\ntypes:\n"
                                         "  - {radius: 1.0e-3, fraction: 0.1111111111111}\n"
                                         "  - {radius: 2.0e-3, fraction: 0.8888888888889}\n")),
              expected, 1e-12);
}

TEST(DispersityIndex, AgreesBetweenPsdAndParticleList) {
  // A particle list built from Table 37's counts gives the counts-based Delta,
  // which the table's rounded counts shift slightly away from the 2.75 of the
  // weight ratios.
  const Psd psd = shipped("table37_type5");
  const std::vector<int> counts = {9843, 107, 28, 13, 9};
  std::vector<double> radii;
  Psd from_counts;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    const double r = nominal_radius_table(psd)[i].first;
    radii.insert(radii.end(), counts[i], r);
    from_counts.types.push_back({psd.types[i].major_semi_axis, psd.types[i].minor_semi_axis, counts[i] / 10000.0});
  }
  EXPECT_NEAR(dispersity_index(radii), dispersity_index(from_counts), 1e-12);
  EXPECT_NEAR(dispersity_index(radii), dispersity_index(psd), 0.02);
}

TEST(DispersityIndex, RejectsBadInput) {
  EXPECT_THROW(dispersity_index(std::vector<double>{}), std::invalid_argument);
  EXPECT_THROW(dispersity_index(std::vector<double>{1.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(dispersity_index(std::vector<double>{1.0, -2.0}), std::invalid_argument);
  EXPECT_THROW(dispersity_index(std::vector<double>{1.0, std::nan("")}), std::invalid_argument);
  EXPECT_THROW(dispersity_index(std::vector<double>{1.0, INFINITY}), std::invalid_argument);
  EXPECT_THROW(dispersity_index(Psd{}), std::invalid_argument);
  Psd bad;
  bad.types.push_back({1.0, 0.0, 1.0});
  EXPECT_THROW(dispersity_index(bad), std::invalid_argument);
  bad.types = {{1.0, 1.0, 0.0}};
  EXPECT_THROW(dispersity_index(bad), std::invalid_argument);
}

// ---- parsing --------------------------------------------------------------------------

TEST(PsdParse, NominalRadiusTable) {
  const Psd psd = parse_psd("fraction_basis: number\ntypes:\n"
                            "  - {radius: 1.5e-3, fraction: 0.25}\n"
                            "  - {major_semi_axis: 1.2e-3, minor_semi_axis: 1.0e-3, fraction: 0.75}\n");
  const auto rows = nominal_radius_table(psd);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].first, 1.5e-3);  // a sphere's nominal radius is its radius, exactly
  EXPECT_DOUBLE_EQ(rows[0].second, 0.25);
  EXPECT_NEAR(rows[1].first, std::cbrt(1.2e-3 * 1.0e-3 * 1.0e-3), 1e-18);
  EXPECT_DOUBLE_EQ(rows[1].second, 0.75);
  EXPECT_EQ(psd.types[0].major_semi_axis, psd.types[0].minor_semi_axis);
}

TEST(PsdParse, MassFractionsConvertToNumberFractions) {
  // Spheres of 1 and 2 mm, masses 0.2 / 0.8: numbers ~ 0.2/1 : 0.8/8 = 2 : 1.
  Psd psd = parse_psd("fraction_basis: mass\ntypes:\n"
                      "  - {radius: 1.0e-3, fraction: 0.2}\n"
                      "  - {radius: 2.0e-3, fraction: 0.8}\n");
  ASSERT_EQ(psd.types.size(), 2u);
  EXPECT_NEAR(psd.types[0].fraction, 2.0 / 3.0, 1e-15);
  EXPECT_NEAR(psd.types[1].fraction, 1.0 / 3.0, 1e-15);
  // Spheroids: volume ~ a b^2, so (2.4, 2.0) mm has 8 x the volume of (1.2, 1.0) mm.
  psd = parse_psd("fraction_basis: Mass\ntypes:\n"
                  "  - {major_semi_axis: 1.2e-3, minor_semi_axis: 1.0e-3, fraction: 0.5}\n"
                  "  - {major_semi_axis: 2.4e-3, minor_semi_axis: 2.0e-3, fraction: 0.5}\n");
  EXPECT_NEAR(psd.types[0].fraction, 8.0 / 9.0, 1e-15);
  EXPECT_NEAR(psd.types[1].fraction, 1.0 / 9.0, 1e-15);
  // Only the minor axis differs: a b^2 ratio 4 for b doubled at equal a.
  psd = parse_psd("fraction_basis: mass\ntypes:\n"
                  "  - {major_semi_axis: 2.0e-3, minor_semi_axis: 1.0e-3, fraction: 0.5}\n"
                  "  - {major_semi_axis: 2.0e-3, minor_semi_axis: 2.0e-3, fraction: 0.5}\n");
  EXPECT_NEAR(psd.types[0].fraction, 0.8, 1e-15);
  EXPECT_NEAR(psd.types[1].fraction, 0.2, 1e-15);
  // Table 33: weight ratios 10/15/20/25/30 % -> 9234/513/148/67/38 of 10,000.
  const Psd t33 = shipped("table33_type1");
  EXPECT_NEAR(t33.types[0].fraction, 0.9234, 1e-4);
  EXPECT_NEAR(t33.types[4].fraction, 0.0038, 1e-4);
}

TEST(PsdParse, NumberFractionsAreRenormalisedAndToleranceIsOneInAMillion) {
  Psd psd = parse_psd("fraction_basis: number\ntypes:\n"
                      "  - {radius: 1.0e-3, fraction: 0.3333333}\n"
                      "  - {radius: 2.0e-3, fraction: 0.3333333}\n"
                      "  - {radius: 3.0e-3, fraction: 0.3333333}\n");
  EXPECT_NEAR(psd.types[0].fraction + psd.types[1].fraction + psd.types[2].fraction, 1.0, 1e-15);
  EXPECT_NEAR(psd.types[2].fraction, 1.0 / 3.0, 1e-15);
  EXPECT_NO_THROW(parse_psd("fraction_basis: number\ntypes: [{radius: 1.0e-3, fraction: 1.0000009}]\n"));
  EXPECT_THROW(parse_psd("fraction_basis: number\ntypes: [{radius: 1.0e-3, fraction: 1.0000011}]\n"), SceneError);
}

TEST(PsdParse, NameDefaultsToTheFileStem) {
  EXPECT_EQ(parse_psd("fraction_basis: number\ntypes: [{radius: 1.0e-3, fraction: 1}]\n").name, "");
  EXPECT_EQ(parse_psd("fraction_basis: number\ntypes: [{radius: 1.0e-3, fraction: 1}]\n", "/x/y/my_psd.yaml").name,
            "my_psd");
  EXPECT_EQ(parse_psd("name: given\nfraction_basis: number\ntypes: [{radius: 1.0e-3, fraction: 1}]\n",
                      "/x/y/my_psd.yaml")
                .name,
            "given");
  const fs::path tmp = fs::temp_directory_path() / ("vt_psd_file_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(tmp) << "fraction_basis: number\ntypes: [{radius: 1.0e-3, fraction: 1}]\n";
  const Psd psd = load_psd(tmp.string());
  std::error_code ec;
  fs::remove(tmp, ec);
  EXPECT_EQ(psd.name, tmp.stem().string());
}

// Every validation error names its field.
struct BadCase {
  std::string label;
  std::string yaml;
  std::string field;
  std::string reason_part;
};

const char* kBasis = "fraction_basis: number\n";

std::vector<BadCase> bad_cases() {
  const std::string b = kBasis;
  const auto one = [&](const std::string& entry) { return b + "types:\n  - " + entry + "\n"; };
  return {
      {"empty list", b + "types: []\n", "types", "empty"},
      {"null list", b + "types:\n", "types", "empty"},
      {"no types", b, "types", "required"},
      {"types not a list", b + "types: 3\n", "types", "expected a list"},
      {"entry not a mapping", b + "types:\n  - 3\n", "types[0]", "expected a mapping"},
      {"entry null", b + "types:\n  -\n", "types[0]", "expected a mapping"},
      {"fraction zero", one("{radius: 1.0e-3, fraction: 0}"), "types[0].fraction", "must be > 0"},
      {"fraction negative", b + "types:\n  - {radius: 1.0e-3, fraction: 1.5}\n  - {radius: 2.0e-3, fraction: -0.5}\n",
       "types[1].fraction", "must be > 0"},
      {"fraction missing", one("{radius: 1.0e-3}"), "types[0].fraction", "required"},
      {"fraction text", one("{radius: 1.0e-3, fraction: most}"), "types[0].fraction", "expected a number"},
      {"fraction nan", one("{radius: 1.0e-3, fraction: .nan}"), "types[0].fraction", "finite"},
      {"sum too small", b + "types:\n  - {radius: 1.0e-3, fraction: 0.5}\n  - {radius: 2.0e-3, fraction: 0.4}\n",
       "types", "sum to 0.9"},
      {"sum too large", b + "types:\n  - {radius: 1.0e-3, fraction: 0.6}\n  - {radius: 2.0e-3, fraction: 0.6}\n",
       "types", "sum to 1.2"},
      {"mass sum", "fraction_basis: mass\ntypes:\n  - {radius: 1.0e-3, fraction: 0.25}\n", "types",
       "mass fractions sum to 0.25"},
      {"radius zero", one("{radius: 0, fraction: 1}"), "types[0].radius", "must be > 0"},
      {"radius negative", one("{radius: -1.0e-3, fraction: 1}"), "types[0].radius", "must be > 0"},
      {"radius inf", one("{radius: .inf, fraction: 1}"), "types[0].radius", "finite"},
      {"radius nan", one("{radius: .nan, fraction: 1}"), "types[0].radius", "finite"},
      {"radius overflow", one("{radius: 1e999, fraction: 1}"), "types[0].radius", "finite"},
      {"major zero", one("{major_semi_axis: 0, minor_semi_axis: 1.0e-3, fraction: 1}"), "types[0].major_semi_axis",
       "must be > 0"},
      {"minor negative", one("{major_semi_axis: 1.2e-3, minor_semi_axis: -1.0e-3, fraction: 1}"),
       "types[0].minor_semi_axis", "must be > 0"},
      {"major inf", one("{major_semi_axis: .inf, minor_semi_axis: 1.0e-3, fraction: 1}"), "types[0].major_semi_axis",
       "finite"},
      {"minor nan", one("{major_semi_axis: 1.2e-3, minor_semi_axis: .nan, fraction: 1}"), "types[0].minor_semi_axis",
       "finite"},
      {"minor > major", one("{major_semi_axis: 1.0e-3, minor_semi_axis: 1.2e-3, fraction: 1}"),
       "types[0].minor_semi_axis", "must be <= major_semi_axis"},
      {"radius and semi-axes", one("{radius: 1.0e-3, major_semi_axis: 1.2e-3, minor_semi_axis: 1.0e-3, fraction: 1}"),
       "types[0].radius", "not both"},
      {"radius and major", one("{radius: 1.0e-3, major_semi_axis: 1.2e-3, fraction: 1}"), "types[0].radius",
       "not both"},
      {"major only", one("{major_semi_axis: 1.2e-3, fraction: 1}"), "types[0].minor_semi_axis", "required"},
      {"minor only", one("{minor_semi_axis: 1.0e-3, fraction: 1}"), "types[0].major_semi_axis", "required"},
      {"no size", one("{fraction: 1}"), "types[0]", "give radius"},
      {"unknown type key", one("{radius: 1.0e-3, fraction: 1, shape: sphere}"), "types[0].shape", "unknown key"},
      {"duplicate type key", one("{radius: 1.0e-3, fraction: 0.5, fraction: 0.5}"), "types[0].fraction", "duplicate"},
      {"unknown top key", b + "colour: red\ntypes: [{radius: 1.0e-3, fraction: 1}]\n", "colour", "unknown key"},
      {"bad basis", "fraction_basis: volume\ntypes: [{radius: 1.0e-3, fraction: 1}]\n", "fraction_basis",
       "'number' or 'mass'"},
      {"basis missing", "types: [{radius: 1.0e-3, fraction: 1}]\n", "fraction_basis", "required"},
      {"basis a list", "fraction_basis: [number]\ntypes: [{radius: 1.0e-3, fraction: 1}]\n", "fraction_basis",
       "expected a string"},
      {"syntax error", b + "types: [{radius: 1.0e-3, fraction: 1}\n", "psd", "YAML syntax error"},
      {"empty document", "", "psd", "empty document"},
      {"top level a list", "- 1\n- 2\n", "psd", "expected a mapping"},
      {"two documents", b + "types: [{radius: 1.0e-3, fraction: 1}]\n---\n" + b, "psd", "2 YAML documents"},
  };
}

TEST(PsdParse, EveryValidationErrorNamesItsField) {
  for (const auto& c : bad_cases()) {
    SCOPED_TRACE(c.label);
    try {
      parse_psd(c.yaml, "case.yaml");
      ADD_FAILURE() << "accepted:\n" << c.yaml;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.field(), c.field) << e.what();
      EXPECT_NE(e.reason().find(c.reason_part), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).rfind(c.field + ": ", 0), 0u) << e.what();
    }
  }
}

TEST(PsdParse, EmptyTypesReasonIsEmpty) {
  try {
    parse_psd("fraction_basis: number\ntypes: []\n");
    FAIL() << "accepted an empty types list";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), "types");
    EXPECT_EQ(e.reason().rfind("empty", 0), 0u) << e.what();
  }
}

TEST(PsdParse, MissingFileNamesThePath) {
  const std::string path = (kPsdDir / "no_such_psd.yaml").string();
  try {
    load_psd(path);
    FAIL() << "loaded a missing file";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), "psd");
    EXPECT_NE(e.reason().find("cannot open"), std::string::npos) << e.what();
    EXPECT_NE(e.reason().find(path), std::string::npos) << e.what();
  }
  try {
    load_psd(kPsdDir.string());
    FAIL() << "loaded a directory";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), "psd");
    EXPECT_NE(e.reason().find("is a directory"), std::string::npos) << e.what();
  }
}

}  // namespace
