// Two timed cases in turn, a block of steps each (triax_bench --alternate
// and --pair-tile): a drift of the host's speed over seconds then hits both
// cases alike, which whole runs interleaved in rounds cannot ensure (on this
// 2-vCPU VM one thread's cost moves by +-25 % between runs seconds apart).
//
// Pair p of turns runs `block` steps of each turn's simulation on its
// `threads` threads, turn 0 first in even pairs and turn 1 first in odd
// ones (A B, B A, A B, ...: the one that goes second in a pair meets a
// state sheared further and caches the other turn left, so the order
// alternates), until each turn has taken `steps` steps (a last, shorter
// pair takes what is left). Per full pair the cost ratio
//   r = cost_0 / cost_1,  cost = t / (N k)        [s per particle-step]
// is kept; the summary is its median and quartiles over the pairs.
#pragma once

#include <omp.h>

#include <algorithm>
#include <vector>

#include "virtual_triaxial/dem/simulation.h"
#include "wall_clock.h"

namespace vt::bench {

/// Cost per particle-step of k steps of n particles in `seconds` [s].
inline double particle_step_cost(double seconds, std::size_t n, long long k) {
  return seconds / (static_cast<double>(n) * static_cast<double>(k));
}

struct Turn {
  dem::Simulation* sim = nullptr;
  int threads = 1;
  double seconds = 0.0;  ///< summed over the turn's blocks
  long long steps = 0;   ///< summed over the turn's blocks
  double cost() const { return particle_step_cost(seconds, sim->particles().size(), steps); }
};

/// The turns as in the header; `fail(sim)` is called when a step fails
/// (it must not return). Returns the full pairs' cost ratios r.
template <class Fail>
std::vector<double> run_turns(Turn (&turns)[2], long long steps, long long block, Fail fail) {
  std::vector<double> ratios;
  for (long long done = 0, pair = 0; done < steps; ++pair) {
    const long long k = std::min(block, steps - done);
    double cost[2];
    for (int order = 0; order < 2; ++order) {
      const int t = pair % 2 == 0 ? order : 1 - order;
      Turn& turn = turns[t];
      omp_set_num_threads(turn.threads);
      const WallClock::time_point t0 = WallClock::now();
      for (long long s = 0; s < k; ++s)
        if (!turn.sim->step(false)) fail(*turn.sim);
      const double seconds = seconds_since(t0);
      turn.seconds += seconds;
      turn.steps += k;
      cost[t] = particle_step_cost(seconds, turn.sim->particles().size(), k);
    }
    if (k == block) ratios.push_back(cost[0] / cost[1]);
    done += k;
  }
  return ratios;
}

}  // namespace vt::bench
