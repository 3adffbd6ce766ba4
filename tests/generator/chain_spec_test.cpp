// The chain spec (docs/chain-spec.md): planar5.yaml gives the expected model, every key and
// default of the format does what the document says, the document's examples load, and it
// documents every key the parser accepts.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "files.hpp"
#include "generate.hpp"
#include "pattern.hpp"
#include "robot.hpp"

namespace {

namespace fs = std::filesystem;
using namespace dyngen;
using namespace dyngen::gen;
using dyngen::test::Groups;
using dyngen::test::Pattern;
using dyngen::test::read;

const std::string models = DYNGEN_TEST_MODELS;

/// Inline specs are written to a scratch directory, one per test process.
class ChainSpec : public dyngen::test::ScratchTest {
 protected:
  std::string write(const std::string& yaml) {
    const fs::path path = dir / ("spec" + std::to_string(files++) + ".yaml");
    std::ofstream(path) << yaml;
    return path.string();
  }
  Robot load(const std::string& yaml, const LoadOptions& options = {}) {
    return load_robot(write(yaml), options);
  }
  /// The InputError message for a spec.
  std::string error(const std::string& yaml) {
    const std::string path = write(yaml);
    try {
      load_robot(path);
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(path, 0), 0u) << "the message starts with the file: " << message;
      return message;
    }
    return "(no InputError)";
  }

  int files = 0;
};

void expect_vec(const Vec3<double>& v, double x, double y, double z, const std::string& what) {
  EXPECT_EQ(v.x, x) << what;
  EXPECT_EQ(v.y, y) << what;
  EXPECT_EQ(v.z, z) << what;
}

void expect_identity(const Mat3<double>& E, const std::string& what) {
  const double e[9] = {E.xx, E.xy, E.xz, E.yx, E.yy, E.yz, E.zx, E.zy, E.zz};
  for (int k = 0; k < 9; ++k) EXPECT_EQ(e[k], k % 4 == 0 ? 1.0 : 0.0) << what << " entry " << k;
}

struct LinkData {
  double length, mass, cx, cy, ixx, iyy, izz;
};

TEST_F(ChainSpec, Planar5LoadsIntoTheExpectedModel) {
  const Robot robot = load_robot(models + "/planar5.yaml");
  const Model<double>& m = robot.model;
  EXPECT_EQ(robot.name, "planar5");
  EXPECT_TRUE(robot.warnings.empty());
  EXPECT_EQ(robot.sha256.size(), 64u);
  ASSERT_EQ(m.nbodies, 5);
  EXPECT_EQ(m.nq, 5);
  EXPECT_EQ(m.nv, 5);
  expect_vec(m.gravity, 0, -9.81, 0, "gravity from the file");
  const LinkData links[5] = {{1.0, 1.2, 0.35, 0.02, 0.001, 0.11, 0.11},
                             {0.8, 0.9, 0.5, -0.03, 0.001, 0.05, 0.05},
                             {0.7, 0.7, 0.2, 0, 0.001, 0.03, 0.03},
                             {0.5, 0.5, 0.3, 0.01, 0.0005, 0.01, 0.01},
                             {0.4, 0.3, 0.28, 0, 0.0002, 0.004, 0.004}};
  for (int i = 0; i < 5; ++i) {
    const std::string name = "link" + std::to_string(i + 1);
    const LinkData& l = links[i];
    EXPECT_EQ(m.body_name[i], name);
    EXPECT_EQ(m.joint_name[i], name + "_joint");
    EXPECT_EQ(m.parent[i], i - 1);
    EXPECT_EQ(m.q_index[i], i);
    if (i == 3) {
      EXPECT_EQ(m.joint_type[i], JointType::Prismatic);
      expect_vec(m.joint_axis[i], 1, 0, 0, name + " axis");
    } else {
      EXPECT_EQ(m.joint_type[i], JointType::RevoluteZ) << name;
      expect_vec(m.joint_axis[i], 0, 0, 1, name + " axis");
    }
    // each joint sits at the previous link's length along its x axis
    expect_vec(m.X_tree[i].r, i == 0 ? 0.0 : links[i - 1].length, 0, 0, name + " X_tree.r");
    expect_identity(m.X_tree[i].E, name + " X_tree.E");
    // h = m c; I about the joint by the parallel axis theorem
    const RigidInertia<double>& I = m.I[i];
    EXPECT_EQ(I.m, l.mass) << name;
    expect_vec(I.h, l.mass * l.cx, l.mass * l.cy, 0, name + " h");
    EXPECT_DOUBLE_EQ(I.I.xx, l.ixx + l.mass * l.cy * l.cy) << name;
    EXPECT_DOUBLE_EQ(I.I.yy, l.iyy + l.mass * l.cx * l.cx) << name;
    EXPECT_DOUBLE_EQ(I.I.zz, l.izz + l.mass * (l.cx * l.cx + l.cy * l.cy)) << name;
    EXPECT_DOUBLE_EQ(I.I.xy, -l.mass * l.cx * l.cy) << name;
    EXPECT_EQ(I.I.xz, 0) << name;
    EXPECT_EQ(I.I.yz, 0) << name;
  }
}

