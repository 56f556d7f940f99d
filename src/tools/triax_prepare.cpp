// triax_prepare --psd FILE --pressure PA --mu1 MU --seed S --out sample.h5
//               [--aspect 1,1,1] [--particles N] [--shape psd|sphere] [--target-void-ratio E]
//               [--e-min E --e-max E] [--damping-ratio XI] [--young-modulus PA]
//               [--poisson-ratio NU] [--density RHO] [--friction MU_FINAL] [--quiet]
// Material flags default to rho 2650 kg/m^3, E 70 GPa, nu 0.3, final mu 0.5;
// `--damping-ratio` is the OD ratio of every phase (default 0.003).
// `--shape psd` (default) prepares the PSD's own shapes: prolate spheroids
// (chapter 4, random orientations) for types with a > b; `--shape sphere`
// replaces every type by the sphere of equal volume.
//
// Prepares a sample with the automatic three-phase method (chapter 4.3):
// prints progress per phase and a summary; the last stdout line is JSON.
// --target-void-ratio finds mu1 by bisection on the monotonic e(mu1)
// relation (fig. 11) within 0.005 and says when the target is out of reach.
// Exit codes: 0 prepared, 2 bad input or unreachable target, 3 preparation
// failed (numerical failure or no convergence).
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>

#include "virtual_triaxial/dem/cloud_generator.h"
#include "virtual_triaxial/io/psd_file.h"
#include "virtual_triaxial/io/sample_file.h"
#include "virtual_triaxial/io/scene_error.h"
#include "virtual_triaxial/protocol/sample_preparation.h"
#include "virtual_triaxial/protocol/void_ratio_search.h"

namespace {

struct BadArg : std::runtime_error {
  using std::runtime_error::runtime_error;
};

double number(const std::string& flag, const char* text) {
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(v)) throw BadArg(flag + ": '" + text + "' is not a number");
  return v;
}

vt::dem::Vec3 triple(const std::string& flag, const std::string& text) {
  vt::dem::Vec3 v;
  std::stringstream ss(text);
  std::string part;
  int i = 0;
  while (std::getline(ss, part, ',')) {
    if (i >= 3) throw BadArg(flag + ": expected three comma-separated numbers");
    v[i++] = number(flag, part.c_str());
  }
  if (i != 3) throw BadArg(flag + ": expected three comma-separated numbers");
  return v;
}

