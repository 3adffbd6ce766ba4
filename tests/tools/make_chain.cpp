// Writes a seeded random serial chain as a dyngen chain spec (YAML), for the generated-code
// tests: make_chain N SEED planar|spatial OUTPUT.
//   planar:  joints about z, links along x, gravity along -y, centres of mass off the link's
//            middle, every third joint prismatic along the link;
//   spatial: joint axes cycling through +x, -y, +z and general unit axes, every fourth joint
//            prismatic, rotated joint frames, full inertia tensors.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

namespace {

std::mt19937_64 rng;

double uniform(double lo, double hi) {
  return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: make_chain N SEED planar|spatial OUTPUT\n");
    return 2;
  }
  const int n = std::atoi(argv[1]);
  rng.seed(std::strtoull(argv[2], nullptr, 10));
  const bool planar = std::string(argv[3]) == "planar";
  FILE* out = std::fopen(argv[4], "w");
  if (!out || n < 1) return 1;
  std::fprintf(out, "# %s chain of %d links, seed %s (written by tests/tools/make_chain)\n",
               argv[3], n, argv[2]);
  std::fprintf(out, "name: %s%d\n", planar ? "planar" : "spatial", n);
  if (planar) std::fprintf(out, "gravity: [0, -9.81, 0]\n");
  std::fprintf(out, "links:\n");
  for (int i = 0; i < n; ++i) {
    const double length = uniform(0.2, 1.0);
    const double mass = uniform(0.3, 3.0);
    std::fprintf(out, "  - name: link%d\n", i + 1);
    if (planar) {
      const bool prismatic = i % 3 == 2;
      std::fprintf(out, "    joint: {type: %s, axis: [%s]}\n", prismatic ? "prismatic" : "revolute",
                   prismatic ? "1, 0, 0" : "0, 0, 1");
      std::fprintf(out, "    length: %.17g\n", length);
      std::fprintf(out, "    mass: %.17g\n", mass);
      std::fprintf(out, "    com: [%.17g, %.17g, 0]\n", uniform(0.1, 0.9) * length,
                   uniform(-0.05, 0.05));
      const double I = mass * length * length / 12;
      std::fprintf(out, "    inertia: {ixx: %.17g, iyy: %.17g, izz: %.17g}\n", 0.01 * I, I, I);
      continue;
    }
    const char* axes[] = {"1, 0, 0", "0, -1, 0", "0, 0, 1", nullptr};
    char general[96];
    const double ax = uniform(-1, 1), ay = uniform(-1, 1), az = uniform(-1, 1);
    const double norm = std::sqrt(ax * ax + ay * ay + az * az);
    std::snprintf(general, sizeof general, "%.17g, %.17g, %.17g", ax / norm, ay / norm, az / norm);
    const char* axis = axes[i % 4] ? axes[i % 4] : general;
    std::fprintf(out, "    joint:\n      type: %s\n      axis: [%s]\n",
                 i % 4 == 3 ? "prismatic" : "revolute", axis);
    std::fprintf(out, "      xyz: [%.17g, %.17g, %.17g]\n", uniform(-0.3, 0.3), uniform(-0.3, 0.3),
                 uniform(0.1, 0.5));
    std::fprintf(out, "      rpy: [%.17g, %.17g, %.17g]\n", uniform(-3, 3), uniform(-1.5, 1.5),
                 uniform(-3, 3));
    std::fprintf(out, "    mass: %.17g\n", mass);
    std::fprintf(out, "    com: [%.17g, %.17g, %.17g]\n", uniform(-0.1, 0.1), uniform(-0.1, 0.1),
                 uniform(0.05, 0.4));
    // principal moments that satisfy the triangle inequality, turned by a random rotation
    const double a = uniform(0.01, 0.1), b = uniform(0.01, 0.1);
    const double c = uniform(std::abs(a - b), a + b);
    const double r = uniform(-3, 3), p = uniform(-1.5, 1.5), y = uniform(-3, 3);
    const double cr = std::cos(r), sr = std::sin(r), cp = std::cos(p), sp = std::sin(p);
    const double cy = std::cos(y), sy = std::sin(y);
    const double R[3][3] = {{cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr},
                            {sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr},
                            {-sp, cp * sr, cp * cr}};
    const double d[3] = {a, b, c};
    double I[3][3] = {};
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) I[j][k] += R[j][l] * d[l] * R[k][l];
    std::fprintf(out,
                 "    inertia: {ixx: %.17g, iyy: %.17g, izz: %.17g, ixy: %.17g, ixz: %.17g, "
                 "iyz: %.17g}\n",
                 I[0][0], I[1][1], I[2][2], I[0][1], I[0][2], I[1][2]);
    std::fprintf(out, "    length: 0\n");
  }
  return std::fclose(out) == 0 ? 0 : 1;
}
