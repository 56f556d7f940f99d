// triax_qs: the quasi-static advisor (Yousefi 2017, chapters 5-6).
//
//   triax_qs predict PROTOCOL.yaml [--cost S]
//       eps'_QS of the protocol's sample by eq. 84 (and eq. 85, eq. 72), the
//       shear stage's plan at its rate and at eps'_QS, warnings; instant.
//   triax_qs fit-rates --run EPS',SUMMARY.json [--run ...] [--threshold I]
//       eq. 73 (and eqs. 74, 75) from finished runs at one damping ratio;
//       SUMMARY.json is triax_run's JSON summary line (or a file holding it).
//   triax_qs fit-damping --run XI,EPS',SUMMARY.json [--run ...] [--threshold I]
//       optimum damping ratio (parabola in ln xi - ln I_mom), eq. 86 and the
//       damping-based phi_QS (eq. 74 over xi >= xi_opt).
//   triax_qs rate-sweep PROTOCOL.yaml --rates 1e-5,5e-6,2e-6 [--jobs J] [--out DIR]
//                       [--backend local|slurm] [--threshold I]
//   triax_qs damping-sweep PROTOCOL.yaml --ratios ... --model OD|ND --rate EPS' [...]
//       run the shear stage at each rate (damping ratio) through triax_sweep's
//       code (parallel, resumable, local or Slurm), then fit-rates /
//       fit-damping on the finished runs, and write a report folder. These
//       two exec scripts/triax_qs_sweep (Python, package vt_qs_sweep), which
//       calls this program back for the fits: the sweeps have their home in
//       vt_sweep, the fits here.
// Progress and messages on stderr; the result is the last stdout line, one
// JSON object with unit-named keys. Exit codes as triax_run's: 0 done,
// 2 bad input (one line naming the field).
#include <unistd.h>
#include "virtual_triaxial/io/number_text.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "virtual_triaxial/io/qs_advice.h"
#include "virtual_triaxial/io/scene_builder.h"
#include "virtual_triaxial/io/scene_error.h"
#include "virtual_triaxial/io/scene_parser.h"
#include "virtual_triaxial/quasi_static/cowper_symonds_fit.h"
#include "virtual_triaxial/quasi_static/friction_line_fit.h"
#include "virtual_triaxial/quasi_static/optimum_damping.h"
#include "virtual_triaxial/quasi_static/rate_sweep_fit.h"

namespace qs = vt::quasi_static;

namespace {

const char* kUsage =
    "usage: triax_qs predict PROTOCOL.yaml [--cost SECONDS_PER_PARTICLE_STEP]\n"
    "       triax_qs fit-rates --run EPS',SUMMARY.json --run ... [--threshold I_QS]\n"
    "       triax_qs fit-damping --run XI,EPS',SUMMARY.json --run ... [--threshold I_QS]\n"
    "       triax_qs rate-sweep PROTOCOL.yaml --rates 1e-5,5e-6,2e-6 [--jobs J] [--out DIR] [--backend local|slurm]\n"
    "       triax_qs damping-sweep PROTOCOL.yaml --ratios 0.001,0.003,0.01 --model OD|ND --rate EPS' [...]\n";

struct BadInput : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string num(double v) { return std::isfinite(v) ? vt::io::number_text(v, 6) : "null"; }

double parse_number(const std::string& text, const std::string& field) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v))
    throw BadInput(field + ": expected a number, got '" + text + "'");
  return v;
}

// The value of a numeric key in triax_run's JSON summary (its last line).
double summary_number(const std::string& path, const std::string& key, const std::string& field) {
  std::ifstream in(path);
  if (!in) throw BadInput(field + ": cannot open '" + path + "'");
  std::string line, last;
  while (std::getline(in, line))
    if (line.find('{') != std::string::npos) last = line;
  const std::string k = "\"" + key + "\":";
  const auto pos = last.find(k);
  if (pos == std::string::npos)
    throw BadInput(field + ": '" + path + "' has no \"" + key + "\" (a triax_run summary of a shear test?)");
  return parse_number(last.substr(pos + k.size(), last.find_first_of(",}", pos + k.size()) - pos - k.size()),
                      field + "." + key);
}