struct Args {
  std::string psd, out;
  double pressure = NAN, mu1 = NAN, target_e = NAN, e_min = NAN, e_max = NAN, damping = 0.003;
  vt::dem::Material material;
  std::uint64_t seed = 1;
  bool has_seed = false, quiet = false;
  vt::dem::Vec3 aspect{1, 1, 1};
  long particles = 1000;
  std::string shape = "psd";  ///< psd: the PSD's own shapes (spheroids where a > b); sphere: equal-volume spheres
};

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string f = argv[i];
    auto val = [&]() -> const char* {
      if (i + 1 >= argc) throw BadArg(f + ": missing value");
      return argv[++i];
    };
    if (f == "--psd") a.psd = val();
    else if (f == "--out") a.out = val();
    else if (f == "--pressure") a.pressure = number(f, val());
    else if (f == "--mu1") a.mu1 = number(f, val());
    else if (f == "--target-void-ratio") a.target_e = number(f, val());
    else if (f == "--e-min") a.e_min = number(f, val());
    else if (f == "--e-max") a.e_max = number(f, val());
    else if (f == "--damping-ratio") a.damping = number(f, val());
    else if (f == "--young-modulus") a.material.young = number(f, val());
    else if (f == "--poisson-ratio") a.material.poisson = number(f, val());
    else if (f == "--density") a.material.density = number(f, val());
    else if (f == "--friction") a.material.friction = number(f, val());
    else if (f == "--aspect") a.aspect = triple(f, val());
    else if (f == "--shape") {
      a.shape = val();
      if (a.shape != "psd" && a.shape != "sphere")
        throw BadArg("--shape: expected psd (the PSD's spheroids) or sphere (equal-volume spheres), got '" + a.shape +
                     "'");
    }
    else if (f == "--particles") {
      const double n = number(f, val());
      if (n != std::floor(n) || n < 2 || n > 1e8) throw BadArg("--particles: must be an integer >= 2");
      a.particles = static_cast<long>(n);
    } else if (f == "--seed") {
      const double s = number(f, val());
      if (s != std::floor(s) || s < 0) throw BadArg("--seed: must be a non-negative integer");
      a.seed = static_cast<std::uint64_t>(s);
      a.has_seed = true;
    } else if (f == "--quiet") a.quiet = true;
    else throw BadArg("unknown option '" + f + "'");
  }
  if (a.psd.empty()) throw BadArg("--psd: required");
  if (a.out.empty()) throw BadArg("--out: required");
  if (!(a.pressure > 0)) throw BadArg("--pressure: must be > 0 Pa");
  if (std::isnan(a.mu1) && std::isnan(a.target_e)) throw BadArg("--mu1: required (or give --target-void-ratio)");
  if (!std::isnan(a.mu1) && !std::isnan(a.target_e)) throw BadArg("--mu1: give either --mu1 or --target-void-ratio");
  if (!std::isnan(a.mu1) && a.mu1 < 0) throw BadArg("--mu1: must be >= 0");
  if (!std::isnan(a.target_e) && !(a.target_e > 0)) throw BadArg("--target-void-ratio: must be > 0");
  if (!a.has_seed) throw BadArg("--seed: required");
  for (int k = 0; k < 3; ++k)
    if (!(a.aspect[k] > 0)) throw BadArg("--aspect: every ratio must be > 0");
  if (!(a.damping >= 0)) throw BadArg("--damping-ratio: must be >= 0");
  const std::string bad_material = a.material.validate();
  if (!bad_material.empty()) throw BadArg("--" + bad_material);
  // Fail before hours of work if the output cannot be written.
  const std::filesystem::path dir = std::filesystem::absolute(a.out).parent_path();
  if (!std::filesystem::is_directory(dir) || ::access(dir.c_str(), W_OK) != 0)
    throw BadArg("--out: cannot write into '" + dir.string() + "' (missing or not writable)");
  return a;
}

