// Finding the shrinkage friction mu1 that gives a requested void ratio.
//
// The void ratio of a prepared sample rises monotonically with the friction
// used during shrinkage (fig. 11, table 49), between the densest sample
// (mu1 = 0) and the loosest (mu1 = mu1_max = 0.5, the final friction; 4.3.1).
// Bisection on mu1: first both ends are prepared; a target outside
// [e(0) - tol, e(mu1_max) + tol] is out of reach and reported with the range;
// otherwise the bracket is halved until |e - target| <= tol.
#pragma once

#include <functional>
#include <string>

#include "virtual_triaxial/protocol/sample_preparation.h"

namespace vt::protocol {

struct VoidRatioSearch {
  bool reachable = false;
  std::string message;          ///< why not, when not reachable
  double mu1 = 0;
  int preparations = 0;
  PreparationResult result;     ///< the sample with |e - target| <= tol
};

VoidRatioSearch find_mu1_for_void_ratio(PreparationSettings s, double target, double tol,
                                        const std::function<void(const std::string&)>& progress = {},
                                        double mu1_max = 0.5, int max_iterations = 14);

}  // namespace vt::protocol
