// Torque-free rollouts of generated forward dynamics, integrated with RK4 (rk4.hpp): the
// iiwa14 arm falling under gravity, and the solo12 quadruped tumbling freely in zero gravity.
// Prints how far the energy (and for solo12 the momentum) drifts over one second for a few
// step sizes: RK4 is fourth order, so halving the step should divide the drift by about 16.
#include <cmath>
#include <cstdio>

#include "iiwa14_double_dynamics.hpp"
#include "iiwa14_double_model.hpp"
#include "rk4.hpp"
#include "solo12_free_double_dynamics.hpp"
#include "solo12_free_double_model.hpp"

namespace {

using rollout::initial_state;

void report(const char* name, const rollout::System& system, bool free_floating) {
  dyngen::Workspace<double> ws(system.model);
  const rollout::State x0 = initial_state(system.model);
  std::printf("%s: %d DoF, 1 s torque-free rollout, initial energy %.6g J\n", name,
              system.model.nv, rollout::invariants(system, ws, x0).energy);
  std::printf("  %10s %16s %18s\n", "step (s)", "energy drift (J)",
              free_floating ? "momentum drift" : "");
  for (const double h : {8e-3, 4e-3, 2e-3, 1e-3}) {
    const rollout::Drift d =
        rollout::rollout(system, x0, h, static_cast<int>(std::lround(1.0 / h)));
    if (free_floating) std::printf("  %10.4g %16.3e %18.3e\n", h, d.energy, d.momentum);
    else std::printf("  %10.4g %16.3e\n", h, d.energy);
  }
}

}  // namespace

int main() {
  report("iiwa14 under gravity", {iiwa14_double::runtime_model(), iiwa14_double::aba}, false);
  report("solo12 floating in zero gravity",
         {solo12_free_double::runtime_model(), solo12_free_double::aba}, true);
}
