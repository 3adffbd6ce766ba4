// The four-bar linkage of examples/closed_loop (four_bar.hpp): the generated open chain closed
// by a loop constraint through a KKT solve, integrated by RK4 for 5 s at 1 ms with the crank
// turning 8 times. Checked against what does not come from the generated code: the closed-form
// loop closure (Freudenstein's equation), central differences of the constraint, and the
// physics (energy is conserved, the constraint does no work). The rollouts' bounds carry a
// factor of about 4 over the measured values, which a wrong term breaks by orders of magnitude.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "four_bar.hpp"
#include "test_support.hpp"

namespace {

using closed_loop::Loop;
using closed_loop::State;
using closed_loop::Window;

constexpr int seconds = 5;
using Windows = std::array<Window, seconds>;

Windows rollout(double h, closed_loop::Stabilisation s) {
  return closed_loop::rollout<seconds>(closed_loop::initial_state(), h, s, closed_loop::assembly);
}

double largest(const Windows& windows, double Window::*field) {
  double m = 0;
  for (const Window& w : windows) m = std::max(m, w.*field);
  return m;
}

TEST(ClosedLoop, ClosedFormStateClosesTheGeneratedLoop) {
  ASSERT_STREQ(four_bar::frame_names[closed_loop::tip], "tip");
  ASSERT_STREQ(four_bar::frame_names[closed_loop::ground_pivot], "ground_pivot");
  // Freudenstein's angles put the generated tip on the generated pivot: the URDF, the generated
  // kinematics and the closed form describe one linkage, to rounding (an ulp of 0.45 m is 6e-17)
  const State x = closed_loop::initial_state();
  const Loop loop = closed_loop::evaluate(x);
  EXPECT_LE(loop.phi.norm(), 1e-15);        // measured 7.9e-17 m
  EXPECT_LE((loop.J * x.v).norm(), 1e-14);  // measured 4.9e-17 m/s
  EXPECT_GT(loop.Jdot_v.norm(), 1.0);       // the tip's path is curved: Jdot_v matters
}

TEST(ClosedLoop, ConstraintRowsAreTheDerivativesOfThePositionError) {
  // J against central differences of phi, Jdot_v against those of J v along v (h = 1e-6: the
  // truncation error is h^2 times third derivatives of order 10, rounding 1e-16 / h)
  const State x = closed_loop::initial_state(0.7, 5.0);
  const Loop loop = closed_loop::evaluate(x);
  constexpr double h = 1e-6;
  for (int j = 0; j < closed_loop::nv; ++j) {
    State plus = x, minus = x;
    plus.q[j] += h, minus.q[j] -= h;
    const closed_loop::Vector2 column =
        (closed_loop::evaluate(plus).phi - closed_loop::evaluate(minus).phi) / (2 * h);
    EXPECT_LE((column - loop.J.col(j)).norm(), 1e-9) << "column " << j;  // measured 7e-11
  }
  State plus = x, minus = x;
  plus.q += h * x.v, minus.q -= h * x.v;
  const closed_loop::Vector2 rate =
      (closed_loop::evaluate(plus).J * x.v - closed_loop::evaluate(minus).J * x.v) / (2 * h);
  EXPECT_LE((rate - loop.Jdot_v).norm(), 1e-9 * loop.Jdot_v.norm());  // measured 1.6e-11
}

TEST(ClosedLoop, KktAccelerationsKeepTheTipOnThePivotAndDoNoWork) {
  const State x = closed_loop::initial_state(0.7, 5.0);
  const Loop loop = closed_loop::evaluate(x);
  const closed_loop::Vector tau(0.3, -0.2, 0.1);
  const closed_loop::Constrained c = closed_loop::constrained_acceleration(loop, x.v, tau, {});
  // the tip's acceleration J qdd + Jdot_v is zero (|Jdot_v| is 6 m/s^2)
  EXPECT_LE((loop.J * c.qdd + loop.Jdot_v).norm(), 1e-13);
  // Newton-Euler with the constraint force: M qdd + h = tau + J^T lambda
  EXPECT_LE((loop.M * c.qdd + loop.h - tau - loop.J.transpose() * c.lambda).norm(), 1e-13);
  // the constraint force does no work on a consistent velocity
  EXPECT_LE(std::abs(c.lambda.dot(loop.J * x.v)), 1e-13 * c.lambda.norm());
  EXPECT_GT(c.lambda.norm(), 1.0);  // and it is not zero: the loop holds the rocker up
}

TEST(ClosedLoop, StabilisedDriftStaysBounded) {
  // RK4 errs by O(h^5) a step; Baumgarte pulls the error back with a time constant of 50 ms,
  // so it settles where the two balance: flat from the first second to the last
  const Windows w = rollout(closed_loop::step, closed_loop::baumgarte);
  std::printf("[ measured ] stabilised: |phi| %.3e m, |J v| %.3e m/s\n",
              largest(w, &Window::position), largest(w, &Window::velocity));
  EXPECT_LE(largest(w, &Window::position), 5e-9);  // measured 1.2e-9 m
  EXPECT_LE(largest(w, &Window::velocity), 2e-7);  // measured 4.3e-8 m/s
  EXPECT_LE(w.back().position, 1.2 * w.front().position);
}

TEST(ClosedLoop, UnstabilisedDriftGrows) {
  // without stabilisation nothing pulls phi back to zero: phi'' = 0 integrates each step's error
  // in phi' into a drift that grows with time (about as t^2)
  const Windows free = rollout(closed_loop::step, {});
  const Windows held = rollout(closed_loop::step, closed_loop::baumgarte);
  std::printf(
      "[ measured ] unstabilised |phi|: %.3e m in the first second, %.3e m in the "
      "fifth\n",
      free.front().position, free.back().position);
  EXPECT_GE(free.back().position, 10 * free.front().position);              // measured 18 times
  EXPECT_GE(free.back().position, 300 * largest(held, &Window::position));  // measured 1070
  for (int k = 1; k < seconds; ++k) EXPECT_GT(free[k].position, free[k - 1].position) << k;
}

TEST(ClosedLoop, EnergyIsConservedToFourthOrder) {
  // tau = 0 and a workless constraint: the energy changes only by RK4's error, which falls by
  // 16 when the step halves; a wrong term of h or of lambda would change it at O(1)
  const double coarse =
      largest(rollout(closed_loop::step, closed_loop::baumgarte), &Window::energy);
  const double fine =
      largest(rollout(closed_loop::step / 2, closed_loop::baumgarte), &Window::energy);
  std::printf("[ measured ] energy drift %.3e J at h = 1 ms, %.3e J at 0.5 ms (ratio %.1f)\n",
              coarse, fine, coarse / fine);
  EXPECT_LE(coarse, 2e-6);  // measured 4.7e-7 J of 6.76 J
  EXPECT_GE(coarse / fine, 12.0);
  EXPECT_LE(coarse / fine, 20.0);  // measured 14.8
}

TEST(ClosedLoop, RockerFollowsFreudenstein) {
  // along the whole rollout (8 turns of the crank) the rocker's angle is the closed form's for
  // the crank's angle, to about the drift divided by the rocker's 0.4 m
  const Windows w = rollout(closed_loop::step, closed_loop::baumgarte);
  EXPECT_LE(largest(w, &Window::rocker), 2e-8);  // measured 4.0e-9 rad
}

TEST(ClosedLoop, RolloutAllocatesNothing) {
  const State x = closed_loop::initial_state();
  const dyngen::test::AllocationCounter counter;
  const auto w =
      closed_loop::rollout<1>(x, closed_loop::step, closed_loop::baumgarte, closed_loop::assembly);
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(w[0].position, 0.0);
}

}  // namespace
