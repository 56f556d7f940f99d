// triax_prepare end to end: a small sample is prepared and written with its
// provenance; bad inputs (empty PSD, fractions not summing to 1, pressure <= 0,
// mu1 < 0, unwritable output) give exit code 2 and an error naming the field.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/cli.h"
#include "virtual_triaxial/io/sample_file.h"

namespace fs = std::filesystem;

namespace {

using vt::test::CliRun;

fs::path tmp() {
  static const fs::path d = vt::test::scratch_dir("prep_cli");
  return d;
}

CliRun prepare(const std::string& args) { return vt::test::run_program("triax_prepare", args, tmp()); }

fs::path psd(const std::string& name, const std::string& types) {
  const fs::path p = tmp() / name;
  std::ofstream(p) << "name: " << name << "\nfraction_basis: number\ntypes:\n" << types;
  return p;
}

const char* kTwoSizes = "  - {radius: 0.9e-3, fraction: 0.5}\n  - {radius: 1.1e-3, fraction: 0.5}\n";

}  // namespace

TEST(TriaxPrepareCli, PreparesAndWritesASampleWithProvenance) {
  const fs::path out = tmp() / "small.h5";
  const CliRun r = prepare("--psd " + psd("two.yaml", kTwoSizes).string() +
                           " --pressure 100000 --mu1 0.2 --seed 7 --particles 100 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("[shrinkage]"), std::string::npos) << "progress per phase";
  EXPECT_NE(r.err.find("[compression]"), std::string::npos);
  EXPECT_NE(r.out.find("\"converged\":true"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"e0\":"), std::string::npos);
  vt::io::SampleMetadata meta;
  const vt::dem::SimulationState st = vt::io::read_sample(out.string(), &meta);
  EXPECT_EQ(st.particles.size(), 100u);
  EXPECT_EQ(meta.seed, 7u);
  EXPECT_EQ(meta.friction_during_shrinkage, 0.2);
  EXPECT_EQ(meta.target_pressure, 100000.0);
  EXPECT_NE(meta.created_by.find("triax_prepare"), std::string::npos);
}

TEST(TriaxPrepareCli, BadInputsExitWithCode2AndNameTheField) {
  const std::string good = psd("good.yaml", kTwoSizes).string();
  const std::string out = (tmp() / "x.h5").string();
  struct Case {
    std::string name, args, field;
  } cases[] = {
      {"empty psd", "--psd " + psd("empty.yaml", "  []\n").string() + " --pressure 1e5 --mu1 0.1 --seed 1 --out " + out,
       "types"},
      {"fractions", "--psd " + psd("sum.yaml", "  - {radius: 1e-3, fraction: 0.5}\n  - {radius: 2e-3, fraction: 0.3}\n").string() +
                        " --pressure 1e5 --mu1 0.1 --seed 1 --out " + out,
       "types"},
      {"pressure zero", "--psd " + good + " --pressure 0 --mu1 0.1 --seed 1 --out " + out, "--pressure"},
      {"pressure negative", "--psd " + good + " --pressure -3 --mu1 0.1 --seed 1 --out " + out, "--pressure"},
      {"mu1 negative", "--psd " + good + " --pressure 1e5 --mu1 -0.2 --seed 1 --out " + out, "--mu1"},
      {"unwritable", "--psd " + good + " --pressure 1e5 --mu1 0.1 --seed 1 --out /nonexistent_dir/x.h5", "--out"},
      {"missing psd", "--psd " + (tmp() / "nope.yaml").string() + " --pressure 1e5 --mu1 0.1 --seed 1 --out " + out,
       "nope.yaml"},
  };
  for (const Case& c : cases) {
    const CliRun r = prepare(c.args);
    EXPECT_EQ(r.code, 2) << c.name << ": " << r.err;
    EXPECT_NE(r.err.find(c.field), std::string::npos) << c.name << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(out));
}
