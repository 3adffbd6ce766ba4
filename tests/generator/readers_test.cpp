// The reader registry (generator/readers.hpp): a .xml is read by its root element, and what
// --help and the errors say about robot files comes from the table.
#include "readers.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "files.hpp"
#include "output.hpp"
#include "robot.hpp"

namespace {

namespace fs = std::filesystem;
using namespace dyngen::gen;
using dyngen::test::CliResult;
using dyngen::test::read;
using dyngen::test::run_dyngen;
using Scratch = dyngen::test::ScratchTest;

const std::string models = DYNGEN_TEST_MODELS;

/// The extensions of the formats dyngen reads (not those it only refuses).
std::set<std::string> read_extensions() {
  std::set<std::string> extensions;
  for (const Reader& reader : readers())
    if (!reader.refused) extensions.insert(reader.extensions.begin(), reader.extensions.end());
  return extensions;
}

TEST(Readers, UrdfMjcfAndChainSpecAreReadByTheirExtensions) {
  EXPECT_EQ(read_extensions(), (std::set<std::string>{".urdf", ".xml", ".yaml", ".yml"}));
}

// the root element is what tells them apart
TEST(Readers, FormatsSharingAnExtensionHaveDistinctRootElements) {
  for (const Reader& a : readers())
    for (const Reader& b : readers()) {
      if (&a == &b) continue;
      for (const std::string_view ext : a.extensions)
        if (std::count(b.extensions.begin(), b.extensions.end(), ext)) {
          EXPECT_FALSE(a.root.empty()) << a.format << " shares " << ext << " with " << b.format;
          EXPECT_NE(a.root, b.root) << a.format << " and " << b.format << " share " << ext;
        }
    }
}

TEST(Readers, XmlWithAMujocoRootIsReadAsMjcf) {
  const Robot robot = load_robot(models + "/mjcf/quadruped.xml");
  EXPECT_EQ(robot.name, "mjcf_quadruped");
  EXPECT_EQ(robot.model.nv, 18);
  EXPECT_EQ(robot.model.joint_type[0], dyngen::JointType::Free);
  ASSERT_EQ(robot.warnings.size(), 2u);
  EXPECT_NE(robot.warnings[0].find("<contact>, <keyframe>, <option> not used by dyngen"),
            std::string::npos)
      << robot.warnings[0];
  // its legs' class sets damping, and no joint has limits
  EXPECT_NE(robot.warnings[1].find("the joints' damping (MuJoCo's passive and constraint "
                                   "forces) are not part of the rigid-body dynamics"),
            std::string::npos)
      << robot.warnings[1];
}

// the bodies' inertia is given, so their meshes' files (not here) are not needed
TEST(Readers, MjcfMeshGeomsOfBodiesWithAnInertialAreNotRead) {
  const Robot robot = load_robot(models + "/mjcf/visual_meshes.xml");
  ASSERT_EQ(robot.model.nv, 2);
  EXPECT_EQ(robot.model.I[0].m, 2.0);
  EXPECT_EQ(robot.model.I[1].m, 1.2);
}

// MuJoCo 3's keywords where they do not change the dynamics (integrator="implicitfast", which
// MuJoCo 2.2 rejects) are dropped with their element, so the file loads
TEST_F(Scratch, MjcfWithMujoco3OptionsLoads) {
  const fs::path xml = dir / "implicit.xml";
  write_file(xml, "<mujoco model=\"implicit\"><option integrator=\"implicitfast\" "
                  "gravity=\"0 0 -3.7\"/><worldbody><body name=\"a\"><joint name=\"j\"/>"
                  "<geom size=\"0.1\" pos=\"0.2 0 0\"/></body></worldbody></mujoco>\n");
  const Robot robot = load_robot(xml.string());
  EXPECT_EQ(robot.model.nv, 1);
  EXPECT_EQ(robot.model.gravity.z, -3.7);  // <option gravity> is still read
}

TEST_F(Scratch, XmlWithARobotRootIsReadAsUrdf) {
  const fs::path xml = dir / "double_pendulum.xml";
  fs::copy_file(models + "/double_pendulum.urdf", xml);
  const Robot from_xml = load_robot(xml.string());
  const Robot from_urdf = load_robot(models + "/double_pendulum.urdf");
  EXPECT_EQ(from_xml.name, "2dof_planar");
  EXPECT_EQ(from_xml.model.nv, 2);
  EXPECT_EQ(from_xml.model.joint_name, from_urdf.model.joint_name);
  EXPECT_EQ(from_xml.model.body_name, from_urdf.model.body_name);
  for (int i = 0; i < from_xml.model.nbodies; ++i)
    EXPECT_EQ(from_xml.model.I[i].m, from_urdf.model.I[i].m);
}

// an extension in the table is in every command's help for the robot argument
TEST_F(Scratch, EveryCommandsHelpListsEveryExtensionRead) {
  for (const std::string command : {"", "eval", "report", "firmware-report"}) {
    std::vector<std::string> args{"--help"};
    if (!command.empty()) args.insert(args.begin(), command);
    const CliResult r = run_dyngen(args, dir);
    ASSERT_EQ(r.status, 0) << command;
    const std::size_t at = r.out.find("\n  robot ");
    ASSERT_NE(at, std::string::npos) << r.out;
    const std::string line = r.out.substr(at + 1, r.out.find('\n', at + 1) - at - 1);
    for (const Reader& reader : readers()) {
      if (reader.refused) continue;
      EXPECT_NE(line.find(reader.format), std::string::npos) << command << ": " << line;
      for (const std::string_view ext : reader.extensions)
        EXPECT_NE(line.find(std::string(ext) + (ext == reader.extensions.back() ? ")" : ",")),
                  std::string::npos)
            << command << ": " << ext << " not in " << line;
    }
  }
}

TEST(Readers, UnknownExtensionListsEveryExtensionRead) {
  try {
    parse_robot("robot.sdf", "", {});
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("robot.sdf: unknown kind of robot file", 0), 0u) << message;
    for (const std::string& ext : read_extensions())
      EXPECT_NE(message.find(ext), std::string::npos) << ext << " not in " << message;
  }
}

}  // namespace
