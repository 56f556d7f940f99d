// The run-limits table (tests/data/run_limits_cases.yaml) that both runners'
// tests read: each case is a protocol (drained_mini.yaml with one value
// changed) and the start of the one-line refusal both runners must give.
// Header-only (yaml-cpp), so the rostests can include it too.
#pragma once

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace vt::test {

struct RunLimitsCase {
  std::string name;
  std::string yaml;     ///< the whole protocol
  std::string message;  ///< the refusal starts with this
};

/// `data_dir`: tests/data; `sample`: absolute path of the sample the
/// protocols load (replaces their relative path and SAMPLE in the table).
inline std::vector<RunLimitsCase> run_limits_cases(const std::string& data_dir, const std::string& sample) {
  const YAML::Node table = YAML::LoadFile(data_dir + "/run_limits_cases.yaml");
  std::ifstream in(data_dir + "/" + table["base"].as<std::string>());
  std::stringstream ss;
  ss << in.rdbuf();
  std::string base = ss.str();
  const std::string rel = "../sample_200_100kPa.h5";
  const std::size_t at = base.find(rel);
  if (at == std::string::npos) throw std::runtime_error("run_limits_cases: no " + rel + " in the base protocol");
  base.replace(at, rel.size(), sample);
  std::vector<RunLimitsCase> cases;
  for (const YAML::Node& c : table["cases"]) {
    std::string from = c["from"].as<std::string>();
    if (const std::size_t s = from.find("SAMPLE"); s != std::string::npos) from.replace(s, 6, sample);
    std::string yaml = base;
    const std::size_t f = yaml.find(from);
    if (f == std::string::npos) throw std::runtime_error("run_limits_cases: '" + from + "' not in the base protocol");
    yaml.replace(f, from.size(), c["to"].as<std::string>());
    cases.push_back({c["name"].as<std::string>(), yaml, c["message"].as<std::string>()});
  }
  return cases;
}

}  // namespace vt::test
