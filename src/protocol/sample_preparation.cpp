#include "virtual_triaxial/protocol/sample_preparation.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include "virtual_triaxial/control/servo_strategy.h"
#include "virtual_triaxial/dem/axis_stiffness.h"
#include "virtual_triaxial/dem/cloud_generator.h"
#include "virtual_triaxial/dem/spatial_sort.h"

namespace vt::protocol {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

dem::Vec3 normal_stress(const dem::Simulation& sim) {
  const dem::Mat3 s = sim.current_stress();
  return {s(0, 0), s(1, 1), s(2, 2)};
}

double max3(const dem::Vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

template <class... A>
std::string fmt(const char* f, A... a) {
  char buf[320];
  std::snprintf(buf, sizeof buf, f, a...);
  return buf;
}

class Preparer {
 public:
  Preparer(const PreparationSettings& s, const std::function<void(const std::string&)>& progress)
      : s_(s), progress_(progress) {}

  PreparationResult run() {
    const auto t0 = Clock::now();
    generate();
    if (shrink() && compress()) {
      result_.converged = true;
    } else {
      result_.state = sim_->state();  // the last state reached, for diagnosis
      if (sim_->step(true)) result_.final = sim_->measures();
    }
    const dem::Mat3& h = result_.state.h;
    result_.aspect = {h(0, 0) / h(0, 0), h(1, 1) / h(0, 0), h(2, 2) / h(0, 0)};
    result_.aspect = s_.aspect.x * result_.aspect;
    result_.wall_seconds = since(t0);
    return result_;
  }

 private:
  void say(const std::string& line) {
    if (progress_) progress_(line);
  }

  void generate() {
    const auto t = Clock::now();
    dem::CloudRequest req;
    req.radii = s_.radii;
    req.aspect_ratios = s_.aspect_ratios;
    req.density = s_.material.density;
    req.aspect = s_.aspect;
    req.void_ratio = s_.initial_void_ratio;
    req.seed = s_.seed;
    dem::Cloud cloud = dem::generate_cloud(req);
    // a new specimen: above 1536 particles in slab order (dem/spatial_sort.h),
    // before the first step, so the criteria are judged on the state saved
    dem::order_new_specimen(cloud.particles, cloud.cell);
    dem::SimulationSettings ss;
    ss.material = s_.material;
    ss.material.friction = s_.mu1;
    ss.damping = s_.damping;
    ss.time_step_ratio = s_.time_step_ratio;
    sim_ = std::make_unique<dem::Simulation>(std::move(cloud.particles), cloud.cell, ss);
    const double e = sim_->cell().volume() / sim_->particles().solid_volume() - 1.0;
    result_.phases.push_back({"generation", 0, 0, since(t)});
    say(fmt("[generation] %zu particles, box grown %d times, void ratio %.3f (%.2f s)", s_.radii.size(),
            cloud.box_growths, e, since(t)));
  }

  bool run_steps(std::int64_t n, PhaseReport& ph) {
    for (std::int64_t k = 0; k < n; ++k) {
      if (!sim_->step()) {
        result_.failure = ph.name + ": numerical failure: " + sim_->failure();
        return false;
      }
      ++ph.steps;
      ++result_.steps;
    }
    return true;
  }

  void restore(const dem::SimulationState& st) { sim_ = std::make_unique<dem::Simulation>(st); }

  bool shrink() {
    PhaseReport ph{"shrinkage", 0, 0, 0};
    const auto t = Clock::now();
    double rate = s_.shrink_rate;
    dem::SimulationState good = sim_->state();
    bool done = false;
    for (; ph.cycles < s_.max_cycles && !done; ++ph.cycles) {
      const double r = rate / sim_->time_scale().t0;
      sim_->set_strain_rates({-r, -r, -r});
      // A numerical failure while shrinking (an overlap beyond the limit at a
      // high target pressure and a fast rate) is an overshoot too: restore
      // and halve, like a stress above the target.
      bool failed = !run_steps(s_.shrink_steps, ph);
      if (!failed) {
        sim_->set_strain_rates({});
        failed = !run_steps(s_.balance_steps, ph);
      }
      if (failed && rate <= s_.shrink_rate_min) return false;
      if (failed) result_.failure.clear();
      const dem::Vec3 st = failed ? dem::Vec3{INFINITY, INFINITY, INFINITY} : normal_stress(*sim_);
      if (max3(st) > s_.pressure) {
        restore(good);
        if (rate <= s_.shrink_rate_min) {
          done = true;
          say(fmt("[shrinkage] overshoot at the minimum rate eps' = %.3g after %lld cycles: restored",
                  rate, static_cast<long long>(ph.cycles + 1)));
        } else {
          rate = std::max(0.5 * rate, s_.shrink_rate_min);
          say(fmt("[shrinkage] %s: restored, eps' halved to %.3g (e %.4f)",
                  failed ? "numerical failure" : fmt("stress %.1f kPa over the target", max3(st) / 1e3).c_str(), rate,
                  sim_->cell().volume() / sim_->particles().solid_volume() - 1.0));
        }
      } else {
        good = sim_->state();
      }
    }
    ph.seconds = since(t);
    result_.phases.push_back(ph);
    if (!done) {
      result_.failure = "shrinkage: no overshoot at the minimum rate within max_cycles";
      return false;
    }
    return true;
  }

  bool compress() {
    PhaseReport ph{"compression", 0, 0, 0};
    const auto t = Clock::now();
    sim_->set_friction(s_.material.friction);
    control::ServoParameters sp;
    sp.gain = s_.servo_gain;
    sp.max_strain_rate = s_.servo_max_rate / sim_->time_scale().t0;
    std::unique_ptr<control::ServoStrategy> servo = control::make_servo("proportional", sp);
    servo->init({s_.pressure, s_.pressure, s_.pressure}, control::AxisMask{});
    servo->start(sim_->time());
    for (; ph.cycles < s_.max_cycles; ++ph.cycles) {
      dem::Vec3 stiff = dem::axis_stiffness(*sim_);
      for (std::int64_t k = 0; k < s_.servo_steps; ++k) {
        if (k % 10 == 0) stiff = dem::axis_stiffness(*sim_);
        const control::ServoOutput out = servo->update({sim_->time(), sim_->dt(), normal_stress(*sim_), stiff});
        sim_->set_strain_rates(-1.0 * out.strain_rate);  // compression positive -> cell convention
        if (!run_steps(1, ph)) return false;
      }
      sim_->set_strain_rates({});
      if (!run_steps(s_.balance_steps, ph)) return false;
      // The criteria are judged on the first force evaluation of exactly the
      // state that would be saved.
      dem::SimulationState candidate = sim_->state();
      if (!sim_->step(true)) {
        result_.failure = "compression: numerical failure: " + sim_->failure();
        return false;
      }
      ++ph.steps;
      ++result_.steps;
      const dem::Measures m = sim_->measures();
      const dem::Vec3 st{m.stress(0, 0), m.stress(1, 1), m.stress(2, 2)};
      // Chapter 4 checks equilibrium with eq. 54: the ratio of mean squared
      // out-of-balance force to mean squared contact force, i.e. I_uf^2 (eq. 65).
      const double ufr54 = m.iuf * m.iuf;
      const bool ok = servo->within(st, s_.tolerance) && ufr54 < s_.ufr_threshold;
      if (ph.cycles % 10 == 0 || ok)
        say(fmt("[compression] cycle %lld: stresses %.2f %.2f %.2f kPa, UFR(eq. 54) %.2e, e %.4f, Z %.2f",
                static_cast<long long>(ph.cycles), st.x / 1e3, st.y / 1e3, st.z / 1e3, ufr54, m.void_ratio,
                m.coordination_number));
      if (ok) {
        servo->stop();
        result_.state = std::move(candidate);
        result_.final = m;
        ph.seconds = since(t);
        result_.phases.push_back(ph);
        return true;
      }
    }
    ph.seconds = since(t);
    result_.phases.push_back(ph);
    result_.failure = "compression: stresses or UFR not within tolerance after max_cycles";
    return false;
  }

  const PreparationSettings& s_;
  std::function<void(const std::string&)> progress_;
  std::unique_ptr<dem::Simulation> sim_;
  PreparationResult result_;
};

}  // namespace

std::string PreparationSettings::validate() const {
  if (radii.empty()) return "psd: no particles (empty size distribution)";
  if (radii.size() < 2) return "particles: at least 2 particles are needed";
  for (double r : radii)
    if (!(r > 0.0 && std::isfinite(r))) return "psd: radii must be finite and > 0";
  if (!aspect_ratios.empty() && aspect_ratios.size() != radii.size())
    return "aspect_ratios: one per particle or none";
  for (double k : aspect_ratios)
    if (!(k >= 1.0 && std::isfinite(k))) return "aspect_ratios: must be >= 1 (prolate spheroids; 1 = sphere)";
  const std::string m = material.validate();
  if (!m.empty()) return "material." + m;
  if (!(pressure > 0.0 && std::isfinite(pressure))) return "pressure: must be a finite number > 0 Pa";
  if (!(mu1 >= 0.0 && std::isfinite(mu1))) return "mu1: must be a finite number >= 0";
  for (int a = 0; a < 3; ++a)
    if (!(aspect[a] > 0.0 && std::isfinite(aspect[a]))) return "aspect: every ratio must be > 0";
  if (!(initial_void_ratio > 0.0)) return "initial_void_ratio: must be > 0";
  if (!(time_step_ratio > 0.0 && time_step_ratio < 1.0)) return "time_step_ratio: must lie in (0, 1)";
  if (!(shrink_rate > 0.0 && shrink_rate_min > 0.0 && shrink_rate_min <= shrink_rate))
    return "shrink_rate: need 0 < shrink_rate_min <= shrink_rate";
  if (!(tolerance > 0.0)) return "tolerance: must be > 0";
  if (!(ufr_threshold > 0.0)) return "ufr_threshold: must be > 0";
  if (shrink_steps <= 0 || balance_steps <= 0 || servo_steps <= 0 || max_cycles <= 0)
    return "cycle counts: shrink_steps, balance_steps, servo_steps and max_cycles must be > 0";
  return {};
}

PreparationResult prepare_sample(const PreparationSettings& s, const std::function<void(const std::string&)>& progress) {
  const std::string bad = s.validate();
  if (!bad.empty()) throw std::invalid_argument(bad);
  return Preparer(s, progress).run();
}

}  // namespace vt::protocol
