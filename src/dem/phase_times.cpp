#include "virtual_triaxial/dem/phase_times.h"

#include <algorithm>
#include <utility>

namespace vt::dem {

void PhaseTimes::ensure_threads(int threads) {
  if (threads > static_cast<int>(slots_.size())) slots_.resize(static_cast<std::size_t>(threads));
}

void PhaseTimes::reset() {
  for (Slot& slot : slots_) slot = Slot{};
  for (int r = 0; r < kRegionCount; ++r) regions_[r] = imbalance_[r] = overhead_[r] = 0.0;
}

double PhaseTimes::busy_of(const Slot& slot) {
  double sum = 0.0;
  for (const double s : slot.s) sum += s;
  return sum;
}

namespace {

/// The largest of the positive values `busy(slot)` over the slots (the
/// threads of the team) and their mean; {0, 0} without any.
template <class Slots, class Busy>
std::pair<double, double> most_and_mean(const Slots& slots, const Busy& busy) {
  double most = 0.0, sum = 0.0;
  int team = 0;
  for (const auto& slot : slots) {
    const double b = busy(slot);
    if (b <= 0.0) continue;  // not in the team
    most = std::max(most, b);
    sum += b;
    ++team;
  }
  return {most, team == 0 ? 0.0 : sum / team};
}

}  // namespace

void PhaseTimes::add_region(Region r, double seconds) {
  regions_[r] += seconds;
  for (Slot& slot : slots_) {
    const double now = busy_of(slot);
    slot.step = now - slot.mark;
    slot.mark = now;
    if (slot.step > 0.0) slot.region_busy[r] += slot.step;
  }
  const auto [most, mean] = most_and_mean(slots_, [](const Slot& slot) { return slot.step; });
  if (most <= 0.0) return;  // no team
  imbalance_[r] += most - mean;
  overhead_[r] += seconds - most;
}

double PhaseTimes::steady_imbalance(Region r) const {
  const auto [most, mean] = most_and_mean(slots_, [r](const Slot& slot) { return slot.region_busy[r]; });
  return most - mean;
}

double PhaseTimes::seconds(int t, Phase p) const {
  if (t < 0 || t >= threads()) return 0.0;
  return slots_[static_cast<std::size_t>(t)].s[p];
}

double PhaseTimes::busy(int t) const {
  return t < 0 || t >= threads() ? 0.0 : busy_of(slots_[static_cast<std::size_t>(t)]);
}

const char* PhaseTimes::name(Phase p) {
  switch (p) {
    case Prepare: return "prepare";
    case Pairs: return "pairs";
    case Integrate: return "integrate";
    case kPhaseCount: break;
  }
  return "?";
}

}  // namespace vt::dem
