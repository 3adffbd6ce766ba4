// Torque-free RK4 rollouts of generated ABA (examples/rollout/rk4.hpp): the energy of a 7-DoF
// arm under gravity, and the energy and spatial momentum of a floating quadruped in zero
// gravity, must be conserved up to the integrator's error, which shrinks as h^4. Over 1 s,
// steps of 8, 4 and 2 ms: each halving must divide the largest drift by 12 to 20 (an order of
// 3.6 to 4.3; measured 15.7 to 16.2), and the 2 ms drift must stay below a bound with a
// factor of 4 over the measured value. A wrong term in ABA would break conservation at O(1).
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "iiwa14_double_dynamics.hpp"
#include "iiwa14_double_model.hpp"
#include "rk4.hpp"
#include "solo12_free_double_dynamics.hpp"
#include "solo12_free_double_model.hpp"

namespace {

constexpr double steps_s[] = {8e-3, 4e-3, 2e-3};

std::vector<rollout::Drift> drifts(const rollout::System& system) {
  std::vector<rollout::Drift> out;
  for (const double h : steps_s)
    out.push_back(rollout::rollout(system, rollout::initial_state(system.model), h,
                                   static_cast<int>(std::lround(1.0 / h))));
  return out;
}

void expect_fourth_order(const std::vector<double>& drift, const char* what) {
  for (std::size_t k = 0; k + 1 < drift.size(); ++k) {
    const double ratio = drift[k] / drift[k + 1];
    std::printf("[ measured ] %s drift %.3e at h = %g s, ratio to h/2: %.2f\n", what, drift[k],
                steps_s[k], ratio);
    EXPECT_GE(ratio, 12.0) << what << " at h = " << steps_s[k];
    EXPECT_LE(ratio, 20.0) << what << " at h = " << steps_s[k];
  }
}

TEST(Rollout, ArmUnderGravityConservesEnergyToFourthOrder) {
  const rollout::System arm{iiwa14_double::runtime_model(), iiwa14_double::aba};
  const std::vector<rollout::Drift> d = drifts(arm);
  std::vector<double> energy;
  for (const rollout::Drift& x : d) energy.push_back(x.energy);
  expect_fourth_order(energy, "iiwa14 energy (J)");
  EXPECT_LE(energy.back(), 6e-5);  // measured 1.5e-5 J
}

TEST(Rollout, FreeFloatingQuadrupedConservesEnergyAndMomentumToFourthOrder) {
  const rollout::System solo{solo12_free_double::runtime_model(), solo12_free_double::aba};
  ASSERT_EQ(solo.model.joint_type[0], dyngen::JointType::Free);
  const std::vector<rollout::Drift> d = drifts(solo);
  std::vector<double> energy, momentum;
  for (const rollout::Drift& x : d) energy.push_back(x.energy), momentum.push_back(x.momentum);
  expect_fourth_order(energy, "solo12 energy (J)");
  expect_fourth_order(momentum, "solo12 momentum");
  EXPECT_LE(energy.back(), 3.2e-12);    // measured 7.8e-13 J
  EXPECT_LE(momentum.back(), 2.8e-11);  // measured 6.9e-12
}

}  // namespace