struct Run {
  double xi = 0.0, eps_prime = 0.0, i_mom = 0.0, phi_deg = 0.0;
};

// "--run a,b,...,SUMMARY": `numbers` leading numbers then a summary file.
std::vector<Run> parse_runs(const std::vector<std::string>& specs, int numbers) {
  std::vector<Run> runs;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const std::string field = "--run[" + std::to_string(i) + "]";
    std::vector<std::string> parts;
    std::stringstream ss(specs[i]);
    std::string p;
    while (std::getline(ss, p, ',')) parts.push_back(p);
    if (static_cast<int>(parts.size()) != numbers + 1)
      throw BadInput(field + ": expected " + (numbers == 1 ? "EPS',SUMMARY" : "XI,EPS',SUMMARY") +
                     ", got '" + specs[i] + "'");
    Run r;
    if (numbers == 2) r.xi = parse_number(parts[0], field + ".xi");
    r.eps_prime = parse_number(parts[numbers - 1], field + ".eps_prime");
    r.i_mom = summary_number(parts[numbers], "mean_moment_index_to_peak", field);
    r.phi_deg = summary_number(parts[numbers], "phi_peak_deg", field);
    runs.push_back(r);
  }
  return runs;
}

std::string fit_rates(const std::vector<Run>& runs, double threshold) {
  std::vector<qs::RatePoint> rp;
  std::vector<qs::FrictionPoint> fp;
  std::vector<qs::RateFrictionPoint> cp;
  for (const Run& r : runs) {
    rp.push_back({r.eps_prime, r.i_mom});
    fp.push_back({r.i_mom, r.phi_deg, r.xi});
    cp.push_back({r.eps_prime, r.phi_deg});
  }
  const qs::RateSweepFit f = qs::fit_rate_sweep(rp, threshold);
  const qs::FrictionLineFit line = qs::fit_friction_line(fp, "--run");
  std::string o = "{\"runs\":" + std::to_string(runs.size()) + ",\"quasi_static_threshold\":" + num(threshold) +
                  ",\"a_i_eq73\":" + num(f.law.a) + ",\"b_i_eq73\":" + num(f.law.b) +
                  ",\"r_squared_eq73\":" + num(f.law.r_squared) +
                  ",\"eps_prime_qs_eq73\":" + num(f.eps_prime_qs) +
                  ",\"se_ln_eps_prime_qs_eq73\":" + num(f.se_ln_eps_prime_qs) +
                  ",\"extrapolation_decades\":" + num(f.extrapolation_decades) +
                  ",\"phi_qs_eq74_deg\":" + num(line.phi_qs_deg) +
                  ",\"se_phi_qs_eq74_deg\":" + num(line.se_phi_qs_deg) +
                  ",\"k_eq74\":" + num(line.slope) + ",\"r_squared_eq74\":" + num(line.r_squared);
  if (runs.size() >= 3) {
    const qs::CowperSymondsFit cs = qs::fit_cowper_symonds(cp);
    o += ",\"phi_qs_eq75_deg\":" + num(cs.phi_qs_deg) + ",\"a_phi_eq75\":" + num(cs.a_phi) +
         ",\"b_phi_eq75\":" + num(cs.b_phi) + ",\"b_phi_eq75_at_bound\":" + (cs.b_at_bound ? "true" : "false");
  }
  std::fprintf(stderr, "triax_qs: eq. 73: I_mom = %.4g eps'^%.3f (R^2 %s) -> eps'_QS = %.3g at I_QS = %g\n",
               f.law.a, f.law.b, num(f.law.r_squared).c_str(), f.eps_prime_qs, threshold);
  std::fprintf(stderr, "triax_qs: eq. 74: phi_QS = %.2f deg (+- %s)\n", line.phi_qs_deg,
               num(line.se_phi_qs_deg).c_str());
  return o + "}";
}

