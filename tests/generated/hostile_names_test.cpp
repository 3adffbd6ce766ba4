// The names of tests/models/coverage/hostile_names.urdf reach the generated headers (C++ and C)
// and model tables byte for byte. The expected names are that file's attribute values decoded
// by the XML rules (&#10; is a newline, &quot; a quote) and written here as C++ literals, by
// hand. The packages are named after the robot: its name made an identifier, cut to 48
// characters with the FNV-1a hash of the whole name (8d3a6688, computed apart from dyngen).
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "evil_message_FATAL_ERROR_injected_error_8d3a6688_dynamics.hpp"
#include "evil_message_FATAL_ERROR_injected_error_8d3a6688_model.hpp"
#include HOSTILE_C_HEADER

namespace {

namespace robot = ::evil_message_FATAL_ERROR_injected_error_8d3a6688;

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
  ASSERT_EQ(EVIL_MESSAGE_FATAL_ERROR_INJECTED_ERROR_8D3A6688_NV, robot::nv);
  const dyngen::Model<double> model = robot::runtime_model();
  ASSERT_EQ(model.nbodies, static_cast<int>(links.size()));
  for (int k = 0; k < robot::nv; ++k) {
    EXPECT_EQ(robot::joint_names[k], joints[k]) << k;
    EXPECT_EQ(evil_message_FATAL_ERROR_injected_error_8d3a6688_joint_names[k], joints[k]) << k;
    EXPECT_EQ(model.joint_name[k], joints[k]) << k;
    EXPECT_EQ(model.body_name[k], links[k]) << k;
  }
}

TEST(HostileNames, FrameNameArrivesByteForByte) {
  // the fixed leaf link, the one default frame
  const std::string frame = "tool\\ */\n#error frame\t\"";
  ASSERT_EQ(robot::nframes, 1);
  ASSERT_EQ(EVIL_MESSAGE_FATAL_ERROR_INJECTED_ERROR_8D3A6688_NFRAMES, 1);
  EXPECT_EQ(robot::frame_names[0], frame);
  EXPECT_EQ(evil_message_FATAL_ERROR_injected_error_8d3a6688_frame_names[0], frame);
  const dyngen::Model<double> model = robot::runtime_model();
  ASSERT_EQ(model.frames.size(), 1u);
  EXPECT_EQ(model.frames[0].name, frame);
}

}  // namespace
