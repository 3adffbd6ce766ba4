// The names of tests/models/coverage/hostile_names.urdf reach the generated header and model
// tables byte for byte. The expected names are that file's attribute values decoded by the XML
// rules (&#10; is a newline, &quot; a quote) and written here as C++ literals, by hand.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hostile_names_double_dynamics.hpp"
#include "hostile_names_double_model.hpp"

namespace {

namespace robot = hostile_names_double;

TEST(HostileNames, JointAndLinkNamesArriveByteForByte) {
  const std::vector<std::string> joints = {
      "j\"1\\",
      "j\n#error newline in a joint name",
      "j\r3?\?/",
      "\xce\xb1/\xce\xb2 */ #error j4",
      "j5\xe2\x80\xa8x",
      "int",
      "link-1",
      "link_1",
      std::string(300, 'J'),
  };
  const std::vector<std::string> links = {
      "link-1",
      "link_1",
      "\xce\xb1/\xce\xb2 */ #error",
      "tab\tlink\\",
      "ls\xe2\x80\xa8#error",
      "int",
      "nbsp\xc2\x85"
      "c1",
      "q\"'<>&",
      std::string(300, 'L'),
  };
  ASSERT_EQ(robot::nv, static_cast<int>(joints.size()));
  const dyngen::Model<double> model = robot::runtime_model();
  ASSERT_EQ(model.nbodies, static_cast<int>(links.size()));
  for (int k = 0; k < robot::nv; ++k) {
    EXPECT_EQ(robot::joint_names[k], joints[k]) << k;
    EXPECT_EQ(model.joint_name[k], joints[k]) << k;
    EXPECT_EQ(model.body_name[k], links[k]) << k;
  }
}

}  // namespace
