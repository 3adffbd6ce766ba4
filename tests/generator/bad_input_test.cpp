// Bad input (docs/design.md, "Errors and warnings"): every error names the file, the element and the
// problem, through the library and through the dyngen command, which exits non-zero and writes
// nothing. Imperfect real-world URDFs load with warnings instead.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
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
using namespace dyngen::gen;
using dyngen::test::Groups;
using dyngen::test::Pattern;
using dyngen::test::read;
using dyngen::test::entries_of;
using dyngen::test::snapshot;

const std::string bad = DYNGEN_TEST_BAD;
const std::string models = DYNGEN_TEST_MODELS;

using Scratch = dyngen::test::ScratchTest;

using dyngen::test::CliResult;
using dyngen::test::run_dyngen;
using dyngen::test::independent_mimics;

/// The options of the command line that the library takes too.
LoadOptions load_options(const std::vector<std::string>& options) {
  LoadOptions load;
  for (std::size_t k = 0; k + 1 < options.size(); ++k)
    if (options[k] == "--lock") load.lock.push_back(options[k + 1]);
  load.mimic_independent =
      std::find(options.begin(), options.end(), "--mimic-independent") != options.end();
  load.floating_base =
      std::find(options.begin(), options.end(), "--floating-base") != options.end();
  return load;
}

