#include "support/state_compare.h"

#include <gtest/gtest.h>

namespace vt::test {

void expect_same_state(const dem::SimulationState& a, const dem::SimulationState& b) {
  EXPECT_TRUE(same_bits(a.particles.frac, b.particles.frac));
  EXPECT_TRUE(same_bits(a.particles.velocity, b.particles.velocity));
  EXPECT_TRUE(same_bits(a.particles.omega, b.particles.omega));
  EXPECT_TRUE(same_bits(a.particles.orientation, b.particles.orientation));
  ASSERT_EQ(a.contacts.size(), b.contacts.size());
  for (std::size_t k = 0; k < a.contacts.size(); ++k) {
    EXPECT_EQ(a.contacts[k].id_a, b.contacts[k].id_a);
    EXPECT_EQ(a.contacts[k].id_b, b.contacts[k].id_b);
    EXPECT_EQ(0, std::memcmp(&a.contacts[k].spring, &b.contacts[k].spring, sizeof(dem::Vec3)));
    EXPECT_EQ(a.contacts[k].cache.valid, b.contacts[k].cache.valid);
  }
  EXPECT_EQ(0, std::memcmp(&a.h, &b.h, sizeof(dem::Mat3)));
  EXPECT_EQ(a.step, b.step);
  EXPECT_EQ(0, std::memcmp(&a.time, &b.time, sizeof(double)));
  EXPECT_EQ(0, std::memcmp(&a.energy.boundary_work, &b.energy.boundary_work, sizeof(double)));
  EXPECT_EQ(0, std::memcmp(&a.energy.damping, &b.energy.damping, sizeof(double)));
  EXPECT_EQ(0, std::memcmp(&a.energy.friction, &b.energy.friction, sizeof(double)));
}

}  // namespace vt::test
