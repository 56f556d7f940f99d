#include "virtual_triaxial/io/results_recorder.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "virtual_triaxial/io/sample_file.h"

namespace vt::io {

ResultsRecorder::ResultsRecorder(const std::string& path, bool quiet, double flush_seconds)
    : writer_(path), quiet_(quiet), flush_seconds_(flush_seconds), last_flush_(std::chrono::steady_clock::now()) {
  writer_.set_summary({}, {{"verdict", "interrupted"},
                           {"failure", "the run stopped before it finished: the series as of the last flush"}});
}

void ResultsRecorder::resume(std::size_t rows) {
  std::vector<dem::Measures> series = read_results_series(writer_.path(), writer_.group());
  if (series.size() < rows)
    throw std::runtime_error(writer_.path() + ": holds " + std::to_string(series.size()) +
                             " samples, fewer than the checkpoint's " + std::to_string(rows));
  series.resize(rows);
  writer_.restore_series(std::move(series));
}

void ResultsRecorder::flush_partial(const std::string& note) {
  writer_.set_summary({}, {{"verdict", "interrupted"}, {"failure", note}});
  writer_.flush();
  last_flush_ = std::chrono::steady_clock::now();
  if (after_flush_) after_flush_(writer_.size(), stage_);
}

void ResultsRecorder::on_stage_start(const protocol::StageSpec& st, const dem::Simulation& sim) {
  if (quiet_) return;
  if (st.rate_spec.strategy != control::RateStrategyKind::Fixed) {
    std::fprintf(stderr, "[%s] start: %s, strain rate by the %s rate strategy\n", st.name.c_str(),
                 protocol::to_string(st.type), control::to_string(st.rate_spec.strategy));
    return;
  }
  const double rate = st.strain_rate ? *st.strain_rate
                                     : (st.strain_rate_dimensionless ? *st.strain_rate_dimensionless / sim.time_scale().t0 : 0.0);
  std::fprintf(stderr, "[%s] start: %s, strain rate %.4g 1/s (eps' = %.3g)\n", st.name.c_str(),
               protocol::to_string(st.type), rate, rate * sim.time_scale().t0);
}

void ResultsRecorder::on_sample(const protocol::StageSpec& st, const dem::Measures& m) {
  writer_.append(m);
  const auto now = std::chrono::steady_clock::now();
  const bool new_stage = st.name != stage_;
  stage_ = st.name;
  if (new_stage || std::chrono::duration<double>(now - last_flush_).count() >= flush_seconds_) {
    writer_.flush();
    last_flush_ = now;
    if (after_flush_) after_flush_(writer_.size(), stage_);
  }
}

void ResultsRecorder::on_progress(const std::string& line) {
  if (!quiet_) std::fprintf(stderr, "%s\n", line.c_str());
}

void ResultsRecorder::finish(const protocol::RunReport& r, const dem::Simulation& sim) {
  finish(r, run_context(sim));
}

void ResultsRecorder::finish(const protocol::RunReport& r, const RunContext& ctx) {
  std::map<std::string, double> num;
  std::map<std::string, std::string> txt;
  txt["verdict"] = protocol::to_string(r.verdict);
  txt["failure"] = r.failure;
  num["steps"] = static_cast<double>(r.steps);
  num["wall_seconds"] = r.wall_seconds;
  num["ticks"] = static_cast<double>(r.ticks);
  num["particles"] = static_cast<double>(ctx.particles);
  num["t0_s"] = ctx.t0;
  num["dt_s"] = ctx.dt;
  num["l0_m"] = ctx.l0;
  if (r.shear.has_data) {
    num["e0"] = r.shear.e0;
    num["phi_peak_rad"] = r.shear.phi_peak;
    num["eps_peak"] = r.shear.eps_peak;
    num["q_peak_pa"] = r.shear.q_peak;
    num["phi_end_rad"] = r.shear.phi_end;
    num["p_end_pa"] = r.shear.p_end;
    num["q_end_pa"] = r.shear.q_end;
    num["mean_moment_index_to_peak"] = r.shear.mean_moment_index_to_peak;
    num["max_moment_index_to_peak"] = r.shear.max_moment_index_to_peak;
    txt["rate_strategy"] = r.shear.rate_strategy;
    num["strain_rate_dimensionless_min"] = r.shear.strain_rate_min;
    num["strain_rate_dimensionless_max"] = r.shear.strain_rate_max;
    num["quasi_static_threshold"] = r.shear.quasi_static_threshold;
    txt["quasi_static"] = r.shear.quasi_static ? "yes" : "no";
    txt["phi_peak_basis"] = protocol::phi_peak_basis(r.shear);
  }
  num["energy_relative_balance_error"] = ctx.energy_relative_balance_error;
  if (ctx.spheroid_contact_solves > 0) {
    num["spheroid_contact_solves"] = static_cast<double>(ctx.spheroid_contact_solves);
    num["spheroid_contact_fallbacks"] = static_cast<double>(ctx.spheroid_contact_fallbacks);
    num["spheroid_contact_failures"] = static_cast<double>(ctx.spheroid_contact_failures);
  }
  if (!r.stages.empty()) {
    std::string names, reasons;
    for (const protocol::StageOutcome& s : r.stages) {
      names += (names.empty() ? "" : "; ") + s.name;
      reasons += (reasons.empty() ? "" : "; ") + s.name + ": " + s.stop_reason;
    }
    txt["stages"] = names;
    txt["stop_reasons"] = reasons;
  }
  writer_.set_summary(num, txt);
  writer_.flush();
}

void ResultsRecorder::save_sample(const std::string& path, const dem::SimulationState& s,
                                  const SceneConfig& scene) const {
  SampleMetadata meta;
  meta.seed = scene.distribution.seed;
  meta.friction_during_shrinkage = NAN;
  meta.target_pressure = NAN;
  meta.initial_void_ratio = NAN;
  meta.software_version = "virtual_triaxial 0.1.0";
  meta.created_by = "triax_run " + scene.source_path;
  meta.description = "state saved by triax_run";
  write_sample(path, s, meta);
}

}  // namespace vt::io