std::string fit_damping(const std::vector<Run>& runs, double threshold) {
  std::vector<qs::DampingPoint> dp;
  std::vector<qs::FrictionPoint> fp;
  std::vector<qs::DampingRatePoint> rp;
  for (const Run& r : runs) {
    dp.push_back({r.xi, r.i_mom});
    fp.push_back({r.i_mom, r.phi_deg, r.xi});
    rp.push_back({r.xi, r.eps_prime, r.i_mom});
  }
  const qs::OptimumDamping opt = qs::find_optimum_damping(dp);
  std::string o = "{\"runs\":" + std::to_string(runs.size()) + ",\"optimum_damping_ratio\":" + num(opt.ratio) +
                  ",\"min_mean_moment_index\":" + num(opt.min_i_mom);
  std::fprintf(stderr, "triax_qs: optimum damping ratio %.4g %% (I_mom %.4g)\n", 100 * opt.ratio, opt.min_i_mom);
  try {
    const qs::FrictionLineFit line = qs::fit_friction_line_above_optimum(fp, opt.ratio);
    o += ",\"phi_qs_damping_based_deg\":" + num(line.phi_qs_deg) + ",\"k_damping_based\":" + num(line.slope) +
         ",\"se_phi_qs_damping_based_deg\":" + num(line.se_phi_qs_deg) +
         ",\"runs_above_optimum\":" + std::to_string(line.points);
    const qs::RateSweepFit f = qs::fit_damping_rate_product(rp, opt.ratio, threshold);
    o += ",\"a_i_eq86\":" + num(f.law.a) + ",\"b_i_eq86\":" + num(f.law.b) +
         ",\"xi_eps_prime_qs_eq86\":" + num(f.eps_prime_qs);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "triax_qs: warning: no fit above the optimum: %s\n", e.what());
  }
  return o + "}";
}

/// rate-sweep / damping-sweep: replaces this process by scripts/triax_qs_sweep
/// (its exit code is the command's); VT_PROGRAM_DIR / VT_TRIAX_QS tell it
/// where triax_run and this program are.
int exec_sweep(int argc, char** argv) {
  char self[4096];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n > 0) {
    self[n] = '\0';
    std::string dir(self);
    dir = dir.substr(0, dir.find_last_of('/'));
    setenv("VT_PROGRAM_DIR", dir.c_str(), 0);
    setenv("VT_TRIAX_QS", self, 0);
  }
  std::string script = std::string(VT_SCRIPTS_DIR) + "/triax_qs_sweep";
  std::vector<char*> args;
  std::string python = "/usr/bin/python3";
  args.push_back(python.data());
  args.push_back(script.data());
  for (int i = 1; i < argc; ++i) args.push_back(argv[i]);
  args.push_back(nullptr);
  std::fflush(nullptr);
  execv(args[0], args.data());
  std::fprintf(stderr, "triax_qs: error: %s: cannot start %s: %s\n", argv[1], script.c_str(), std::strerror(errno));
  return 2;
}