TEST_F(ChainSpec, GravityOptionOverridesTheFile) {
  LoadOptions options;
  options.gravity = Vec3<double>{1.5, -2, 3};
  expect_vec(load_robot(models + "/planar5.yaml", options).model.gravity, 1.5, -2, 3, "option");
  options.gravity = Vec3<double>{0, 0, 0};
  expect_vec(load_robot(models + "/planar5.yaml", options).model.gravity, 0, 0, 0, "no gravity");
}

TEST_F(ChainSpec, Defaults) {
  const Robot robot = load("links:\n"
                           "  - mass: 2\n"
                           "  - mass: 1\n"
                           "    length: 0.3\n"
                           "  - mass: 0.5\n");
  const Model<double>& m = robot.model;
  EXPECT_EQ(robot.name, "chain");
  expect_vec(m.gravity, 0, 0, -9.81, "default gravity");
  ASSERT_EQ(m.nbodies, 3);
  const double x[3] = {0, 0, 0.3};  // no length: the next joint is at the link's origin
  for (int i = 0; i < 3; ++i) {
    const std::string name = "link" + std::to_string(i + 1);
    EXPECT_EQ(m.body_name[i], name);
    EXPECT_EQ(m.joint_name[i], name + "_joint");
    EXPECT_EQ(m.joint_type[i], JointType::RevoluteZ);
    expect_vec(m.joint_axis[i], 0, 0, 1, name + " axis");
    expect_vec(m.X_tree[i].r, x[i], 0, 0, name + " X_tree.r");
    expect_identity(m.X_tree[i].E, name);
    // com at the origin and no rotational inertia: a point mass at the joint
    expect_vec(m.I[i].h, 0, 0, 0, name + " h");
    EXPECT_EQ(m.I[i].I.xx, 0);
    EXPECT_EQ(m.I[i].I.zz, 0);
  }
}

TEST_F(ChainSpec, NameAndBase) {
  const Robot robot = load("name: my arm\nbase: world\nlinks:\n  - {name: base, mass: 1}\n");
  EXPECT_EQ(robot.name, "my arm");
  EXPECT_EQ(identifier(robot.name), "my_arm");
  EXPECT_EQ(robot.model.body_name[0], "base") << "a link may be called base when the base is not";
  const std::string message = error("base: world\nlinks:\n  - {name: world, mass: 1}\n");
  EXPECT_NE(message.find("links[0]: link 'world' is defined twice"), std::string::npos) << message;
}

TEST_F(ChainSpec, MassComAndFullInertia) {
  const Model<double> m =
      load("links:\n"
           "  - mass: 2\n"
           "    com: [0, 0, 0]\n"
           "    inertia: {ixx: 1, iyy: 2, izz: 3, ixy: 0.1, ixz: 0.2, iyz: 0.3}\n"
           "  - mass: 4\n"
           "    com: [0.5, -0.25, 2]\n")
          .model;
  EXPECT_EQ(m.I[0].m, 2);
  EXPECT_EQ(m.I[0].I.xx, 1);
  EXPECT_EQ(m.I[0].I.yy, 2);
  EXPECT_EQ(m.I[0].I.zz, 3);
  EXPECT_EQ(m.I[0].I.xy, 0.1);
  EXPECT_EQ(m.I[0].I.xz, 0.2);
  EXPECT_EQ(m.I[0].I.yz, 0.3);
  expect_vec(m.I[1].h, 2, -1, 8, "h = m c");
  EXPECT_EQ(m.I[1].I.xx, 4 * (0.0625 + 4));
  EXPECT_EQ(m.I[1].I.xy, 0.5) << "-m cx cy";
  EXPECT_EQ(m.I[1].I.yz, 2) << "-m cy cz";
}

