// The four-bar linkage of examples/closed_loop (four_bar.hpp): the generated contact_dynamics of
// a chain spec's loop closure, integrated by RK4 for 5 s at 1 ms with the crank turning 8 times,
// with and without Baumgarte stabilisation. Checked against what does not come from
// contact_dynamics: the closed-form loop closure (Freudenstein's equation), the tip's
// acceleration by central differences of its position along the motion, the open chain's
// generated M, h and frame Jacobians, and the physics (energy is conserved, the loop does no
// work). The rollouts' bounds carry a factor of about 4 over the measured values, which a wrong
// term breaks by orders of magnitude.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "four_bar.hpp"
#include "test_support.hpp"

namespace {

using closed_loop::Loop;
using closed_loop::State;
using closed_loop::Vector;
using closed_loop::Vector2;
using closed_loop::Window;

constexpr int seconds = 5;
using Windows = std::array<Window, seconds>;

Windows rollout(closed_loop::ContactDynamics f, double h) {
  return closed_loop::rollout<seconds>(f, closed_loop::initial_state(), h, closed_loop::assembly);
}

double largest(const Windows& windows, double Window::*field) {
  double m = 0;
  for (const Window& w : windows) m = std::max(m, w.*field);
  return m;
}

TEST(ClosedLoop, ClosedFormStateClosesTheGeneratedLoop) {
  ASSERT_STREQ(four_bar::constraint_names[0], "rocker-base:3d");
  // Freudenstein's angles put the generated tip on the ground pivot: the chain spec, the
  // generated kinematics and the closed form describe one linkage, to rounding
  const State x = closed_loop::initial_state();
  const Loop loop = closed_loop::evaluate(x);
  EXPECT_LE(loop.phi.norm(), 1e-15);
  EXPECT_LE((loop.J * x.v).norm(), 1e-14);
}

/// The tip's acceleration along the motion through x with accelerations qdd: the second
/// central difference of its position along q(t) = q + v t + qdd t^2 / 2 (h = 1e-4: truncation
/// h^2 times fourth derivatives of order 100, rounding 1e-16 m / h^2).
Vector2 tip_acceleration(const State& x, const Vector& qdd) {
  constexpr double h = 1e-4;
  State plus = x, minus = x;
  plus.q += h * x.v + h * h / 2 * qdd;
  minus.q += -h * x.v + h * h / 2 * qdd;
  return (closed_loop::evaluate(plus).phi - 2 * closed_loop::evaluate(x).phi +
          closed_loop::evaluate(minus).phi) /
         (h * h);
}

TEST(ClosedLoop, ContactDynamicsKeepsTheTipOnThePivotAndDoesNoWork) {
  const State x = closed_loop::initial_state(0.7, 5.0);
  const Loop loop = closed_loop::evaluate(x);
  const Vector tau(0.3, -0.2, 0.1);
  for (const closed_loop::ContactDynamics f :
       {closed_loop::stabilised, closed_loop::unstabilised}) {
    const closed_loop::Constrained c = closed_loop::constrained_acceleration(f, x, tau);
    // the tip does not accelerate (on the loop, Baumgarte's terms are zero); free, it would
    // at several m/s^2
    EXPECT_LE(tip_acceleration(x, c.qdd).norm(), 1e-5);
    EXPECT_GE(tip_acceleration(x, Vector::Zero()).norm(), 1.0);
    // Newton-Euler with the loop's force at the tip: M qdd + h = tau + J^T lambda, with the
    // open chain's generated nle and the tip's Jacobian from the generated frame Jacobians
    Vector h;
    four_bar::nle(x.q.data(), x.v.data(), h.data());
    const Vector residual = loop.M * c.qdd + h - tau - loop.J.transpose() * c.lambda.head<2>();
    EXPECT_LE(residual.norm(), 1e-12 * (h.norm() + tau.norm()));
    EXPECT_EQ(c.lambda.z(), 0.0);  // the redundant row: the minimum-norm force has none
    // the loop's force does no work on a velocity that keeps it closed
    EXPECT_LE(std::abs(c.lambda.head<2>().dot(loop.J * x.v)), 1e-13 * c.lambda.norm());
    EXPECT_GT(c.lambda.norm(), 1.0);  // and it is not zero: the loop holds the rocker up
  }
}

TEST(ClosedLoop, StabilisedDriftStaysBounded) {
  // RK4 errs by O(h^5) a step; Baumgarte pulls the error back with a time constant of 50 ms,
  // so it settles where the two balance: flat from the first second to the last
  const Windows w = rollout(closed_loop::stabilised, closed_loop::step);
  std::printf("[ measured ] stabilised: |phi| %.3e m, |J v| %.3e m/s\n",
              largest(w, &Window::position), largest(w, &Window::velocity));
  EXPECT_LE(largest(w, &Window::position), 5e-9);
  EXPECT_LE(largest(w, &Window::velocity), 2e-7);
  EXPECT_LE(w.back().position, 1.2 * w.front().position);
}

TEST(ClosedLoop, UnstabilisedDriftGrows) {
  // without stabilisation nothing pulls phi back to zero: an acceleration-level constraint
  // integrates each step's error in phi' into a drift that grows with time (about as t^2)
  const Windows free = rollout(closed_loop::unstabilised, closed_loop::step);
  const Windows held = rollout(closed_loop::stabilised, closed_loop::step);
  std::printf(
      "[ measured ] unstabilised |phi|: %.3e m in the first second, %.3e m in the "
      "fifth\n",
      free.front().position, free.back().position);
  EXPECT_GE(free.back().position, 10 * free.front().position);
  EXPECT_GE(free.back().position, 300 * largest(held, &Window::position));
  for (int k = 1; k < seconds; ++k) EXPECT_GT(free[k].position, free[k - 1].position) << k;
}

TEST(ClosedLoop, EnergyIsConservedToFourthOrder) {
  // tau = 0 and a workless constraint: the energy changes only by RK4's error, which falls by
  // 16 when the step halves; a wrong term of h or of lambda would change it at O(1)
  const double coarse =
      largest(rollout(closed_loop::stabilised, closed_loop::step), &Window::energy);
  const double fine =
      largest(rollout(closed_loop::stabilised, closed_loop::step / 2), &Window::energy);
  std::printf("[ measured ] energy drift %.3e J at h = 1 ms, %.3e J at 0.5 ms (ratio %.1f)\n",
              coarse, fine, coarse / fine);
  EXPECT_LE(coarse, 2e-6);
  EXPECT_GE(coarse / fine, 12.0);
  EXPECT_LE(coarse / fine, 20.0);
}

TEST(ClosedLoop, RockerFollowsFreudenstein) {
  // along the whole rollout (8 turns of the crank) the rocker's angle is the closed form's for
  // the crank's angle, to about the drift divided by the rocker's 0.4 m
  const Windows w = rollout(closed_loop::stabilised, closed_loop::step);
  EXPECT_LE(largest(w, &Window::rocker), 2e-8);
}

TEST(ClosedLoop, RolloutAllocatesNothing) {
  const State x = closed_loop::initial_state();
  const dyngen::test::AllocationCounter counter;
  const auto w =
      closed_loop::rollout<1>(closed_loop::stabilised, x, closed_loop::step, closed_loop::assembly);
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(w[0].position, 0.0);
}

}  // namespace
