// Snapshots of a running simulation into a state kept from before
// (Simulation::state_into, what the stage runner does at every good
// sample): bit for bit the fresh state(), whether the reused state held
// more contacts or fewer, and with the contacts left in list order until
// sort_histories orders them as state() does. Spatially sorted packings
// (storage order != id order), so list order is not the histories' order.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <utility>
#include <vector>

#include "support/scenes.h"
#include "support/spheroid_scenes.h"
#include "support/state_compare.h"
#include "virtual_triaxial/dem/simulation.h"

using namespace vt::dem;

namespace {

/// Whether the histories are ordered by (id_a, id_b) with no key twice.
bool ordered(const std::vector<ContactHistory>& h) {
  for (std::size_t k = 1; k < h.size(); ++k) {
    const auto a = std::make_pair(h[k - 1].id_a, h[k - 1].id_b), b = std::make_pair(h[k].id_a, h[k].id_b);
    if (!(a < b)) return false;
  }
  return true;
}

/// Runs `sim` and checks snapshots into one reused state against fresh ones.
void check_reused_snapshots(Simulation& sim) {
  SimulationState kept = sim.state();
  const std::size_t first_contacts = kept.contacts.size();
  bool fewer = false, more = false;
  for (int round = 0; round < 6; ++round) {
    for (int s = 0; s < 40; ++s) ASSERT_TRUE(sim.step(false));
    const SimulationState fresh = sim.state();
    fewer = fewer || fresh.contacts.size() < kept.contacts.size();
    more = more || fresh.contacts.size() > kept.contacts.size();
    sim.state_into(kept);
    ASSERT_TRUE(ordered(kept.contacts));
    vt::test::expect_same_state(fresh, kept);
    // list order, then sorted: the same histories
    SimulationState unsorted = fresh;
    sim.state_into(unsorted, false);
    ASSERT_EQ(unsorted.contacts.size(), fresh.contacts.size());
    sort_histories(unsorted.contacts);
    vt::test::expect_same_state(fresh, unsorted);
  }
  EXPECT_GT(first_contacts, 0u);
  std::printf("snapshots: %zu contacts at first; the reused state held fewer before %s, more before %s\n",
              first_contacts, more ? "yes" : "no", fewer ? "yes" : "no");
}

}  // namespace

TEST(StateSnapshot, IntoAReusedStateEqualsAFreshOneForSpheres) {
  Simulation sim(vt::test::spatially_sorted(vt::test::loaded_packing(400)));
  // list order is not id order here (else the unsorted case would prove nothing)
  sim.step(false);
  SimulationState unsorted = sim.state();
  sim.state_into(unsorted, false);
  ASSERT_FALSE(ordered(unsorted.contacts)) << "the packing's list order happens to be id order";
  check_reused_snapshots(sim);
}

TEST(StateSnapshot, IntoAReusedStateEqualsAFreshOneForSpheroids) {
  Simulation sim(vt::test::spatially_sorted(vt::test::loaded_spheroid_packing()));
  check_reused_snapshots(sim);
}