TEST_F(ChainSpec, JointTypes) {
  const Model<double> m = load("links:\n"
                               "  - {mass: 1, length: 1, joint: {type: revolute}}\n"
                               "  - {mass: 1, length: 1, joint: {type: continuous}}\n"
                               "  - {mass: 1, length: 1, joint: {type: prismatic}}\n")
                              .model;
  EXPECT_EQ(m.joint_type[0], JointType::RevoluteZ);
  EXPECT_EQ(m.joint_type[1], JointType::RevoluteZ);
  EXPECT_EQ(m.joint_type[2], JointType::Prismatic);
  expect_vec(m.joint_axis[2], 0, 0, 1, "a prismatic joint slides along the default axis");
}

// A joint's armature is its rotor inertia, by degree of freedom; a massless tail joint with one
// has ABA's pivot, and without one it is refused.
TEST_F(ChainSpec, ArmatureIsTheJointsRotorInertia) {
  const Robot robot = load("links:\n"
                           "  - {mass: 1, length: 1, com: [0.5, 0, 0], joint: {armature: 0.2}}\n"
                           "  - {mass: 1, length: 1, com: [0.5, 0, 0]}\n"
                           "  - {mass: 0, length: 1, joint: {type: prismatic, armature: 1.5}}\n");
  EXPECT_EQ(robot.model.armature, (std::vector<double>{0.2, 0, 1.5}));
  EXPECT_TRUE(joints_blocking_aba(robot.model).empty());
  EXPECT_EQ(joint_list(robot.model, joints_blocking_aba(
                                        load("links:\n"
                                             "  - {mass: 1, com: [0.5, 0, 0], length: 1}\n"
                                             "  - {mass: 0, length: 1}\n")
                                            .model)),
            "'link2_joint'");
  EXPECT_NE(error("links:\n  - {mass: 1, joint: {type: fixed, armature: 0.1}}\n"
                  "  - {mass: 1}\n")
                .find("joint 'link1_joint' is fixed: only a revolute, prismatic, planar or ball "
                      "joint has an armature"),
            std::string::npos);
}

// A ball joint has a quaternion in q and three rates in v, names its rates like a free joint's
// angular ones, and takes no axis; one whose subtree's inertia cannot turn it is refused, like
// a massless revolute joint.
TEST_F(ChainSpec, BallJointsTakeAQuaternionAndThreeRates) {
  const Robot robot = load("links:\n"
                           "  - {mass: 1, length: 1, com: [0.5, 0, 0], joint: {type: ball}}\n"
                           "  - {mass: 1, inertia: {ixx: 0.1, iyy: 0.1, izz: 0.1},\n"
                           "     joint: {name: wrist, type: ball, armature: 0.3}}\n");
  EXPECT_EQ(robot.model.nq, 8);
  EXPECT_EQ(robot.model.nv, 6);
  EXPECT_EQ(robot.model.armature, (std::vector<double>{0, 0, 0, 0.3, 0.3, 0.3}));
  EXPECT_EQ(velocity_names(robot.model),
            (std::vector<std::string>{"link1_joint:wx", "link1_joint:wy", "link1_joint:wz",
                                      "wrist:wx", "wrist:wy", "wrist:wz"}));
  EXPECT_TRUE(joints_blocking_aba(robot.model).empty());
  // a point mass on its own ball joint cannot be turned about any axis through it
  const Model<double> point = load("links:\n"
                                   "  - {mass: 1, length: 1, com: [0.5, 0, 0]}\n"
                                   "  - {mass: 1, joint: {type: ball}}\n")
                                  .model;
  EXPECT_EQ(joint_list(point, joints_blocking_aba(point)), "'link2_joint'");
  EXPECT_NE(error("links:\n  - {mass: 1, joint: {type: ball, axis: [0, 0, 1]}}\n")
                .find("links[0].joint.axis: a ball joint turns about every axis: it takes none"),
            std::string::npos);
}

