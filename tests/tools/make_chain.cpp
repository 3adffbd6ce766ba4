// Writes a seeded random serial chain as a dyngen chain spec (YAML), for the generated-code
// tests and the benchmarks: make_chain N SEED planar|spatial OUTPUT [URDF]. With URDF, also
// the same chain as a URDF for MuJoCo and KDL (bench/), with the same numbers; URDF has no
// gravity, so the planar chain's (0, -9.81, 0) is the spec's alone.
//   planar:  joints about z, links along x, gravity along -y, centres of mass off the link's
//            middle, every third joint prismatic along the link;
//   spatial: joint axes cycling through +x, -y, +z and general unit axes, every fourth joint
//            prismatic, rotated joint frames, full inertia tensors.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

namespace {

std::mt19937_64 rng;

double uniform(double lo, double hi) {
  return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

/// Three numbers as text that reads back to the same doubles.
std::string triple(const double (&v)[3]) {
  char text[80];
  std::snprintf(text, sizeof text, "%.17g, %.17g, %.17g", v[0], v[1], v[2]);
  return text;
}

/// URDF's spelling of a triple: spaces, without the commas.
std::string urdf(const std::string& numbers) {
  std::string text;
  for (const char c : numbers)
    if (c != ',') text += c;
  return text;
}

/// One link and the joint it hangs from.
struct Link {
  bool prismatic;
  std::string axis;       // as written in the spec: "x, y, z"
  double xyz[3], rpy[3];  // joint origin
  double length, mass, com[3];
  double I[6];  // ixx, iyy, izz, ixy, ixz, iyz about the centre of mass
};

// The numbers are drawn in the order of the tool's first version, which drew them inside each
// line's fprintf (whose arguments GCC evaluates right to left): a seed's spec stays the same.
Link planar_link(int i, double previous_length) {
  Link l{};
  l.length = uniform(0.2, 1.0);
  l.mass = uniform(0.3, 3.0);
  l.prismatic = i % 3 == 2;
  l.axis = l.prismatic ? "1, 0, 0" : "0, 0, 1";
  l.xyz[0] = previous_length;  // the spec's default joint origin
  l.com[1] = uniform(-0.05, 0.05);
  l.com[0] = uniform(0.1, 0.9) * l.length;
  const double I = l.mass * l.length * l.length / 12;
  l.I[0] = 0.01 * I, l.I[1] = I, l.I[2] = I;
  return l;
}

Link spatial_link(int i) {
  Link l{};
  l.length = uniform(0.2, 1.0);  // unused (the joints' xyz place the links), but drawn
  l.mass = uniform(0.3, 3.0);
  const char* axes[] = {"1, 0, 0", "0, -1, 0", "0, 0, 1", nullptr};
  const double ax = uniform(-1, 1), ay = uniform(-1, 1), az = uniform(-1, 1);
  const double norm = std::sqrt(ax * ax + ay * ay + az * az);
  l.axis = axes[i % 4] ? axes[i % 4] : triple({ax / norm, ay / norm, az / norm});
  l.prismatic = i % 4 == 3;
  l.xyz[2] = uniform(0.1, 0.5), l.xyz[1] = uniform(-0.3, 0.3), l.xyz[0] = uniform(-0.3, 0.3);
  l.rpy[2] = uniform(-3, 3), l.rpy[1] = uniform(-1.5, 1.5), l.rpy[0] = uniform(-3, 3);
  l.com[2] = uniform(0.05, 0.4), l.com[1] = uniform(-0.1, 0.1), l.com[0] = uniform(-0.1, 0.1);
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
      for (int m = 0; m < 3; ++m) I[j][k] += R[j][m] * d[m] * R[k][m];
  const double entries[6] = {I[0][0], I[1][1], I[2][2], I[0][1], I[0][2], I[1][2]};
  std::copy(entries, entries + 6, l.I);
  return l;
}

void write_spec(FILE* out, const char* kind, int n, const char* seed, bool planar,
                const std::vector<Link>& links) {
  std::fprintf(out, "# %s chain of %d links, seed %s (written by tests/tools/make_chain)\n", kind,
               n, seed);
  std::fprintf(out, "name: %s%d\n", planar ? "planar" : "spatial", n);
  if (planar) std::fprintf(out, "gravity: [0, -9.81, 0]\n");
  std::fprintf(out, "links:\n");
  for (int i = 0; i < n; ++i) {
    const Link& l = links[i];
    const char* type = l.prismatic ? "prismatic" : "revolute";
    std::fprintf(out, "  - name: link%d\n", i + 1);
    if (planar) {
      std::fprintf(out, "    joint: {type: %s, axis: [%s]}\n", type, l.axis.c_str());
      std::fprintf(out, "    length: %.17g\n", l.length);
      std::fprintf(out, "    mass: %.17g\n", l.mass);
      std::fprintf(out, "    com: [%.17g, %.17g, 0]\n", l.com[0], l.com[1]);
      std::fprintf(out, "    inertia: {ixx: %.17g, iyy: %.17g, izz: %.17g}\n", l.I[0], l.I[1],
                   l.I[2]);
      continue;
    }
    std::fprintf(out, "    joint:\n      type: %s\n      axis: [%s]\n", type, l.axis.c_str());
    std::fprintf(out, "      xyz: [%s]\n", triple(l.xyz).c_str());
    std::fprintf(out, "      rpy: [%s]\n", triple(l.rpy).c_str());
    std::fprintf(out, "    mass: %.17g\n", l.mass);
    std::fprintf(out, "    com: [%s]\n", triple(l.com).c_str());
    std::fprintf(out,
                 "    inertia: {ixx: %.17g, iyy: %.17g, izz: %.17g, ixy: %.17g, ixz: %.17g, "
                 "iyz: %.17g}\n",
                 l.I[0], l.I[1], l.I[2], l.I[3], l.I[4], l.I[5]);
    std::fprintf(out, "    length: 0\n");
  }
}

// Revolute joints are written as continuous ones (URDF wants limits for revolute joints, and
// limits play no part in the dynamics); prismatic ones get limits that no state reaches.
void write_urdf(FILE* out, const char* kind, int n, const char* seed, bool planar,
                const std::vector<Link>& links) {
  std::fprintf(out, "<?xml version=\"1.0\"?>\n");
  std::fprintf(out, "<!-- %s chain of %d links, seed %s (written by tests/tools/make_chain) -->\n",
               kind, n, seed);
  std::fprintf(out, "<robot name=\"%s%d\">\n  <link name=\"base\"/>\n",
               planar ? "planar" : "spatial", n);
  for (int i = 0; i < n; ++i) {
    const Link& l = links[i];
    const std::string parent = i == 0 ? "base" : "link" + std::to_string(i);
    std::fprintf(out, "  <link name=\"link%d\">\n    <inertial>\n", i + 1);
    std::fprintf(out, "      <origin xyz=\"%s\"/>\n      <mass value=\"%.17g\"/>\n",
                 urdf(triple(l.com)).c_str(), l.mass);
    std::fprintf(out,
                 "      <inertia ixx=\"%.17g\" iyy=\"%.17g\" izz=\"%.17g\" ixy=\"%.17g\" "
                 "ixz=\"%.17g\" iyz=\"%.17g\"/>\n",
                 l.I[0], l.I[1], l.I[2], l.I[3], l.I[4], l.I[5]);
    std::fprintf(out, "    </inertial>\n  </link>\n");
    std::fprintf(out, "  <joint name=\"link%d_joint\" type=\"%s\">\n", i + 1,
                 l.prismatic ? "prismatic" : "continuous");
    std::fprintf(out, "    <parent link=\"%s\"/>\n    <child link=\"link%d\"/>\n", parent.c_str(),
                 i + 1);
    std::fprintf(out, "    <origin xyz=\"%s\" rpy=\"%s\"/>\n    <axis xyz=\"%s\"/>\n",
                 urdf(triple(l.xyz)).c_str(), urdf(triple(l.rpy)).c_str(), urdf(l.axis).c_str());
    if (l.prismatic)
      std::fprintf(out, "    <limit lower=\"-1e6\" upper=\"1e6\" effort=\"0\" velocity=\"0\"/>\n");
    std::fprintf(out, "  </joint>\n");
  }
  std::fprintf(out, "</robot>\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5 && argc != 6) {
    std::fprintf(stderr, "usage: make_chain N SEED planar|spatial OUTPUT [URDF]\n");
    return 2;
  }
  const int n = std::atoi(argv[1]);
  rng.seed(std::strtoull(argv[2], nullptr, 10));
  const bool planar = std::string(argv[3]) == "planar";
  if (n < 1) return 1;
  std::vector<Link> links;
  for (int i = 0; i < n; ++i)
    links.push_back(planar ? planar_link(i, i == 0 ? 0 : links.back().length) : spatial_link(i));
  for (int k = 4; k < argc; ++k) {
    FILE* out = std::fopen(argv[k], "w");
    if (!out) return 1;
    (k == 4 ? write_spec : write_urdf)(out, argv[3], n, argv[2], planar, links);
    if (std::fclose(out) != 0) return 1;
  }
  return 0;
}
