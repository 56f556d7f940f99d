#include "virtual_triaxial/io/run_summary_json.h"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace vt::io {

namespace {

std::string quoted(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\', o += c;
    else if (static_cast<unsigned char>(c) < 0x20) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", c);
      o += b;
    } else o += c;
  }
  return o + "\"";
}

std::string number(double x) {
  if (!std::isfinite(x)) return "null";
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", x);
  return b;
}

}  // namespace

RunContext run_context(const dem::Simulation& sim) {
  RunContext c;
  c.particles = sim.particles().size();
  c.t0 = sim.time_scale().t0;
  c.dt = sim.dt();
  c.l0 = sim.time_scale().l0;
  c.energy_relative_balance_error = sim.energy().relative_balance_error();
  const dem::SpheroidContactStats& st = sim.spheroid_contact_stats();
  c.spheroid_contact_solves = static_cast<std::int64_t>(st.solves);
  c.spheroid_contact_fallbacks = static_cast<std::int64_t>(st.fallbacks);
  c.spheroid_contact_failures = static_cast<std::int64_t>(st.failures);
  return c;
}

std::string run_summary_json(const protocol::RunReport& r, const RunContext& ctx, const std::string& results) {
  std::ostringstream o;
  o << "{\"verdict\":" << quoted(protocol::to_string(r.verdict));
  if (!r.failure.empty()) o << ",\"failure\":" << quoted(r.failure);
  o << ",\"stages\":[";
  for (std::size_t i = 0; i < r.stages.size(); ++i) {
    const protocol::StageOutcome& s = r.stages[i];
    o << (i ? "," : "") << "{\"name\":" << quoted(s.name) << ",\"type\":" << quoted(protocol::to_string(s.type))
      << ",\"steps\":" << s.steps << ",\"stop\":" << quoted(s.stop_reason) << "}";
  }
  o << "],\"steps\":" << r.steps << ",\"ticks\":" << r.ticks << ",\"wall_seconds\":" << number(r.wall_seconds)
    << ",\"particles\":" << ctx.particles << ",\"t0_s\":" << number(ctx.t0) << ",\"dt_s\":" << number(ctx.dt);
  if (r.shear.has_data) {
    const double deg = 180.0 / M_PI;
    o << ",\"e0\":" << number(r.shear.e0) << ",\"phi_peak_deg\":" << number(r.shear.phi_peak * deg)
      << ",\"eps_peak\":" << number(r.shear.eps_peak) << ",\"q_peak_pa\":" << number(r.shear.q_peak)
      << ",\"phi_end_deg\":" << number(r.shear.phi_end * deg) << ",\"eps_end\":" << number(r.shear.eps_end)
      << ",\"p_end_pa\":" << number(r.shear.p_end) << ",\"q_end_pa\":" << number(r.shear.q_end)
      << ",\"mean_moment_index_to_peak\":" << number(r.shear.mean_moment_index_to_peak)
      << ",\"max_moment_index_to_peak\":" << number(r.shear.max_moment_index_to_peak)
      << ",\"rate_strategy\":" << quoted(r.shear.rate_strategy)
      << ",\"strain_rate_dimensionless_min\":" << number(r.shear.strain_rate_min)
      << ",\"strain_rate_dimensionless_max\":" << number(r.shear.strain_rate_max)
      << ",\"quasi_static_threshold\":" << number(r.shear.quasi_static_threshold)
      << ",\"quasi_static\":" << (r.shear.quasi_static ? "true" : "false")
      << ",\"phi_peak_basis\":" << quoted(protocol::phi_peak_basis(r.shear));
  }
  if (ctx.spheroid_contact_solves > 0)
    o << ",\"spheroid_contact_solves\":" << ctx.spheroid_contact_solves
      << ",\"spheroid_contact_fallbacks\":" << ctx.spheroid_contact_fallbacks
      << ",\"spheroid_contact_failures\":" << ctx.spheroid_contact_failures;
  if (ctx.lockstep_timeouts >= 0) o << ",\"lockstep_timeouts\":" << ctx.lockstep_timeouts;
  o << ",\"energy_relative_balance_error\":" << number(ctx.energy_relative_balance_error)
    << ",\"results\":" << quoted(results) << "}";
  return o.str();
}

std::string partial_summary_json(std::size_t samples, const std::string& stage, const std::string& results) {
  return "{\"verdict\":\"interrupted\",\"failure\":" +
         quoted("the test stopped after its last flush: " + std::to_string(samples) + " samples, stage '" + stage +
                "', in " + results) +
         ",\"partial\":true,\"samples\":" + std::to_string(samples) + ",\"stage\":" + quoted(stage) +
         ",\"results\":" + quoted(results) + "}";
}

}  // namespace vt::io