TEST_F(ChainSpec, FixedJointMergesTheLinkIntoThePreviousBody) {
  const Robot robot = load("links:\n"
                           "  - {name: arm, mass: 1, length: 0.5, com: [0.25, 0, 0]}\n"
                           "  - {name: tool, mass: 2, length: 0.1, com: [0.05, 0, 0],\n"
                           "     joint: {name: mount, type: fixed}}\n"
                           "  - {name: finger, mass: 0.5}\n");
  const Model<double>& m = robot.model;
  ASSERT_EQ(m.nbodies, 2);
  EXPECT_EQ(m.body_name[1], "finger");
  EXPECT_EQ(m.parent[1], 0);
  EXPECT_DOUBLE_EQ(m.I[0].m, 3);
  EXPECT_DOUBLE_EQ(m.I[0].h.x, 1 * 0.25 + 2 * (0.5 + 0.05));
  // the fixed link's length still places the next joint, from the merged body's frame
  EXPECT_DOUBLE_EQ(m.X_tree[1].r.x, 0.6);
  EXPECT_EQ(m.joint_name[1], "finger_joint");
}

TEST_F(ChainSpec, AxesAreNormalisedAndAxisAlignedOnesGetTheirKinds) {
  const Model<double> m = load("links:\n"
                               "  - {mass: 1, joint: {axis: [0, 0, 2]}}\n"
                               "  - {mass: 1, joint: {axis: [0, -3, 0]}}\n"
                               "  - {mass: 1, joint: {axis: [-0.5, 0, 0]}}\n"
                               "  - {mass: 1, joint: {axis: [3, 0, 4]}}\n"
                               "  - {mass: 1, joint: {axis: [0, 2, 0], type: prismatic}}\n")
                              .model;
  EXPECT_EQ(m.joint_type[0], JointType::RevoluteZ);
  expect_vec(m.joint_axis[0], 0, 0, 1, "[0, 0, 2]");
  EXPECT_EQ(m.joint_type[1], JointType::RevoluteY);
  expect_vec(m.joint_axis[1], 0, -1, 0, "[0, -3, 0]");
  EXPECT_EQ(m.joint_type[2], JointType::RevoluteX);
  expect_vec(m.joint_axis[2], -1, 0, 0, "[-0.5, 0, 0]");
  EXPECT_EQ(m.joint_type[3], JointType::Revolute);
  expect_vec(m.joint_axis[3], 0.6, 0, 0.8, "[3, 0, 4]");
  EXPECT_EQ(m.joint_type[4], JointType::Prismatic);
  expect_vec(m.joint_axis[4], 0, 1, 0, "[0, 2, 0]");
}

TEST_F(ChainSpec, JointNameXyzAndRpy) {
  const double roll = 0.1, pitch = -0.4, yaw = 1.2;
  const Model<double> m =
      load("links:\n"
           "  - {mass: 1, length: 5}\n"
           "  - mass: 1\n"
           "    joint: {name: elbow, xyz: [0.1, 0.2, 0.3], rpy: [0.1, -0.4, 1.2]}\n")
          .model;
  EXPECT_EQ(m.joint_name[1], "elbow");
  expect_vec(m.X_tree[1].r, 0.1, 0.2, 0.3, "xyz replaces the previous link's length");
  // E maps parent to child coordinates: the transpose of R = Rz(yaw) Ry(pitch) Rx(roll)
  const Mat3<double> R = rotation_from_rpy(roll, pitch, yaw);
  const Mat3<double>& E = m.X_tree[1].E;
  EXPECT_EQ(E.xy, R.yx);
  EXPECT_EQ(E.yx, R.xy);
  EXPECT_EQ(E.zx, R.xz);
  EXPECT_EQ(E.xz, R.zx);
  EXPECT_EQ(E.yy, R.yy);
  EXPECT_NEAR(E.xx, std::cos(yaw) * std::cos(pitch), 1e-15);
  EXPECT_NEAR(E.xz, -std::sin(pitch), 1e-15);
}