int usage_error(const std::string& msg) {
  std::fprintf(stderr, "triax_prepare: error: %s\nusage: triax_prepare --psd FILE --pressure PA --mu1 MU --seed S "
                       "--out sample.h5 [--aspect 1,1,1] [--particles N] [--shape psd|sphere] [--target-void-ratio E] "
                       "[--e-min E --e-max E] [--damping-ratio XI] [--young-modulus PA] [--poisson-ratio NU] [--density RHO] "
                       "[--friction MU_FINAL] [--quiet]\n",
               msg.c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  vt::io::Psd psd;
  try {
    a = parse(argc, argv);
    psd = vt::io::load_psd(a.psd);
  } catch (const BadArg& e) {
    return usage_error(e.what());
  } catch (const vt::io::SceneError& e) {
    return usage_error(std::string("--psd ") + a.psd + ": " + e.what());
  }
  vt::protocol::PreparationSettings s;
  {
    vt::io::PsdParticles pp = vt::io::psd_particles(psd, a.particles);
    s.radii = std::move(pp.radii);
    if (a.shape == "psd") {
      bool any = false;
      for (double k : pp.aspect_ratios) any = any || k != 1.0;
      if (any) s.aspect_ratios = std::move(pp.aspect_ratios);
    }
  }
  s.material = a.material;
  s.pressure = a.pressure;
  s.aspect = a.aspect;
  s.seed = a.seed;
  s.damping = vt::dem::MassDamping(vt::dem::DampingModel::OD, a.damping);
  const double delta = vt::io::dispersity_index(psd);
  auto progress = [&](const std::string& line) {
    if (!a.quiet) std::fprintf(stderr, "%s\n", line.c_str());
  };
  std::fprintf(stderr, "triax_prepare: %ld particles from %s (dispersity index %.3f, eq. 80), target %.4g Pa\n",
               a.particles, a.psd.c_str(), delta, a.pressure);
  vt::protocol::PreparationResult r;
  double mu1 = a.mu1;
  try {
    if (!std::isnan(a.target_e)) {
      const vt::protocol::VoidRatioSearch search = vt::protocol::find_mu1_for_void_ratio(s, a.target_e, 0.005, progress);
      if (!search.reachable) {
        std::fprintf(stderr, "triax_prepare: error: %s\n", search.message.c_str());
        return 2;
      }
      r = search.result;
      mu1 = search.mu1;
    } else {
      s.mu1 = a.mu1;
      r = vt::protocol::prepare_sample(s, progress);
    }
  } catch (const std::invalid_argument& e) {
    return usage_error(e.what());
  }
  if (!r.converged) {
    std::fprintf(stderr, "triax_prepare: preparation failed: %s\n", r.failure.c_str());
    std::printf("{\"converged\":false,\"failure\":\"%s\"}\n", r.failure.c_str());
    return 3;
  }
  vt::io::SampleMetadata meta;
  meta.seed = a.seed;
  meta.friction_during_shrinkage = mu1;
  meta.target_pressure = a.pressure;
  meta.initial_void_ratio = r.final.void_ratio;
  meta.software_version = "virtual_triaxial 0.1.0";
  std::string cmd;
  for (int i = 0; i < argc; ++i) cmd += (i ? " " : "") + std::string(argv[i]);
  meta.created_by = cmd;
  meta.description = "three-phase preparation (chapter 4.3), psd " + psd.name;
  vt::io::write_sample(a.out, r.state, meta);

  const vt::dem::Measures& m = r.final;
  const bool has_dr = std::isfinite(a.e_min) && std::isfinite(a.e_max) && a.e_max > a.e_min;
  const double dr = has_dr ? (a.e_max - m.void_ratio) / (a.e_max - a.e_min) : NAN;
  std::fprintf(stderr, "triax_prepare: e0 %.4f, relative density %s, Z %.3f, idle mass fraction %.3f, UFR %.2e\n",
               m.void_ratio, has_dr ? std::to_string(dr).c_str() : "n/a (give --e-min and --e-max)",
               m.coordination_number, m.idle_mass_fraction, m.ufr);
  std::fprintf(stderr, "triax_prepare: stresses %.2f %.2f %.2f kPa, aspect %.4f %.4f %.4f, %lld steps, %.1f s -> %s\n",
               m.stress(0, 0) / 1e3, m.stress(1, 1) / 1e3, m.stress(2, 2) / 1e3, r.aspect.x, r.aspect.y, r.aspect.z,
               static_cast<long long>(r.steps), r.wall_seconds, a.out.c_str());
  std::printf("{\"converged\":true,\"e0\":%.6f,\"relative_density\":%s,\"mu1\":%.6g,\"coordination_number\":%.4f,"
              "\"idle_mass_fraction\":%.4f,\"ufr\":%.4g,\"stress_pa\":[%.6g,%.6g,%.6g],\"aspect\":[%.6f,%.6f,%.6f],"
              "\"max_overlap_ratio\":%.4g,\"dispersity_index\":%.6f,\"particles\":%ld,\"steps\":%lld,"
              "\"wall_seconds\":%.2f,\"out\":\"%s\"}\n",
              m.void_ratio, has_dr ? std::to_string(dr).c_str() : "null", mu1, m.coordination_number,
              m.idle_mass_fraction, m.ufr, m.stress(0, 0), m.stress(1, 1), m.stress(2, 2), r.aspect.x, r.aspect.y,
              r.aspect.z, m.max_overlap_ratio, delta, a.particles, static_cast<long long>(r.steps), r.wall_seconds,
              a.out.c_str());
  return 0;
}
