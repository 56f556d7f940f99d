// Two timed cases in turn, a block of steps each (triax_bench --alternate
// and --pair-tile): a drift of the host's speed over seconds then hits both
// cases alike, which whole runs interleaved in rounds cannot ensure (on this
// 2-vCPU VM one thread's cost moves by +-25 % between runs seconds apart).
//
// Turn k runs `block` steps of its simulation on `threads` threads, then
// the other turn runs its block, and so on until turn 0 has taken `steps`
// steps (turn 1 takes its block as often; a last, shorter block of turn 0
// is followed by the same share of turn 1's). Per full pair of blocks the
// cost ratio
//   r = (t_0 / (N_0 k_0)) / (t_1 / (N_1 k_1))      (cost per particle-step)
// is kept; the summary is its median and quartiles over the pairs.
#pragma once

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <vector>

#include "virtual_triaxial/dem/simulation.h"

namespace vt::bench {

struct Turn {
  dem::Simulation* sim = nullptr;
  int threads = 1;
  long long block = 1;   ///< steps per turn
  double seconds = 0.0;  ///< summed over the turn's blocks
  long long steps = 0;   ///< summed over the turn's blocks
  double cost() const {  ///< [s per particle-step]
    return seconds / (static_cast<double>(sim->particles().size()) * static_cast<double>(steps));
  }
};

/// The turns as in the header; `fail(sim)` is called when a step fails
/// (it must not return). Returns the pairs' cost ratios r.
template <class Fail>
std::vector<double> run_turns(Turn (&turns)[2], long long steps, Fail fail) {
  using Clock = std::chrono::steady_clock;
  std::vector<double> ratios;
  for (long long done = 0; done < steps;) {
    const long long k0 = std::min(turns[0].block, steps - done);
    double cost[2];
    for (int t = 0; t < 2; ++t) {
      Turn& turn = turns[t];
      const long long k = t == 0 ? k0 : std::max(1LL, turn.block * k0 / turns[0].block);
      omp_set_num_threads(turn.threads);
      const auto t0 = Clock::now();
      for (long long s = 0; s < k; ++s)
        if (!turn.sim->step(false)) fail(*turn.sim);
      const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
      turn.seconds += seconds;
      turn.steps += k;
      cost[t] = seconds / (static_cast<double>(turn.sim->particles().size()) * static_cast<double>(k));
    }
    if (k0 == turns[0].block) ratios.push_back(cost[0] / cost[1]);
    done += k0;
  }
  return ratios;
}

}  // namespace vt::bench
