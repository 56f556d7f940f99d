#include "virtual_triaxial/dem/phase_times.h"

namespace vt::dem {

void PhaseTimes::ensure_threads(int threads) {
  if (threads > static_cast<int>(slots_.size())) slots_.resize(static_cast<std::size_t>(threads));
}

void PhaseTimes::reset() {
  for (Slot& slot : slots_) slot = Slot{};
  for (double& r : regions_) r = 0.0;
}

double PhaseTimes::seconds(int t, Phase p) const {
  if (t < 0 || t >= threads()) return 0.0;
  return slots_[static_cast<std::size_t>(t)].s[p];
}

double PhaseTimes::busy(int t) const {
  double sum = 0.0;
  for (int p = 0; p < kPhaseCount; ++p) sum += seconds(t, static_cast<Phase>(p));
  return sum;
}

const char* PhaseTimes::name(Phase p) {
  switch (p) {
    case Prepare: return "prepare";
    case Pairs: return "pairs";
    case Ghosts: return "ghosts";
    case Sums: return "sums";
    case Integrate: return "integrate";
    case kPhaseCount: break;
  }
  return "?";
}

}  // namespace vt::dem