/// What the library throws for a robot, loading it and generating every algorithm.
std::string library_error(const std::string& robot, const LoadOptions& load) {
  try {
    const Robot r = load_robot(robot, load);
    GenerateOptions options;
    options.name = "robot";
    generate(r, options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

struct Case {
  std::string name;                   // test parameter name
  std::string robot;                  // the input file
  std::vector<std::string> options;   // further command-line options
  std::vector<std::string> expected;  // parts of the message: the element and the problem
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

/// Bad robots, and options that the library takes too.
const std::vector<Case> bad_robots = {
    {"MissingFile", bad + "/no_such_robot.urdf", {}, {"no such file"}},
    {"DirectoryInsteadOfFile", bad, {}, {"not a regular file"}},
    {"MalformedXml", bad + "/malformed.urdf", {}, {"malformed.urdf:5:", "malformed XML", "link"}},
    {"NotUrdf", bad + "/not_urdf.urdf", {}, {"not a URDF", "no <robot> element"}},
    // .xml is URDF's and MJCF's: the root element tells them apart
    {"MalformedXmlInXml", bad + "/malformed.xml", {},
     {"malformed.xml:5:", "malformed XML", "link"}},
    {"MjcfWithoutJoints", bad + "/mjcf.xml", {}, {"mjcf.xml: the robot has no moving joint"}},
    {"MjcfTurnAfterBall", bad + "/mjcf_turn_after_ball.xml", {},
     {"mjcf_turn_after_ball.xml: MuJoCo's compiler:", "ball followed by rotation in body 'arm'"}},
    {"MjcfNestedFreeJoint", bad + "/mjcf_nested_free.xml", {},
     {"mjcf_nested_free.xml: MuJoCo's compiler:", "free joint"}},
    {"MjcfEquality", bad + "/mjcf_equality.xml", {},
     {"mjcf_equality.xml:8: <equality> constraints are not supported"}},
    {"MjcfFrame", bad + "/mjcf_frame.xml", {}, {"mjcf_frame.xml:4: <frame> is not supported"}},
    {"MjcfFloatingBase", models + "/mjcf/arm.xml", {"--floating-base"},
     {"arm.xml: --floating-base puts the root link on a free joint, and this file's root is "
      "the world", "<freejoint/>"}},
    {"MjcfIncludedEquality", bad + "/mjcf_included_equality.xml", {},
     {"mjcf_included_equality.xml: 1 <equality> constraints (in an included file) are not "
      "supported"}},
    {"MjcfMissingMesh", bad + "/mjcf_missing_mesh.xml", {},
     {"no_such_mesh.stl", "the inertia of body 'a' (mesh 'shell') comes from its mesh (no "
      "<inertial>)"}},
    {"XmlOfAnotherFormat", bad + "/other_root.xml", {},
     {"other_root.xml: root element <sdf>", "<robot> for URDF", "<mujoco> for MJCF"}},
    {"XmlWithoutAnElement", bad + "/no_element.xml", {},
     {"no_element.xml: no element: dyngen expects <robot> for URDF or <mujoco> for MJCF"}},
    {"LinkWithTwoParents", bad + "/two_parents.urdf", {},
     {"link 'tip'", "two parent joints", "'left_to_tip'", "'right_to_tip'", "loop"}},
    {"LoopWithoutRoot", bad + "/cycle.urdf", {}, {"joints 'a_to_b', 'b_to_a'", "form a loop"}},
    {"UndefinedParentLink", bad + "/undefined_parent.urdf", {},
     {"parent link [torso]", "joint [shoulder]", "not found"}},
    {"NegativeMassUrdf", bad + "/negative_mass.urdf", {}, {"link 'arm'", "mass is negative (-1)"}},
    {"InfiniteMassUrdf", bad + "/infinite_mass.urdf", {},
     {"Link [arm]", "mass [1e999] is not a float"}},
    {"NanInertiaUrdf", bad + "/nan_inertia.urdf", {},
     {"Link [arm]", "inertia element iyy is not a valid double"}},
    {"NegativeEigenvalueUrdf", bad + "/negative_eigenvalue.urdf", {},
     {"link 'arm'", "negative eigenvalue (-1;"}},
    {"ZeroAxisUrdf", bad + "/zero_axis.urdf", {}, {"joint 'shoulder'", "zero or non-finite axis"}},
    {"LockUnknownJoint", models + "/ur5.urdf", {"--lock", "no_such_joint"},
     {"joint 'no_such_joint'", "no joint of that name"}},
    {"UnknownExtension", bad + "/robot.sdf", {}, {"unknown kind of robot file", ".urdf", ".yaml"}},
    {"XacroFile", bad + "/robot.urdf.xacro", {},
     {"a xacro file", "xacro " + bad + "/robot.urdf.xacro > robot.urdf", "give dyngen the .urdf"}},
    {"MalformedYaml", bad + "/malformed.yaml", {}, {"malformed.yaml:7:", "malformed YAML"}},
    {"ChainUnknownKey", bad + "/unknown_key.yaml", {},
     {"unknown_key.yaml:8:", "links[1]", "unknown key 'lenght'", "allowed:"}},
    {"ChainMissingMass", bad + "/missing_mass.yaml", {},
     {"missing_mass.yaml:7:", "links[1]", "missing 'mass'"}},
    {"ChainBadJointType", bad + "/bad_joint_type.yaml", {},
     {"links[0].joint.type", "joint type 'spherical' is not supported"}},
    {"ChainMassNotANumber", bad + "/mass_not_number.yaml", {},
     {"links[0].mass", "expected a number"}},
    {"ChainInfiniteMass", bad + "/infinite_mass.yaml", {},
     {"links[0].mass", "expected a finite number"}},
    {"ChainNanInertia", bad + "/nan_inertia.yaml", {},
     {"links[0].inertia.iyy", "expected a finite number"}},
    {"ChainNegativeMass", bad + "/negative_mass.yaml", {}, {"link 'link1'", "mass is negative"}},
    {"ChainNegativeEigenvalue", bad + "/negative_eigenvalue.yaml", {},
     {"link 'link1'", "negative eigenvalue"}},
    {"ChainZeroAxis", bad + "/zero_axis.yaml", {},
     {"joint 'link1_joint'", "zero or non-finite axis"}},
    {"ChainVectorOfTwo", bad + "/bad_vector.yaml", {}, {"links[0].com", "expected [x, y, z]"}},
    {"ChainNoLinks", bad + "/no_links.yaml", {}, {"links", "expected a non-empty list"}},
    {"ChainKeyNotAName", bad + "/key_not_a_name.yaml", {},
     {"key_not_a_name.yaml:2:", "chain spec", "a key must be a name"}},
    {"ChainLinkKeyNotAName", bad + "/link_key_not_a_name.yaml", {},
     {"link_key_not_a_name.yaml:4:", "links[0]", "a key must be a name"}},
    {"ChainDuplicateLink", bad + "/duplicate_link.yaml", {},
     {"links[1]", "link 'arm' is defined twice"}},
    {"AbaOnRomeo", models + "/romeo.urdf", {"--mimic-independent"},
     {"ABA is undefined", "24 joints move no mass", "--lock LHand", "--lock-massless",
      "--algorithms rnea,crba"}},
    {"AbaOnMasslessFloatingCartPole", bad + "/floating_massless_cartpole.urdf",
     {"--floating-base"},
     {"ABA is undefined", "free joint 'floating_base' is singular", "body 'rail', which has no mass",
      "Give link 'rail' a mass", "leave out --floating-base", "--algorithms rnea,crba"}},
    {"AbaOnMasslessFloatingArm", bad + "/floating_massless_arm.urdf", {"--floating-base"},
     {"ABA is undefined", "free joint 'floating_base' is singular", "--algorithms rnea,crba"}},
    // model constants that the algorithms cannot compute with: one check after building
    {"HugeMassUrdf", bad + "/huge_mass.urdf", {},
     {"link 'arm': the mass 1e+308 kg exceeds 1e+50 in magnitude"}},
    {"FarCentreOfMassUrdf", bad + "/far_com.urdf", {},
     {"link 'arm': the first moment (mass times centre of mass) (1e+200, 0, 0) kg m exceeds "
      "1e+50"}},
    {"SubnormalMassUrdf", bad + "/subnormal_mass.urdf", {},
     {"link 'arm': the mass 9.99989e-321 kg is subnormal"}},
    {"ChainSubnormalMass", bad + "/subnormal_mass.yaml", {},
     {"link 'link1': the mass 9.99989e-321 kg is subnormal"}},
    {"ChainHugeGravity", bad + "/huge_gravity.yaml", {},
     {"gravity (0, 0, -1e+308) m/s^2 exceeds 1e+50 in magnitude"}},
    {"ChainSubnormalPivot", bad + "/subnormal_pivot.yaml", {},
     {"ABA is undefined", "1 joint moves no mass", "'link1_joint'"}},
    // a chain spec's loop closures, checked once the model is built
    {"LoopUnknownLink", bad + "/loop_unknown_link.yaml", {},
     {"loop_unknown_link.yaml: loop link2-base: no link named 'link2'; the links are"}},
    {"LoopOnOneBody", bad + "/loop_one_body.yaml", {},
     {"loop link1-tip: both links are on one rigid body, so the loop constrains nothing"}},
};

/// Options that only the command line parses.
const std::vector<Case> bad_options = {
    {"GravityTwoNumbers", models + "/ur5.urdf", {"--gravity", "1,2"},
     {"--gravity 1,2", "expected three numbers"}},
    {"GravityNotANumber", models + "/ur5.urdf", {"--gravity", "0,x,-9.81"},
     {"'x' is not a finite number"}},
    {"GravityNan", models + "/ur5.urdf", {"--gravity", "nan,0,0"},
     {"'nan' is not a finite number"}},
    {"GravityInfinite", models + "/ur5.urdf", {"--gravity", "0,0,-inf"},
     {"'-inf' is not a finite number"}},
    {"GravityTrailingText", models + "/ur5.urdf", {"--gravity", "0,0,-9.81m"},
     {"'-9.81m' is not a finite number"}},
    {"AlgorithmUnknown", models + "/ur5.urdf", {"--algorithms", "rnea,foo"},
     {"unknown algorithm 'foo'"}},
    {"AlgorithmsEmpty", models + "/ur5.urdf", {"--algorithms", ""},
     {"--algorithms", "name at least one"}},
    {"AlgorithmsNamedAndAdded", models + "/ur5.urdf", {"--algorithms", "rnea,+crba"},
     {"--algorithms rnea,+crba: either name the whole set", "not both"}},
    {"AlgorithmsAddedWithoutPlus", models + "/ur5.urdf", {"--algorithms", "+minv,crba"},
     {"--algorithms +minv,crba: 'crba': to add to the default set, start every name with +"}},
    {"AlgorithmAddedUnknown", models + "/ur5.urdf", {"--algorithms", "+foo"},
     {"--algorithms +foo: unknown algorithm 'foo'"}},
    {"ScalarUnknown", models + "/ur5.urdf", {"--scalar", "half"}, {"--scalar", "half"}},
    {"BatchLanesUnknown", models + "/ur5.urdf", {"--batch", "3"}, {"--batch", "3"}},
    {"BatchInC", models + "/ur5.urdf", {"--batch", "4", "--lang", "c"},
     {"--batch: batch functions are C++", "--lang c++"}},
    {"PythonInC", models + "/ur5.urdf", {"--python", "--lang", "c"},
     {"--python: batch functions are C++"}},
    {"FrameUnknown", models + "/ur5.urdf", {"--frames", "tool0,tool9"},
     {"--frames: no link named 'tool9'", "'tool0'", "'wrist_3_link'"}},
    {"FramesEmpty", models + "/ur5.urdf", {"--frames", ","},
     {"--frames: ',' has an empty name", "such as tool0,ee_link"}},
    {"FramesEmptyItem", models + "/ur5.urdf",
     {"--frames", "tool0,,ee_link", "--algorithms", "frame_placements"},
     {"--frames: 'tool0,,ee_link' has an empty name"}},
    // CLI11 would take the next option as the value
    {"FramesEqualsNothing", models + "/ur5.urdf",
     {"--frames=", "--algorithms", "frame_placements"}, {"--frames: no value after the ="}},
    {"FramesBeforeAnOption", models + "/ur5.urdf",
     {"--frames", "--algorithms", "frame_placements"},
     {"--frames: no value before --algorithms, which is an option"}},
    {"LanesInC", models + "/ur5.urdf", {"--structure", "lanes", "--lang", "c"},
     {"--structure lanes: vector lanes are C++", "with --lang c choose auto, shared or unrolled"}},
    {"NearMissOption", models + "/ur5.urdf", {"--floating"},
     {"unknown option --floating (did you mean --floating-base?)"}},
    {"NearMissOptions", models + "/ur5.urdf", {"--lock-masless", "--bogus=1"},
     {"unknown options --lock-masless (did you mean --lock-massless?), --bogus\n"}},
    {"JacobianFrameUnknown", models + "/ur5.urdf", {"--jacobian-frame", "body"},
     {"--jacobian-frame", "body"}},
    {"UnknownOption", models + "/ur5.urdf", {"--bogus"}, {"--bogus", "--help"}},
    {"SnapNotANumber", models + "/ur5.urdf", {"--snap", "abc"},
     {"--snap: 'abc' is not a finite number"}},
    {"SnapNan", models + "/ur5.urdf", {"--snap", "nan"}, {"--snap: 'nan' is not a finite number"}},
    {"SnapTooLarge", models + "/ur5.urdf", {"--snap", "0.5"},
     {"--snap: 0.5 is not between 0 and 0.001"}},
    {"ArmatureWithoutValue", models + "/ur5.urdf", {"--armature", "elbow_joint"},
     {"--armature elbow_joint: expected JOINT=VALUE, or all=VALUE"}},
    {"ArmatureNotANumber", models + "/ur5.urdf", {"--armature", "elbow_joint=heavy"},
     {"--armature elbow_joint=heavy: 'heavy' is not a finite number"}},
    {"ArmatureUnknownJoint", models + "/ur5.urdf", {"--armature", "knee=0.1"},
     {"ur5.urdf: cannot give joint 'knee' an armature: no joint of that name"}},
    {"ArmatureNegative", models + "/ur5.urdf", {"--armature", "all=-0.1"},
     {"ur5.urdf: joint 'shoulder_pan_joint': the armature -0.1 kg m^2 is negative"}},
    {"ArmatureOnAFixedJoint", models + "/ur5.urdf", {"--armature", "ee_fixed_joint=0.1"},
     {"joint 'ee_fixed_joint' is fixed: only a revolute, prismatic, planar or ball joint has "
      "an armature"}},
    {"GravityAndNoGravity", models + "/ur5.urdf", {"--gravity", "0,0,1", "--no-gravity"},
     {"--gravity excludes --no-gravity"}},
    {"GravityOverflowing", models + "/ur5.urdf", {"--gravity", "0,0,1e308"},
     {"--gravity: gravity (0, 0, 1e+308) m/s^2 exceeds 1e+50 in magnitude"}},
    {"ConstantBeyondFloat", bad + "/huge_for_float.yaml", {"--scalar", "float"},
     {"huge_for_float.yaml: in float, link 'link1': the mass 1e+39 kg exceeds 3.40282e+38",
      "--scalar double"}},
    {"FloatOverflowInTheTrace", bad + "/float_overflow.yaml",
     {"--scalar", "float", "--algorithms", "aba"},
     {"float_overflow.yaml: aba overflows in float: it computes inf from the model's constants",
      "at link 'link1' (acceleration pass)", "--scalar double"}},
    // constraints: links that are not there or cannot move, a kind other than 3d and 6d (read as
    // part of the name), gains and restitution out of range, algorithms that need constraints
    {"ContactUnknownLink", models + "/ur5.urdf", {"--contacts", "tool0,toe"},
     {"--contacts toe: no link named 'toe'", "'tool0'"}},
    {"ContactUnknownKind", models + "/ur5.urdf", {"--contacts", "tool0:5d"},
     {"--contacts tool0:5d: no link named 'tool0:5d'"}},
    {"ContactOnTheFixedBase", models + "/ur5.urdf", {"--contacts", "base_link"},
     {"--contacts base_link: link 'base_link' is welded to the fixed base, so a contact there "
      "constrains nothing"}},
    {"ContactTwice", models + "/ur5.urdf", {"--contacts", "tool0:3d,tool0:6d"},
     {"--contacts: link 'tool0' is given twice"}},
    {"ContactsEmptyItem", models + "/ur5.urdf", {"--contacts", "tool0,"},
     {"--contacts: 'tool0,' has an empty name"}},
    {"BaumgarteOneGain", models + "/ur5.urdf", {"--contacts", "tool0", "--baumgarte", "10"},
     {"--baumgarte 10: expected KP,KD"}},
    {"BaumgarteNegative", models + "/ur5.urdf", {"--contacts", "tool0", "--baumgarte", "10,-1"},
     {"--baumgarte 10,-1: '-1' is not a finite number >= 0"}},
    {"RestitutionAboveOne", models + "/ur5.urdf", {"--contacts", "tool0", "--restitution", "1.5"},
     {"--restitution: 1.5 is not between 0 and 1"}},
    {"ContactDynamicsWithoutContacts", models + "/ur5.urdf",
     {"--algorithms", "rnea,contact_dynamics"},
     {"--algorithms: contact_dynamics needs constraints: give --contacts LINK[:3d|:6d],... or a "
      "chain spec with loops"}},
    // constants within float's range, products beyond it at the check's random states
    {"FloatOverflowAtTypicalStates", bad + "/float_overflow_typical.yaml", {"--scalar", "float"},
     {"float_overflow_typical.yaml: rnea overflows in float at typical states",
      "a product at link 'l1' (forward pass) reaches", "beyond float's largest number 3.4e+38",
      "--scalar double", "leave rnea out"}},
};

// Command-line mistakes are errors like bad input: `dyngen: error:` and exit status 1 (CLI11's
// own exit codes are 105 to 114), for each command.
TEST_F(Scratch, CommandLineMistakesExitWith1AndSaySo) {
  const std::string ur5 = models + "/ur5.urdf", out = (dir / "out").string();
  const std::vector<std::pair<std::vector<std::string>, std::string>> mistakes = {
      {{ur5}, "dyngen: error: --output is required"},
      {{ur5, "-o"}, "dyngen: error: "},
      {{"-o", out}, "dyngen: error: robot is required"},
      {{ur5, "-o", out, "--repetitions", "2"}, "dyngen: error: "},
      {{"eval", ur5}, "dyngen eval: error: --states is required"},
      {{"eval", ur5, "--states", "-", "--snap", "-1"}, "dyngen eval: error: --snap: -1 is not"},
      {{"report", ur5, "-o", out, "--states", "1.5"},
       "dyngen report: error: --states: '1.5' is not an integer"},
      {{"report", ur5, "-o", out, "--min-time", "nan"},
       "dyngen report: error: --min-time: 'nan' is not a finite number"},
      // a list is one value: the robot after it is not a link
      {{"--frames", "tool0", "ee_link", ur5, "-o", out},
       "dyngen: error: The following argument was not expected: " + ur5 +
           " (dyngen reads one robot file, here 'ee_link'; a list is one value, comma-separated"},
      // a near miss gets the option it misses, in every command
      {{"eval", ur5, "--states", "-", "--floting-base"},
       "dyngen eval: error: unknown option --floting-base (did you mean --floating-base?)"},
      {{"report", ur5, "-o", out, "--repetition", "3"},
       "dyngen report: error: unknown option --repetition (did you mean --repetitions?)"},
      {{"firmware-report", ur5, "-o", out, "--targt", "cortex-m7"},
       "dyngen firmware-report: error: unknown option --targt (did you mean --target?)"},
      // before the error it causes: without the option, -o is missing
      {{ur5, "--outptu", out}, "dyngen: error: unknown option --outptu (did you mean --output?)"},
  };
  for (const auto& [args, message] : mistakes) {
    const CliResult r = run_dyngen(args, dir);
    EXPECT_EQ(r.status, 1) << args.back();
    EXPECT_EQ(r.err.rfind(message, 0), 0u) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
  EXPECT_EQ(run_dyngen({"--help"}, dir).status, 0);
  EXPECT_EQ(run_dyngen({"--version"}, dir).status, 0);
  EXPECT_FALSE(fs::exists(dir / "out"));
}

// ---- options that work as a new user would expect

/// The banner's options line of a package.
std::string options_line(const fs::path& header) {
  const std::string text = read(header);
  const std::size_t at = text.find("// Options: ");
  return at == std::string::npos ? "" : text.substr(at, text.find('\n', at) - at);
}

TEST_F(Scratch, FramesAreTrimmedAndRecordedInTheBanner) {
  const CliResult r = run_dyngen({models + "/ur5.urdf", "-o", (dir / "out").string(), "--frames",
                                  " tool0 ,\tee_link", "--algorithms", "frame_placements"},
                                 dir);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\nframes: tool0, ee_link\n"), std::string::npos) << r.out;
  EXPECT_NE(read(dir / "out" / "ur5_dynamics.hpp")
                .find("frame_names[nframes] = {\n    \"tool0\",\n    \"ee_link\",\n};"),
            std::string::npos);
  EXPECT_TRUE(options_line(dir / "out" / "ur5_dynamics.hpp").ends_with(" --frames tool0,ee_link"));
}

TEST_F(Scratch, DefaultFramesAreSaidOnTheConsoleAndInTheBanner) {
  const CliResult r = run_dyngen(
      {models + "/ur5.urdf", "-o", (dir / "out").string(), "--algorithms", "frame_jacobians"}, dir);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\nframes: ee_link, tool0 (the default: the ends of the limbs, the leaf "
                       "links on the bodies that no moving joint hangs from"),
            std::string::npos)
      << r.out;
  EXPECT_TRUE(options_line(dir / "out" / "ur5_dynamics.hpp").ends_with(" --frames ee_link,tool0"));
}

TEST_F(Scratch, FramesWithoutAFrameAlgorithmAreAWarningAndNotInTheBanner) {
  const CliResult r =
      run_dyngen({models + "/ur5.urdf", "-q", "-o", (dir / "out").string(), "--frames", "tool0",
                  "--algorithms", "rnea"},
                 dir);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("dyngen: warning: --frames is ignored: none of the algorithms computes "
                       "frames (add one of frame_placements, frame_jacobians, "),
            std::string::npos)
      << r.err;
  const std::string options = options_line(dir / "out" / "ur5_dynamics.hpp");
  EXPECT_EQ(options.find("--frames"), std::string::npos) << options;
}

TEST_F(Scratch, SubnormalGravityIsAFiniteNumber) {
  // std::stod throws out_of_range on 1e-320, which was taken for "not finite"
  const CliResult r = run_dyngen({models + "/double_pendulum.urdf", "-q", "-o",
                                  (dir / "out").string(), "--gravity", "1e-320,0,-4.9e-324",
                                  "--algorithms", "rnea", "--name", "pendulum"},
                                 dir);
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string options = options_line(dir / "out" / "pendulum_dynamics.hpp");
  EXPECT_NE(options.find(" --gravity 1e-320,0,-5e-324 "), std::string::npos) << options;
}

/// The numbers in text, thousands separators dropped: "40,000 and 2" is {2, 40000}.
std::set<long> numbers_in(const std::string& text) {
  std::set<long> numbers;
  static const Pattern number(R"(\b[0-9][0-9,]*\b)");
  for (Groups g : number.find_all(text)) {
    std::erase(g[0], ',');
    numbers.insert(std::stol(g[0]));
  }
  return numbers;
}

TEST_F(Scratch, HelpAndReadmeGiveTheSameStructureRules) {
  // --structure's thresholds in --help and in README's option table: the same numbers
  const CliResult help = run_dyngen({"--help"}, dir);
  ASSERT_EQ(help.status, 0);
  const std::size_t option = help.out.find("--structure");
  ASSERT_NE(option, std::string::npos) << help.out;
  const std::string in_help = help.out.substr(option, help.out.find("\n  -", option) - option);
  const std::string readme = read(std::string(DYNGEN_SOURCE_DIR) + "/README.md");
  const std::size_t row = readme.find("| `--structure auto");
  ASSERT_NE(row, std::string::npos);
  const std::string in_readme = readme.substr(row, readme.find('\n', row) - row);
  EXPECT_EQ(numbers_in(in_help), numbers_in(in_readme)) << in_help << "\n" << in_readme;
  EXPECT_EQ(numbers_in(in_help),
            (std::set<long>{2, 4, static_cast<long>(dyngen::gen::min_shared_operations),
                            dyngen::gen::min_shared_function_operations,
                            dyngen::gen::max_lane_function_operations}));
}

TEST(Readme, UR5sDefaultFramesAreTheRealOnesInTheirOrder) {
  const std::string readme = read(std::string(DYNGEN_SOURCE_DIR) + "/README.md");
  const std::optional<Groups> m = Pattern(R"(by default [^(]*\(ur5: ([^)]*)\))").search(readme);
  ASSERT_TRUE(m);
  std::vector<std::string> said;
  for (const Groups& name : Pattern("`([^`]+)`").find_all((*m)[1])) said.push_back(name[1]);
  std::vector<std::string> real;
  const std::string ur5 = std::string(DYNGEN_SOURCE_DIR) + "/examples/ur5.urdf";
  for (const auto& f : load_robot(ur5).model.frames) real.push_back(f.name);
  EXPECT_EQ(said, real);
}

class BadRobot : public Scratch, public ::testing::WithParamInterface<Case> {};
class BadInput : public Scratch, public ::testing::WithParamInterface<Case> {};

TEST_P(BadRobot, LibraryThrowsInputErrorNamingFileElementAndProblem) {
  const Case& c = GetParam();
  const std::string message = library_error(c.robot, load_options(c.options));
  EXPECT_NE(message.find(c.robot), std::string::npos) << message;
  for (const std::string& part : c.expected)
    EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
}

TEST_P(BadInput, CommandFailsOnStderrAndCreatesNoOutput) {
  const Case& c = GetParam();
  std::vector<std::string> args{c.robot, "-o", (dir / "out").string()};
  args.insert(args.end(), c.options.begin(), c.options.end());
  const CliResult r = run_dyngen(args, dir);
  EXPECT_GT(r.status, 0) << "exit status (-1: did not exit normally)";
  for (const std::string& part : c.expected)
    EXPECT_NE(r.err.find(part), std::string::npos) << "'" << part << "' not in: " << r.err;
  EXPECT_EQ(r.out.find("error"), std::string::npos) << r.out;
  // nothing at all, not even a staging directory, is left next to the output path
  EXPECT_TRUE(entries_of(dir).empty()) << entries_of(dir).front();
}

TEST_P(BadRobot, CommandExitsWithStatus1AndTheLibrarysMessage) {
  const Case& c = GetParam();
  std::vector<std::string> args{c.robot, "-q", "-o", (dir / "out").string()};
  args.insert(args.end(), c.options.begin(), c.options.end());
  const CliResult r = run_dyngen(args, dir);
  EXPECT_EQ(r.status, 1);
  const std::string message = library_error(c.robot, load_options(c.options));
  EXPECT_NE(r.err.find("dyngen: error: " + message + "\n"), std::string::npos)
      << r.err << "\ndoes not hold: " << message;
}

TEST_P(BadInput, CommandExitsWithStatus1) {
  const Case& c = GetParam();
  std::vector<std::string> args{c.robot, "-q", "-o", (dir / "out").string()};
  args.insert(args.end(), c.options.begin(), c.options.end());
  EXPECT_EQ(run_dyngen(args, dir).status, 1);
}

TEST_P(BadInput, CommandLeavesAnExistingOutputDirectoryUntouched) {
  const Case& c = GetParam();
  const fs::path out = dir / "existing";
  fs::create_directories(out / "build");
  std::ofstream(out / "CMakeLists.txt") << "# the user's previous output\n";
  std::ofstream(out / "notes.txt") << "not dyngen's\n";
  std::ofstream(out / "build" / "CMakeCache.txt") << "CMAKE_BUILD_TYPE:STRING=Release\n";
  const auto before = snapshot(out);
  std::vector<std::string> args{c.robot, "-o", out.string()};
  args.insert(args.end(), c.options.begin(), c.options.end());
  const CliResult r = run_dyngen(args, dir);
  EXPECT_GT(r.status, 0);
  EXPECT_EQ(snapshot(out), before);
  EXPECT_EQ(entries_of(dir), std::vector<std::string>{"existing"});
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) { return info.param.name; }

INSTANTIATE_TEST_SUITE_P(Errors, BadRobot, ::testing::ValuesIn(bad_robots), case_name);
INSTANTIATE_TEST_SUITE_P(Robots, BadInput, ::testing::ValuesIn(bad_robots), case_name);
INSTANTIATE_TEST_SUITE_P(Options, BadInput, ::testing::ValuesIn(bad_options), case_name);

// ---- unreadable files: root reads everything, so these need an ordinary user

class Unreadable : public Scratch, public ::testing::WithParamInterface<std::string> {};

TEST_P(Unreadable, LibraryAndCommandSaySo) {
  if (geteuid() == 0) GTEST_SKIP() << "root can read a file without read permission";
  const fs::path robot = dir / ("robot" + GetParam());
  std::ofstream(robot) << read(GetParam() == ".urdf" ? models + "/double_pendulum.urdf"
                                                     : models + "/planar5.yaml");
  fs::permissions(robot, fs::perms::none);
  const std::string message = library_error(robot.string(), {});
  EXPECT_NE(message.find(robot.string() + ": cannot read the file"), std::string::npos)
      << message;
  const CliResult r = run_dyngen({robot.string(), "-o", (dir / "out").string()}, dir);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("cannot read the file"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

INSTANTIATE_TEST_SUITE_P(Errors, Unreadable, ::testing::Values(".urdf", ".yaml"),
                         [](const auto& info) { return info.param.substr(1); });

// ---- romeo: 24 hand and finger joints move no mass, so ABA is undefined

const std::set<std::string> romeo_hand_joints = {
    "LHand",     "LFinger12", "LFinger13", "LFinger21", "LFinger22", "LFinger23",
    "LFinger31", "LFinger32", "LFinger33", "LThumb1",   "LThumb2",   "LThumb3",
    "RHand",     "RFinger12", "RFinger13", "RFinger21", "RFinger22", "RFinger23",
    "RFinger31", "RFinger32", "RFinger33", "RThumb1",   "RThumb2",   "RThumb3"};

TEST(Romeo, AbaErrorListsExactlyTheHandJointsAndHowToLockThem) {
  const std::string message = library_error(models + "/romeo.urdf", independent_mimics());
  // the list is the first line, after "divide by zero): "
  const std::size_t from = message.find("): "), to = message.find(".\n");
  ASSERT_NE(from, std::string::npos) << message;
  ASSERT_NE(to, std::string::npos) << message;
  const std::string list = message.substr(from, to - from);
  std::set<std::string> listed;
  for (const Groups& quoted : Pattern("'([^']+)'").find_all(list)) listed.insert(quoted[1]);
  EXPECT_EQ(listed, romeo_hand_joints) << message;
  for (const std::string& joint : romeo_hand_joints)
    EXPECT_NE(message.find("--lock " + joint), std::string::npos) << joint;
}

TEST(Romeo, LockMasslessLocksTheHandJointsAndAbaGenerates) {
  LoadOptions load;
  load.lock_massless = true;  // locks every mimic joint too
  const Robot robot = load_robot(models + "/romeo.urdf", load);
  EXPECT_EQ(std::set<std::string>(robot.locked.begin(), robot.locked.end()), romeo_hand_joints);
  EXPECT_EQ(robot.model.nv, 55 - 24);
  GenerateOptions options;
  options.name = "romeo";
  const Generated generated = generate(robot, options);
  ASSERT_EQ(generated.counts.size(), 3u);
  EXPECT_EQ(generated.counts[2].algorithm, "aba");
}

TEST(Romeo, RneaAndCrbaAloneGenerateWithEveryJoint) {
  const Robot robot = load_robot(models + "/romeo.urdf", independent_mimics());
  EXPECT_EQ(robot.model.nv, 55);
  GenerateOptions options;
  options.name = "romeo";
  options.algorithms = {"rnea", "crba"};
  EXPECT_EQ(generate(robot, options).counts.size(), 2u);
}

// asked for only algorithms that divide by ABA's pivots, the error suggests the default set's
// well-defined ones
TEST(Romeo, OnlyPivotingAlgorithmsSuggestTheDefaultsWithoutThem) {
  const Robot robot = load_robot(models + "/romeo.urdf", independent_mimics());
  GenerateOptions options;
  options.name = "romeo";
  options.algorithms = {"aba", "minv"};
  try {
    generate(robot, options);
    ADD_FAILURE() << "generated";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("or leave aba, minv out (--algorithms rnea,crba);"),
              std::string::npos)
        << e.what();
  }
}

using RomeoCommand = Scratch;

TEST_F(RomeoCommand, SucceedsWithLockMasslessOrWithoutAba) {
  for (const std::vector<std::string>& options :
       {std::vector<std::string>{"--lock-massless"},
        {"--mimic-independent", "--algorithms", "rnea,crba"}}) {
    const fs::path out = dir / ("out" + options.back());
    std::vector<std::string> args{models + "/romeo.urdf", "-q", "-o", out.string()};
    args.insert(args.end(), options.begin(), options.end());
    const CliResult r = run_dyngen(args, dir);
    EXPECT_EQ(r.status, 0) << options.back() << ": " << r.err;
    EXPECT_EQ(r.err.find("error"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::is_regular_file(out / "romeo_dynamics.cpp")) << options.back();
  }
}

// ---- warnings: accepted, reported, output written

const std::vector<std::vector<std::string>> imperfect_warnings = {
    {"link 'upper'", "break the triangle inequality"},
    {"links without <inertial>", "'sensor_frame'"},
    {"<gazebo> is not used"},
    {"<transmission> is not used"},
    {"<drake:collision_filter_group> is not used"},
    {"<drake:rotor_inertia> in <joint> is not used"},
    {"mimic joints treated as independent joints", "'follower' (mimics 'elbow')"},
};

TEST(Warnings, ImperfectUrdfLoadsWithOneWarningPerOddity) {
  const std::string path = bad + "/imperfect.urdf";
  const Robot robot = load_robot(path, independent_mimics());
  EXPECT_EQ(robot.model.nv, 3) << "the mimic joint is an independent joint";
  EXPECT_EQ(robot.warnings.size(), imperfect_warnings.size());
  for (const std::string& w : robot.warnings) EXPECT_EQ(w.rfind(path + ": ", 0), 0u) << w;
  for (const auto& parts : imperfect_warnings) {
    const bool found = std::any_of(robot.warnings.begin(), robot.warnings.end(), [&](auto& w) {
      return std::all_of(parts.begin(), parts.end(),
                         [&](auto& p) { return w.find(p) != std::string::npos; });
    });
    EXPECT_TRUE(found) << "no warning with '" << parts[0] << "'";
  }
}

TEST(Warnings, CleanRobotHasNone) {
  EXPECT_TRUE(load_robot(models + "/planar5.yaml").warnings.empty());
}

// Constraints whose rows depend on each other are solved (minimum-norm forces) with a warning
// that names them: four feet in 6d lock solo12 with 24 rows for 18 degrees of freedom, and the
// four-bar's planar loop has a row along z that holds by itself; four point feet do not.
TEST(Warnings, DependentConstraintsAreNamed) {
  const auto dependent = [](const std::string& path, std::vector<std::string> contacts) {
    LoadOptions options;
    options.floating_base = !contacts.empty();
    options.contacts = std::move(contacts);
    for (const std::string& w : load_robot(path, options).warnings)
      if (w.find("are not independent") != std::string::npos) return w;
    return std::string();
  };
  const std::string solo12 = models + "/solo12.urdf";
  const std::string six =
      dependent(solo12, {"FL_FOOT:6d", "FR_FOOT:6d", "HL_FOOT:6d", "HR_FOOT:6d"});
  EXPECT_NE(six.find("the rows of the constraints FL_FOOT:6d, FR_FOOT:6d, HL_FOOT:6d, "
                     "HR_FOOT:6d are not independent (24 rows in all)"),
            std::string::npos)
      << six;
  EXPECT_NE(six.find("minimum-norm lambda"), std::string::npos) << six;
  EXPECT_NE(six.find("damped by 1e-10"), std::string::npos) << six;
  EXPECT_EQ(dependent(solo12, {"FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"}), "");
  const std::string loop =
      dependent(std::string(DYNGEN_SOURCE_DIR) + "/examples/closed_loop/four_bar.yaml", {});
  EXPECT_NE(loop.find("constraints rocker-base:3d are not independent (3 rows in all)"),
            std::string::npos)
      << loop;
}

using WarningsCommand = Scratch;

// An axis is a direction: one of any finite length is normalised (with a warning), not only one
// whose squared length is a normal number.
TEST_F(WarningsCommand, AxesOfAnyFiniteLengthAreDirections) {
  for (const std::string axis : {"1e300 0 0", "1e200 1e200 0", "1e-200 0 0", "0 -1e-310 0"}) {
    std::string text = read(bad + "/zero_axis.urdf");
    text.replace(text.find("<axis xyz=\"0 0 0\"/>"), 20, "<axis xyz=\"" + axis + "\"/>");
    const fs::path robot = dir / "axis.urdf";
    std::ofstream(robot) << text;
    const CliResult r = run_dyngen({robot.string(), "-q", "-o", (dir / "out").string()}, dir);
    EXPECT_EQ(r.status, 0) << axis << ": " << r.err;
    EXPECT_NE(r.err.find("joint 'shoulder': axis ("), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("it is normalised"), std::string::npos) << r.err;
    fs::remove_all(dir / "out");
  }
}

TEST_F(WarningsCommand, PrintedOnStderrEvenWhenQuietAndOutputWritten) {
  const CliResult r =
      run_dyngen({bad + "/imperfect.urdf", "--mimic-independent", "-q", "-o", (dir / "out").string()},
                 dir);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  std::size_t lines = 0;
  for (std::size_t at = r.err.find("dyngen: warning: "); at != std::string::npos;
       at = r.err.find("dyngen: warning: ", at + 1))
    ++lines;
  EXPECT_EQ(lines, imperfect_warnings.size()) << r.err;
  EXPECT_TRUE(fs::is_regular_file(dir / "out" / "imperfect_dynamics.cpp"));
}

// ---- frame_jacobians' limits (README, "Limits")

/// A chain spec of n unit links.
std::string chain_of(int n) {
  std::string text = "name: chain\nlinks:\n";
  for (int i = 0; i < n; ++i) text += "  - {mass: 1, length: 0.1}\n";
  return text;
}

/// The InputError of generating `algorithm` for the robot, or "(none)".
std::string generation_error(const Robot& robot, const std::string& algorithm) {
  GenerateOptions options;
  options.name = "robot";
  options.algorithms = {algorithm};
  try {
    generate(robot, options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(none)";
}

// A star of 1001 links on one base, with the frames of its 1001 leaves: 6 x 1001 entries each,
// 6,012,006 in all, above the limit of 6 million, refused before any tracing; nothing written.
TEST_F(Scratch, FrameJacobiansRefusedAboveTheirEntries) {
  std::string star = "<robot name=\"star\">\n  <link name=\"base\"/>\n";
  for (int i = 1; i <= 1001; ++i) {
    const std::string n = std::to_string(i);
    star += "  <link name=\"l" + n +
            "\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" "
            "ixz=\"0\" iyz=\"0\"/></inertial></link>\n  <joint name=\"j" + n +
            "\" type=\"continuous\"><parent link=\"base\"/><child link=\"l" + n +
            "\"/><axis xyz=\"0 0 1\"/></joint>\n";
  }
  std::ofstream(dir / "star.urdf") << star << "</robot>\n";
  const CliResult r = run_dyngen({(dir / "star.urdf").string(), "-o", (dir / "out").string(),
                                  "--algorithms", "rnea,frame_jacobians"},
                                 dir);
  EXPECT_EQ(r.status, 1);
  for (const char* part :
       {"star.urdf: frame_jacobians for 1001 frames of 1001 degrees of freedom would fill "
        "6012006 entries (frames times 6 nv), above dyngen's limit of 6000000",
        "name fewer frames (--frames)"})
    EXPECT_NE(r.err.find(part), std::string::npos) << part << " not in " << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

// A frame on every link of a 500-link chain: 1 + 2 + ... + 500 = 125,250 Jacobian columns,
// above the limit of 125,000, in either axes; the tip's frame alone on a chain of 600 (beyond
// CRBA's limit, 179,700 steps) is 600 columns and generates.
TEST(FrameLimits, FrameJacobiansRefusedAboveTheirColumns) {
  LoadOptions every_frame;
  every_frame.all_frames = true;
  const Robot chain = parse_robot("chain.yaml", chain_of(500), every_frame);
  for (const char* algorithm : {"frame_jacobians", "frame_jacobians_local"}) {
    const std::string e = generation_error(chain, algorithm);
    for (const std::string& part :
         {std::string("chain.yaml: ") + algorithm, std::string("125250 Jacobian columns"),
          std::string("above dyngen's limit of 125000"), std::string("--frames")})
      EXPECT_NE(e.find(part), std::string::npos) << part << " not in " << e;
  }
  EXPECT_EQ(generation_error(parse_robot("chain.yaml", chain_of(600), {}), "frame_jacobians"),
            "(none)");
  EXPECT_NE(generation_error(parse_robot("chain.yaml", chain_of(600), {}), "crba"), "(none)");
}

}  // namespace
