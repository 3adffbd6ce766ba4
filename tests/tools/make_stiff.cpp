// Writes the stiff and extreme robots of tests/models/stiff (deterministic, no random numbers):
//   make_stiff tapered N RATIO OUTPUT  chain spec: link k is RATIO^(k-1) the size of the 1 m,
//                                      1 kg first link; mass ~ size^3, inertia ~ size^5
//   make_stiff alternating N OUTPUT    chain spec: masses 1 kg and 1e-6 kg in turn (neighbours
//                                      differ by 1e6 both ways), the same shape throughout
//   make_stiff thin_rods N OUTPUT      chain spec: rods with an inertia about their long axis 1e-9
//                                      of the transverse one, every other joint spinning one
//   make_stiff light_limbs OUTPUT      URDF: a 1000 kg torso with two legs and two arms ending in
//                                      1e-3 kg ankles and feet and 1e-4 kg wrists and hands
// Joint axes alternate between z and y (and x for the spinning rods), so the chains are spatial.
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string>

namespace {

/// Principal moments of a solid box of mass m and edges a (along x), b, c.
struct Box {
  double ixx, iyy, izz;
};

Box box(double m, double a, double b, double c) {
  return {m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12};
}

void chain_link(FILE* out, int k, const char* axis, double length, double mass, double com_x,
                const Box& I) {
  std::fprintf(out, "  - name: link%d\n", k);
  std::fprintf(out, "    joint: {axis: [%s]}\n", axis);
  std::fprintf(out, "    length: %.17g\n", length);
  std::fprintf(out, "    mass: %.17g\n", mass);
  std::fprintf(out, "    com: [%.17g, 0, 0]\n", com_x);
  std::fprintf(out, "    inertia: {ixx: %.17g, iyy: %.17g, izz: %.17g}\n", I.ixx, I.iyy, I.izz);
}

const char* swing_axis(int k) { return k % 2 == 1 ? "0, 0, 1" : "0, 1, 0"; }

/// Slender links (width a tenth of the length) shrinking by `ratio` per link. The size is
/// multiplied up link by link (exact IEEE products, the same on every machine).
void tapered(FILE* out, int n, double ratio) {
  double size = 1;
  for (int k = 1; k <= n; ++k, size *= ratio) {
    const double mass = size * size * size;
    chain_link(out, k, swing_axis(k), size, mass, 0.5 * size,
               box(mass, size, 0.1 * size, 0.1 * size));
  }
}

/// 0.4 m links, heavy ones first; only the mass (and with it the inertia) alternates.
void alternating(FILE* out, int n) {
  for (int k = 1; k <= n; ++k) {
    const double mass = k % 2 == 1 ? 1.0 : 1e-6;
    chain_link(out, k, swing_axis(k), 0.4, mass, 0.2, box(mass, 0.4, 0.05, 0.05));
  }
}

/// 0.5 m, 1 kg rods on their own x axis. Joints swing about z, spin about x, swing about y,
/// spin about x, ...: stretched out (q = 0), a spinning joint moves almost no inertia at all.
void thin_rods(FILE* out, int n) {
  const double transverse = 1.0 * 0.5 * 0.5 / 12;
  for (int k = 1; k <= n; ++k) {
    const char* axis = k % 2 == 0 ? "1, 0, 0" : k % 4 == 1 ? "0, 0, 1" : "0, 1, 0";
    chain_link(out, k, axis, 0.5, 1.0, 0.25, {1e-9 * transverse, transverse, transverse});
  }
}

void urdf_link(FILE* out, const std::string& name, double mass, double com_x, double com_z,
               const Box& I) {
  std::fprintf(out,
               "  <link name=\"%s\">\n"
               "    <inertial>\n"
               "      <origin xyz=\"%.17g 0 %.17g\" rpy=\"0 0 0\"/>\n"
               "      <mass value=\"%.17g\"/>\n"
               "      <inertia ixx=\"%.17g\" ixy=\"0\" ixz=\"0\" iyy=\"%.17g\" iyz=\"0\" "
               "izz=\"%.17g\"/>\n"
               "    </inertial>\n"
               "  </link>\n",
               name.c_str(), com_x, com_z, mass, I.ixx, I.iyy, I.izz);
}

void urdf_joint(FILE* out, const std::string& parent, const std::string& child, double x,
                double y, double z, const char* axis) {
  std::fprintf(out,
               "  <joint name=\"%s_joint\" type=\"revolute\">\n"
               "    <parent link=\"%s\"/>\n"
               "    <child link=\"%s\"/>\n"
               "    <origin xyz=\"%.17g %.17g %.17g\" rpy=\"0 0 0\"/>\n"
               "    <axis xyz=\"%s\"/>\n"
               "    <limit lower=\"-3.14\" upper=\"3.14\" effort=\"1000\" velocity=\"10\"/>\n"
               "  </joint>\n",
               child.c_str(), parent.c_str(), child.c_str(), x, y, z, axis);
}

/// One link of a limb: its joint's axis, its mass and its length.
struct Segment {
  const char* name;
  const char* axis;
  double mass, length;
};

/// A limb hanging from the torso at (x, y, z), each link along -z from the end of the previous.
void limb(FILE* out, const std::string& side, double x, double y, double z,
          std::span<const Segment> segments) {
  std::string parent = "torso";
  for (const Segment& s : segments) {
    const std::string name = side + "_" + s.name;
    urdf_joint(out, parent, name, x, y, z, s.axis);
    // a slender link along -z, its width a fifth of its length (at least 2 cm)
    const double width = s.length / 5 > 0.02 ? s.length / 5 : 0.02;
    urdf_link(out, name, s.mass, 0, -s.length / 2, box(s.mass, width, width, s.length));
    parent = name;
    x = 0;
    y = 0;
    z = -s.length;
  }
}

void light_limbs(FILE* out) {
  std::fprintf(out, "<robot name=\"light_limbs\">\n");
  const double torso_mass = 1000;
  urdf_link(out, "torso", torso_mass, 0, 0, box(torso_mass, 0.4, 0.6, 1.0));
  const Segment leg[] = {{"hip_yaw", "0 0 1", 2, 0.05},   {"hip_roll", "1 0 0", 2, 0.05},
                         {"thigh", "0 1 0", 10, 0.45},    {"shank", "0 1 0", 5, 0.45},
                         {"ankle", "0 1 0", 1e-3, 0.03},  {"foot", "1 0 0", 1e-3, 0.06}};
  const Segment arm[] = {{"shoulder", "0 1 0", 2, 0.05},  {"upper_arm", "1 0 0", 3, 0.3},
                         {"forearm", "0 1 0", 2, 0.3},    {"wrist", "0 1 0", 1e-4, 0.02},
                         {"hand", "1 0 0", 1e-4, 0.05}};
  limb(out, "left", 0, 0.15, -0.5, leg);
  limb(out, "right", 0, -0.15, -0.5, leg);
  limb(out, "left", 0, 0.35, 0.4, arm);
  limb(out, "right", 0, -0.35, 0.4, arm);
  std::fprintf(out, "</robot>\n");
}

int usage() {
  std::fprintf(stderr,
               "usage: make_stiff tapered N RATIO OUTPUT | alternating N OUTPUT | "
               "thin_rods N OUTPUT | light_limbs OUTPUT\n");
  return 2;
}

/// The robot's name: the command's words, with '.' turned into 'p' (tapered200_0p5).
std::string robot_name(int argc, char** argv) {
  std::string name = argv[1];
  for (int k = 2; k < argc - 1; ++k) name += std::string(k == 2 ? "" : "_") + argv[k];
  for (char& c : name)
    if (c == '.') c = 'p';
  return name;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return usage();
  const std::string kind = argv[1];
  const int expected_argc = kind == "tapered" ? 5 : kind == "light_limbs" ? 3 : 4;
  if (argc != expected_argc ||
      (kind != "tapered" && kind != "alternating" && kind != "thin_rods" && kind != "light_limbs") ||
      (kind != "light_limbs" && std::atoi(argv[2]) < 1))
    return usage();
  FILE* out = std::fopen(argv[argc - 1], "w");
  if (!out) return 1;
  std::string command = "tests/tools/make_stiff";
  for (int k = 1; k < argc - 1; ++k) command += std::string(" ") + argv[k];
  if (kind == "light_limbs") {
    std::fprintf(out, "<?xml version=\"1.0\"?>\n<!-- written by %s -->\n", command.c_str());
    light_limbs(out);
    return std::fclose(out) == 0 ? 0 : 1;
  }
  std::fprintf(out, "# written by %s\nname: %s\nlinks:\n", command.c_str(),
               robot_name(argc, argv).c_str());
  const int n = std::atoi(argv[2]);
  if (kind == "tapered") tapered(out, n, std::atof(argv[3]));
  if (kind == "alternating") alternating(out, n);
  if (kind == "thin_rods") thin_rods(out, n);
  return std::fclose(out) == 0 ? 0 : 1;
}
