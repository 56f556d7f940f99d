// Ownership and strain rates of the three cell axes of dem_node (DESIGN §6).
//
// An axis is either
//   open loop   - held at the rate set by set_strain_rate (0 by default), or
//   closed loop - owned by one controller (claim_axes), which sends a
//                 cell_command for it every control tick.
// Two owners of one axis are refused; release_axes gives axes back (open
// loop at rate 0). A claimed axis keeps its open-loop rate until the owner's
// first command (a controller takes over a moving axis without a jump; the
// rate controller's first tick runs at the rate the protocol node set). Rates are [1/s], COMPRESSION POSITIVE.
//
// Lockstep bookkeeping: the state of control tick k is answered by every
// owner that held its claim when tick k was published (claimed at a tick
// < k) with a command carrying tick k. missing_owners(k) lists those that
// have not answered yet; their axes keep the previous command (a timeout
// "holds the last command"). A command for another tick is refused in
// lockstep mode; in free-running mode the newest command (tick not older
// than the last accepted one, not in the future) is taken.
//
// ROS-free on purpose (no ROS headers), so it is unit-tested without a master
// (tests/rostest/unit_axis_arbiter.cpp). Every refusal is a string
// "<field>: <reason>" naming the request field; "" means accepted.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "virtual_triaxial/dem/vec3.h"

namespace vt::ros {

class AxisArbiter {
 public:
  /// Limit on |rate| as eps' = rate * t0 (eq. 31); t0 [s] > 0.
  void set_limit(double t0, double max_dimensionless_rate);
  double max_rate() const { return max_dimensionless_rate_ / t0_; }
  double max_dimensionless_rate() const { return max_dimensionless_rate_; }

  /// All-or-nothing claim at control tick `tick` (the last published tick).
  /// Empty `axes` registers `owner` as a lockstep participant without axes
  /// (it must answer every later tick; release with empty axes ends that).
  /// Claiming the same axes again changes nothing: the claim is idempotent,
  /// so a controller whose answer to a claim was lost may simply claim again.
  std::string claim(const std::string& owner, const std::vector<int>& axes, std::uint64_t tick);
  /// The tick after which `owner` answers (its claim's, or a later one's
  /// that added an axis); nullopt for an owner without a claim. This, not
  /// the current tick, is what claim_axes answers: a claim repeated after
  /// its first answer was lost (ros/ros_comm#1976) then tells the owner
  /// which ticks dem_node waits on it for.
  std::optional<std::uint64_t> claimed_at(const std::string& owner) const;
  /// The tick claim_axes answers for an accepted claim made at the last
  /// published tick `tick`: claimed_at(owner), never after `tick`.
  std::uint64_t answer_tick(const std::string& owner, std::uint64_t tick) const {
    return std::min(claimed_at(owner).value_or(tick), tick);
  }
  /// The published ticks start again after `tick` (a test resumed from a
  /// checkpoint): a claim that took effect after it now takes effect at it,
  /// so its owner is waited on from tick + 1.
  void rewind(std::uint64_t tick);
  /// Empty `axes`: every axis of `owner`.
  std::string release(const std::string& owner, const std::vector<int>& axes);
  /// Open-loop rate [1/s] of an axis nobody owns.
  std::string set_open_loop_rate(int axis, double rate);

  /// A cell_command. `current_tick` is the last published tick.
  std::string command(const std::string& owner, std::uint64_t tick, const std::vector<int>& axes,
                      const std::vector<double>& rates, std::uint64_t current_tick, bool lockstep);
  /// Owners that must answer tick `tick` and have not yet (sorted by name).
  std::vector<std::string> missing_owners(std::uint64_t tick) const;
  /// Zero every commanded rate (a new specimen was loaded); owners stay.
  void reset_commands();

  /// Rates to apply now [1/s], compression positive.
  dem::Vec3 rates() const;
  /// "" for an open-loop axis.
  const std::string& owner(int axis) const { return owner_[static_cast<std::size_t>(axis)]; }

  /// "axis: ..." unless 0 <= axis <= 2.
  static std::string check_axis(int axis, const char* field = "axis");
  /// "strain_rate: ..." unless finite and |rate t0| <= max (1e-9 relative slack).
  std::string check_rate(double rate, const char* field = "strain_rate") const;

 private:
  struct Owner {
    std::uint64_t claimed_at = 0;   ///< last published tick when the claim was made
    std::uint64_t answered = 0;     ///< tick of the last accepted command
    bool has_answered = false;
  };
  double t0_ = 1.0;
  double max_dimensionless_rate_ = 1e-3;
  std::array<std::string, 3> owner_;
  std::array<double, 3> open_rate_{0.0, 0.0, 0.0};
  std::array<double, 3> command_rate_{0.0, 0.0, 0.0};
  std::map<std::string, Owner> owners_;
};

}  // namespace vt::ros
