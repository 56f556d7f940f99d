#include "virtual_triaxial/dem/phase_times.h"

#include <algorithm>

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

void PhaseTimes::add_region(Region r, double seconds) {
  regions_[r] += seconds;
  double most = 0.0, sum = 0.0;
  int team = 0;
  for (Slot& slot : slots_) {
    const double now = busy_of(slot);
    const double step = now - slot.mark;
    slot.mark = now;
    if (step <= 0.0) continue;  // not in this team
    slot.region_busy[r] += step;
    most = std::max(most, step);
    sum += step;
    ++team;
  }
  if (team == 0) return;
  imbalance_[r] += most - sum / team;
  overhead_[r] += seconds - most;
}

double PhaseTimes::steady_imbalance(Region r) const {
  double most = 0.0, sum = 0.0;
  int team = 0;
  for (const Slot& slot : slots_) {
    if (slot.region_busy[r] <= 0.0) continue;
    most = std::max(most, slot.region_busy[r]);
    sum += slot.region_busy[r];
    ++team;
  }
  return team == 0 ? 0.0 : most - sum / team;
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
    case Sums: return "sums";
    case Integrate: return "integrate";
    case kPhaseCount: break;
  }
  return "?";
}

}  // namespace vt::dem
