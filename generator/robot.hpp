// Reading a robot: URDF (through urdfdom) or a chain spec (YAML), chosen by readers.hpp, checked,
// with the requested joints locked, built into the runtime's Model by the runtime's own builder.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "dyngen/model.hpp"
#include "dyngen/model_builder.hpp"

namespace dyngen::gen {

/// Bad input: the message names the file, the element and the problem.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A file or directory that cannot be written, or that dyngen will not overwrite: the message
/// names the path and the reason. Like bad input, the user's to fix.
struct FileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A parsed robot before canonicalisation.
struct RobotDescription {
  std::string name;
  ModelBuilder builder;
  std::optional<Vec3<double>> gravity;  // a chain spec may set it
  std::vector<std::string> warnings;
  /// URDF's <mimic> joints: joint follows q = multiplier q_mimicked + offset
  struct Mimic {
    std::string joint, mimicked;
    double multiplier = 1, offset = 0;
  };
  std::vector<Mimic> mimics;
  /// The root link is the world, whose bodies float by their own free joints (MJCF), not a
  /// robot link that --floating-base could put on one.
  bool root_is_world = false;
  /// Loop closures (a chain spec's loops): the point at xyz in link a's frame held to the point
  /// at xyz in link b's, and with six_d their orientations too.
  struct Loop {
    std::string link_a, link_b;
    Vec3<double> xyz_a{}, xyz_b{};
    bool six_d = false;
  };
  std::vector<Loop> loops;
  /// The moving joints in the order Pinocchio's URDF parser gives them coordinates, or empty
  /// with the reason in pinocchio_missing (README, "Coordinates beside Pinocchio's").
  std::vector<std::string> pinocchio_order;
  std::string pinocchio_missing = "the input is not a URDF";
};

/// A file's bytes; InputError naming the path and the system's reason when it cannot be read.
std::string read_file(const std::string& path);

struct LoadOptions {
  std::vector<std::string> lock;        // joints to turn into fixed ones
  bool lock_massless = false;           // also lock every joint whose subtree has no mass
  std::optional<Vec3<double>> gravity;  // overrides the file's and the default
  bool floating_base = false;           // the root link on a free joint
  bool mimic_independent = false;       // URDF mimic joints as independent joints (Model::mimic)
  std::optional<double> snap;           // snap constants within this tolerance (snap())
  std::vector<std::string> frames;      // the links whose frames to keep, in this order
                                        // (--frames); none named: default_frames_rule
  bool all_frames = false;              // keep every link's frame
  /// Rotor inertias (--armature), in the order given: (joint, value), joint "all" for every
  /// revolute, prismatic and planar joint.
  std::vector<std::pair<std::string, double>> armature;
  /// Contacts (--contacts): "FRAME", "FRAME:3d" or "FRAME:6d", a link held to the world; and
  /// the settings of the constrained algorithms (--baumgarte, --restitution).
  std::vector<std::string> contacts;
  ConstraintSettings<double> constraint_settings;
};

struct Robot {
  std::string path;
  std::string format;  // its reader's: "URDF", "MJCF", ...
  std::string name;
  std::string sha256;  // of the input file's bytes
  Model<double> model;
  std::vector<std::string> locked;  // joints locked, in the order given
  std::vector<std::string> warnings;
  std::optional<SnapReport> snapped;  // with LoadOptions::snap
  std::vector<std::string> pinocchio_order;  // RobotDescription's
  std::string pinocchio_missing;
};

inline constexpr Vec3<double> default_gravity{0, 0, -9.81};

/// The frames kept when --frames names none, in words (--help and the console say it): the
/// sensors and rotors on the trunk and along the limbs are left out.
inline constexpr const char* default_frames_rule =
    "the ends of the limbs, the leaf links on the bodies that no moving joint hangs from (tool "
    "flanges, feet, fingertips)";

/// The largest robot dyngen takes (README, "Limits"): joints in the file (and links, one more),
/// and degrees of freedom (entries of v); what the largest cost to generate and evaluate is in
/// the README's table.
inline constexpr int max_joints = 10000, max_nv = 10000;

/// Reads a robot file in one of the formats of readers.hpp and builds its model.
Robot load_robot(const std::string& path, const LoadOptions& options = {});

/// The same for a file's text, read from `path` (whose extension, and for .xml the root
/// element, says the format).
Robot parse_robot(const std::string& path, const std::string& text, const LoadOptions& options);

/// Rows of the constraints that depend on the others at sampled states (their rank falls short
/// of their rows): the names of the constraints that take part, empty when the rows are
/// independent. contact_dynamics then returns the minimum-norm lambda of the proximal solve.
std::vector<std::string> redundant_constraints(const Model<double>& model);

/// Joints whose articulated inertia D vanishes (ABA would divide by zero): D <= 1e-12 of the
/// joint's own mass-matrix diagonal at any of a few sampled states. Joints above them, whose
/// D the division by zero turns into NaN, are not listed.
std::vector<int> joints_moving_no_mass(const Model<double>& model);

/// Joints whose whole subtree has zero mass and inertia.
std::vector<int> joints_with_massless_subtree(const Model<double>& model);

/// The joints that make ABA undefined, both kinds above (less the massless ones with an armature,
/// which is their pivot), in body order (empty: ABA is defined).
std::vector<int> joints_blocking_aba(const Model<double>& model);

/// 'a', 'b', 'c': the names of the joints.
std::string joint_list(const Model<double>& model, const std::vector<int>& joints);

/// Why ABA is undefined for the model (joints_blocking_aba), with the ways out that fit each
/// joint, or "" when it is defined: "ABA is undefined for this robot: ... .\nLock them (...),
/// ...". Callers add their own last way out (", or leave ABA out ...").
std::string aba_undefined_reason(const Model<double>& model);

/// The same for the model with its constants rounded to float, where inertias below float's
/// range become zero.
std::vector<int> joints_blocking_aba_in_float(const Model<double>& model);

}  // namespace dyngen::gen
