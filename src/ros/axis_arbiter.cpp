// AxisArbiter: axis ownership, open-loop rates and lockstep bookkeeping.
// See axis_arbiter.h.
#include "virtual_triaxial/ros/axis_arbiter.h"
#include "virtual_triaxial/io/number_text.h"
#include "virtual_triaxial/ros/rig_reply_words.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace vt::ros {

namespace {

std::string num(double v) { return io::number_text(v, 6); }

}  // namespace

void AxisArbiter::set_limit(double t0, double max_dimensionless_rate) {
  if (!(std::isfinite(t0) && t0 > 0.0)) throw std::invalid_argument("t0: must be finite and > 0");
  if (!(std::isfinite(max_dimensionless_rate) && max_dimensionless_rate > 0.0))
    throw std::invalid_argument("max_dimensionless_rate: must be finite and > 0");
  t0_ = t0;
  max_dimensionless_rate_ = max_dimensionless_rate;
}

std::string AxisArbiter::check_axis(int axis, const char* field) {
  if (axis < 0 || axis > 2)
    return std::string(field) + ": " + std::to_string(axis) + " is not a cell axis (0 = x, 1 = y, 2 = z)";
  return "";
}

std::string AxisArbiter::check_rate(double rate, const char* field) const {
  if (!std::isfinite(rate)) return std::string(field) + ": not a finite number (" + num(rate) + ")";
  const double eps = std::fabs(rate) * t0_;
  if (eps > max_dimensionless_rate_ * (1.0 + 1e-9))
    return std::string(field) + ": |eps'| = |rate| * T0 = " + num(eps) + " exceeds max_dimensionless_rate " +
           num(max_dimensionless_rate_) + " (|rate| <= " + num(max_rate()) + " 1/s)";
  return "";
}

std::string AxisArbiter::claim(const std::string& owner, const std::vector<int>& axes, std::uint64_t tick) {
  if (owner.empty()) return reply_words::owner_refusal("must not be empty");
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const int a = axes[k];
    std::string bad = check_axis(a, "axes");
    if (!bad.empty()) return bad;
    for (std::size_t j = 0; j < k; ++j)
      if (axes[j] == a) return "axes[" + std::to_string(k) + "]: axis " + std::to_string(a) + " is repeated";
    const std::string& cur = owner_[static_cast<std::size_t>(a)];
    if (!cur.empty() && cur != owner)
      return "axes: axis " + std::to_string(a) + " is owned by '" + cur + "'";
  }
  // A claim without axes registers a lockstep participant (e.g. the protocol
  // node): it owns no axis but must answer every tick after `tick`.
  auto it = owners_.find(owner);
  if (it == owners_.end()) it = owners_.emplace(owner, Owner{tick, 0, false}).first;
  for (int a : axes) {
    const auto i = static_cast<std::size_t>(a);
    if (owner_[i] == owner) continue;  // re-claim: keep its command
    owner_[i] = owner;
    command_rate_[i] = open_rate_[i];  // the axis keeps its motion until the owner's first command
    // A new axis joins at this tick: the owner answers from the next tick on.
    it->second.claimed_at = tick;
  }
  return "";
}

std::optional<std::uint64_t> AxisArbiter::claimed_at(const std::string& owner) const {
  const auto it = owners_.find(owner);
  if (it == owners_.end()) return std::nullopt;
  return it->second.claimed_at;
}

std::string AxisArbiter::release(const std::string& owner, const std::vector<int>& axes) {
  if (owner.empty()) return reply_words::owner_refusal("must not be empty");
  if (owners_.find(owner) == owners_.end()) return reply_words::owner_refusal("'" + owner + "' owns no axis");
  std::vector<int> list = axes;
  if (list.empty())
    for (int a = 0; a < 3; ++a)
      if (owner_[static_cast<std::size_t>(a)] == owner) list.push_back(a);
  for (int a : list) {
    std::string bad = check_axis(a, "axes");
    if (!bad.empty()) return bad;
    if (owner_[static_cast<std::size_t>(a)] != owner)
      return "axes: axis " + std::to_string(a) + " is not owned by '" + owner + "'";
  }
  for (int a : list) {
    const auto i = static_cast<std::size_t>(a);
    owner_[i].clear();
    command_rate_[i] = 0.0;
    open_rate_[i] = 0.0;
  }
  bool still = false;
  for (const std::string& o : owner_) still = still || o == owner;
  if (!still) owners_.erase(owner);
  return "";
}

std::string AxisArbiter::set_open_loop_rate(int axis, double rate) {
  std::string bad = check_axis(axis);
  if (!bad.empty()) return bad;
  bad = check_rate(rate);
  if (!bad.empty()) return bad;
  const std::string& cur = owner_[static_cast<std::size_t>(axis)];
  if (!cur.empty())
    return "axis: " + std::to_string(axis) + " is owned by the closed-loop controller '" + cur +
           "' (release_axes first)";
  open_rate_[static_cast<std::size_t>(axis)] = rate;
  return "";
}

std::string AxisArbiter::command(const std::string& owner, std::uint64_t tick, const std::vector<int>& axes,
                                 const std::vector<double>& rates, std::uint64_t current_tick, bool lockstep) {
  auto it = owners_.find(owner);
  if (it == owners_.end()) return reply_words::owner_refusal("'" + owner + "' owns no axis (claim_axes first)");
  if (axes.size() != rates.size())
    return "strain_rate: " + std::to_string(rates.size()) + " values for " + std::to_string(axes.size()) +
           " axes";
  if (lockstep && tick != current_tick)
    return "tick: " + std::to_string(tick) + " is not the current tick " + std::to_string(current_tick);
  if (!lockstep) {
    if (tick > current_tick)
      return "tick: " + std::to_string(tick) + " is in the future (current tick " +
             std::to_string(current_tick) + ")";
    if (it->second.has_answered && tick < it->second.answered)
      return "tick: " + std::to_string(tick) + " is older than the last command (" +
             std::to_string(it->second.answered) + ")";
  }
  for (std::size_t k = 0; k < axes.size(); ++k) {
    std::string bad = check_axis(axes[k], "axes");
    if (!bad.empty()) return bad;
    if (owner_[static_cast<std::size_t>(axes[k])] != owner)
      return "axes: axis " + std::to_string(axes[k]) + " is not owned by '" + owner + "'";
    bad = check_rate(rates[k]);
    if (!bad.empty()) return bad;
  }
  for (std::size_t k = 0; k < axes.size(); ++k) command_rate_[static_cast<std::size_t>(axes[k])] = rates[k];
  it->second.answered = tick;
  it->second.has_answered = true;
  return "";
}

std::vector<std::string> AxisArbiter::missing_owners(std::uint64_t tick) const {
  std::vector<std::string> out;
  for (const auto& [name, o] : owners_) {
    if (o.claimed_at >= tick) continue;  // claimed after tick `tick` was published
    if (!(o.has_answered && o.answered == tick)) out.push_back(name);
  }
  return out;
}

void AxisArbiter::rewind(std::uint64_t tick) {
  for (auto& [name, o] : owners_) {
    o.claimed_at = std::min(o.claimed_at, tick);
    if (o.has_answered && o.answered > tick) o.has_answered = false;
  }
}

void AxisArbiter::reset_commands() { command_rate_ = {0.0, 0.0, 0.0}; }

dem::Vec3 AxisArbiter::rates() const {
  dem::Vec3 r;
  for (int a = 0; a < 3; ++a) {
    const auto i = static_cast<std::size_t>(a);
    r[a] = owner_[i].empty() ? open_rate_[i] : command_rate_[i];
  }
  return r;
}

}  // namespace vt::ros