int run(int argc, char** argv) {
  if (argc < 2) throw BadInput("command: missing (predict, fit-rates, fit-damping, rate-sweep or damping-sweep)");
  const std::string cmd = argv[1];
  if (cmd == "rate-sweep" || cmd == "damping-sweep") return exec_sweep(argc, argv);
  std::string protocol;
  std::vector<std::string> runs;
  double cost = 0.0, threshold = 1e-3;
  for (int i = 2; i < argc; ++i) {
    const std::string s = argv[i];
    auto value = [&](const char* name) {
      if (i + 1 >= argc) throw BadInput(std::string(name) + ": missing value");
      return std::string(argv[++i]);
    };
    if (s == "--cost") {
      cost = parse_number(value("--cost"), "--cost");
      if (!(cost > 0.0)) throw BadInput("--cost: must be > 0 seconds per particle-step");
    } else if (s == "--threshold") {
      threshold = parse_number(value("--threshold"), "--threshold");
    } else if (s == "--run") {
      runs.push_back(value("--run"));
    } else if (!s.empty() && s[0] == '-') {
      throw BadInput(s + ": unknown option");
    } else if (protocol.empty()) {
      protocol = s;
    } else {
      throw BadInput(s + ": unexpected argument");
    }
  }
  std::string json;
  if (cmd == "predict") {
    if (protocol.empty()) throw BadInput("PROTOCOL.yaml: missing");
    const vt::io::SceneConfig scene = vt::io::load_scene(protocol);
    const vt::dem::Simulation sim = vt::io::build_simulation(scene);
    const vt::io::QsAdvice a = vt::io::build_qs_advice(scene, sim, cost);
    std::fprintf(stderr,
                 "triax_qs: %zu %ss, e0 = %.4f, sigma_c = %.4g Pa (sigma_bar0 = %.3g), Delta = %.3f (eq. 80)\n"
                 "triax_qs: eq. 84 (%s, I_QS = %g): eps'_QS = %.3g (%.3g 1/s, eq. 85); other damping model %.3g; "
                 "eq. 72 (I = %.2g): %.3g%s\n"
                 "triax_qs: shear stage '%s' at eps' = %.3g to %.3g: %.0f steps, ~%.0f s; at eps'_QS: %.0f steps, "
                 "~%.0f s (%.3g us per particle-step, %s)\n",
                 a.particles, a.spheroids ? "spheroid" : "sphere", a.void_ratio, a.confining_pressure, a.sigma_bar0,
                 a.dispersity_index, qs::to_string(a.damping), a.threshold, a.prediction.eps_prime_qs,
                 a.prediction.eps_prime_qs / a.t0, a.eps_prime_qs_other_model, a.inertial_threshold,
                 a.eps_prime_eq72, a.prediction.inside_calibration ? "" : " (outside eq. 84's calibration)",
                 a.shear_stage.c_str(), a.shear_eps_prime, a.final_strain, a.plan_requested.steps,
                 a.plan_requested.wall_seconds, a.plan_at_qs.steps, a.plan_at_qs.wall_seconds,
                 1e6 * a.seconds_per_particle_step, a.cost_measured ? "measured now" : "given");
    for (const std::string& w : a.warnings) std::fprintf(stderr, "triax_qs: warning: %s\n", w.c_str());
    json = vt::io::qs_advice_json(a);
  } else if (cmd == "fit-rates" || cmd == "fit-damping") {
    if (!protocol.empty()) throw BadInput(protocol + ": unexpected argument (runs are given with --run)");
    const bool damping = cmd == "fit-damping";
    if (runs.size() < (damping ? 3u : 2u))
      throw BadInput(std::string("--run: ") + (damping ? "at least 3 runs" : "at least 2 runs") + " needed");
    json = damping ? fit_damping(parse_runs(runs, 2), threshold) : fit_rates(parse_runs(runs, 1), threshold);
  } else if (cmd == "-h" || cmd == "--help") {
    std::fputs(kUsage, stderr);
    return 0;
  } else {
    throw BadInput("command: unknown '" + cmd + "' (predict, fit-rates, fit-damping, rate-sweep or damping-sweep)");
  }
  std::printf("%s\n", json.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const BadInput& e) {
    std::fprintf(stderr, "triax_qs: error: %s\n%s", e.what(), kUsage);
  } catch (const vt::io::SceneError& e) {
    std::fprintf(stderr, "triax_qs: error: %s\n", e.what());
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "triax_qs: error: %s\n", e.what());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "triax_qs: error: %s\n", e.what());
  }
  return 2;
}
