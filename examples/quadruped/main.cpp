// The solo12 quadruped dropped 5 cm onto flat ground, caught by its feet and held standing for
// 10 s (quadruped.hpp), from one generated package. Prints each phase's numbers and, second by
// second, how far the feet drift from where they touched down; with a file name, also writes
// every step's drift and base height to it as CSV (plot.gp plots it).
//   quadruped_example [log.csv]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

#include "quadruped.hpp"

namespace {

constexpr int seconds = 10;
const char* const foot_names[] = {"FL", "FR", "HL", "HR"};

using Clock = std::chrono::steady_clock;

double microseconds_since(Clock::time_point start, int calls) {
  return std::chrono::duration<double, std::micro>(Clock::now() - start).count() / calls;
}

void report_touchdown(const quadruped::Drop& drop, const quadruped::Impact& impact) {
  std::printf("drop: %d feet reach the ground after %d steps (%.3f s) at %.4f m/s, %.2f mm deep\n",
              drop.feet_down, drop.steps, drop.steps * quadruped::step, -drop.touchdown.v[2],
              1e3 * drop.penetration);
  std::printf("touchdown (impulse_dynamics), base at %.4f m:\n", drop.touchdown.q[2]);
  std::printf("  foot speed %.3e -> %.3e m/s, base v_z %.4f -> %.4f m/s\n",
              impact.foot_speed_before, impact.foot_speed_after, drop.touchdown.v[2],
              impact.v_plus[2]);
  quadruped::Vector3 total = quadruped::Vector3::Zero();
  for (int i = 0; i < quadruped::nfeet; ++i) {
    const quadruped::Vector3& p = impact.impulse[i];
    std::printf("  %s impulse (%+.4f, %+.4f, %+.4f) N s\n", foot_names[i], p.x(), p.y(), p.z());
    total += p;
  }
  std::printf("  total vertical impulse %.4f N s (the robot's momentum m v_z was %.4f N s)\n",
              total.z(), -quadruped::total_mass * drop.touchdown.v[2]);
  const double lost = impact.energy_before - impact.energy_after;
  std::printf("  kinetic energy %.4f J -> %.4f J: %.4f J (%.1f%%) lost\n", impact.energy_before,
              impact.energy_after, lost, 100 * lost / impact.energy_before);
}

void report_standing(const std::array<quadruped::Second, seconds>& w) {
  std::printf("  %6s %11s %22s %12s %12s %16s\n", "second", "drift (mm)", "base height (m)",
              "|J v| (m/s)", "min f_z (N)", "max |tau| (N m)");
  for (int s = 0; s < seconds; ++s)
    std::printf("  %6d %11.4f %10.4f .. %-9.4f %12.3e %12.3f %16.3f%s\n", s + 1, 1e3 * w[s].drift,
                w[s].base_low, w[s].base_high, w[s].foot_speed, w[s].push, w[s].torque,
                w[s].push <= 0 ? "  a foot pulls" : "");
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

}  // namespace

int main(int argc, char** argv) {
  std::unique_ptr<std::FILE, FileCloser> csv;
  if (argc > 1 && !(csv.reset(std::fopen(argv[1], "w")), csv)) {
    std::perror(argv[1]);
    return 1;
  }
  const quadruped::State x0 = quadruped::initial_state();
  std::printf("solo12, %.4f kg, feet %.0f mm above the ground, step %g s\n", quadruped::total_mass,
              1e3 * quadruped::drop_height, quadruped::step);

  const quadruped::Drop drop = quadruped::drop(x0);
  const quadruped::Impact impact = quadruped::touchdown(drop.touchdown);
  report_touchdown(drop, impact);

  const quadruped::Controller controller = quadruped::standing_controller(drop.touchdown.q);
  std::printf(
      "standing: kp %g N m/rad, kd %g N m s/rad, Baumgarte kd %g /s; feed-forward's base "
      "residual %.2e\n",
      controller.gains.kp, controller.gains.kd, solo12_quadruped::model_constraint_settings.kd,
      controller.base_residual.norm());
  if (csv) std::fprintf(csv.get(), "time,drift_FL,drift_FR,drift_HL,drift_HR,base_height\n");
  const auto log = [&](const quadruped::Sample& s) {
    if (csv)
      std::fprintf(csv.get(), "%.3f,%.6e,%.6e,%.6e,%.6e,%.6f\n", s.time, s.drift[0], s.drift[1],
                   s.drift[2], s.drift[3], s.base_height);
  };
  const auto start = Clock::now();
  const auto w = quadruped::stand<seconds>({drop.touchdown.q, impact.v_plus}, drop.anchors,
                                           controller, log);
  const double per_step =
      microseconds_since(start, static_cast<int>(std::lround(seconds / quadruped::step)));
  report_standing(w);
  std::printf("  %.2f us a step (contact_dynamics, the feet's frames and Jacobians, integrate%s)\n",
              per_step, csv ? ", the CSV line" : "");
}