TEST_F(ChainSpec, ErrorsNameTheLineAndThePathOfTheValue) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"- 1\n", "chain spec: expected a mapping"},
      {"gravty: [0, 0, -9.81]\nlinks: [{mass: 1}]\n",
       ":1: chain spec: unknown key 'gravty' (allowed: base, gravity, links, loops, name)"},
      {"links: [{mass: 1}]\nloops: [{a: link1, b: base, type: 4d}]\n",
       ":2: loops[0].type: '4d' is not 3d or 6d"},
      {"links: [{mass: 1}]\nloops: [{a: link1}]\n", ":2: loops[0]: missing 'b' (a link)"},
      {"name: [a, b]\nlinks: [{mass: 1}]\n", ":1: name: expected a string"},
      {"gravity: [0, 0]\nlinks: [{mass: 1}]\n", ":1: gravity: expected [x, y, z]"},
      {"name: x\n", "links: expected a non-empty list of links"},
      {"links: [3]\n", ":1: links[0]: expected a mapping"},
      {"links:\n  - mass: 1\n    joint: {tpye: fixed}\n", ":3: links[0].joint: unknown key 'tpye'"},
      {"links:\n  - mass: 1\n    inertia: {ixx: 1, izx: 0}\n",
       ":3: links[0].inertia: unknown key 'izx'"},
      {"links:\n  - mass: 1\n    joint: {rpy: [0, a, 0]}\n",
       ":3: links[0].joint.rpy[1]: expected a number"},
      {"links:\n  - {mass: 1, length: -.inf}\n", ":2: links[0].length: expected a finite number"},
      {"links:\n  - {mass: 1}\n  - {mass: 1, joint: {name: link1_joint}}\n",
       "links[1]: joint 'link1_joint' is defined twice"},
  };
  for (const auto& [yaml, expected] : cases) {
    const std::string message = error(yaml);
    EXPECT_NE(message.find(expected), std::string::npos) << yaml << "gave: " << message;
  }
}

TEST_F(ChainSpec, TriangleInequalityIsAWarning) {
  const Robot robot = load("links:\n  - {mass: 1, inertia: {izz: 0.02}}\n");
  ASSERT_EQ(robot.warnings.size(), 1u);
  EXPECT_NE(robot.warnings[0].find("link 'link1'"), std::string::npos) << robot.warnings[0];
  EXPECT_NE(robot.warnings[0].find("triangle inequality"), std::string::npos);
}

// ---- docs/chain-spec.md

const fs::path doc = fs::path(DYNGEN_SOURCE_DIR) / "docs" / "chain-spec.md";

TEST_F(ChainSpec, DocumentedExamplesLoadAndGenerateWithoutWarnings) {
  const std::string text = read(doc);
  int examples = 0;
  for (const Groups& block : Pattern("```yaml\n([^`]*)```").find_all(text)) {
    ++examples;
    const Robot robot = load(block[1]);
    EXPECT_TRUE(robot.warnings.empty()) << block[1] << robot.warnings.front();
    GenerateOptions options;
    options.name = "example";
    EXPECT_NO_THROW(generate(robot, options)) << block[1];
  }
  EXPECT_GE(examples, 3);
}

TEST_F(ChainSpec, DocumentedPlanarExampleIsPlanar5) {
  const std::string text = read(doc);
  const std::string file = read(models + "/planar5.yaml");
  // the document may comment it differently; the data lines must be the file's
  auto data = [](const std::string& yaml) {
    std::string out;
    std::istringstream in(yaml);
    for (std::string line; std::getline(in, line);) {
      line = line.substr(0, line.find('#'));
      while (!line.empty() && line.back() == ' ') line.pop_back();
      if (!line.empty()) out += line + "\n";
    }
    return out;
  };
  const std::size_t start = text.find("```yaml\n", text.find("## Example: the chapter's"));
  ASSERT_NE(start, std::string::npos);
  const std::size_t end = text.find("```", start + 8);
  EXPECT_EQ(data(text.substr(start + 8, end - start - 8)), data(file));
}

TEST_F(ChainSpec, DocumentationListsEveryKeyTheParserAccepts) {
  // the parser's own list of keys, from its unknown-key messages at each level
  const Pattern allowed(R"(\(allowed: ([a-z_, ]+)\))");
  std::set<std::string> keys;
  for (const std::string yaml :
       {"zzz: 1\n", "links: [{mass: 1, zzz: 1}]\n", "links: [{mass: 1, joint: {zzz: 1}}]\n",
        "links: [{mass: 1, inertia: {zzz: 1}}]\n", "links: [{mass: 1}]\nloops: [{zzz: 1}]\n"}) {
    const std::string message = error(yaml);
    const std::optional<Groups> m = allowed.search(message);
    ASSERT_TRUE(m) << message;
    std::istringstream list((*m)[1]);
    for (std::string key; std::getline(list, key, ',');) keys.insert(key.substr(key[0] == ' '));
  }
  EXPECT_EQ(keys.size(), 5u + 6 + 6 + 6 + 5 - 3) << "name is a key at three levels, type at two";
  const std::string text = read(doc);
  for (const std::string& key : keys)
    EXPECT_NE(text.find("`" + key + "`"), std::string::npos) << "not documented: " << key;
}

}  // namespace
