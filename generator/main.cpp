// dyngen ROBOT -o DIR: reads a robot, traces the runtime's algorithms for it and writes the
// specialised code, the model tables, the bit-for-bit check and a CMakeLists.txt.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string_view>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "backend.hpp"
#include "eval.hpp"
#include "firmware_report.hpp"
#include "generate.hpp"
#include "process.hpp"
#include "readers.hpp"
#include "report.hpp"

using namespace dyngen;
using namespace dyngen::gen;

namespace {

/// text as a finite number, or nothing: strtod, not std::stod, which throws out_of_range on a
/// subnormal number such as 1e-320.
std::optional<double> finite_number(const std::string& text) {
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(x)) return {};
  return x;
}

Vec3<double> parse_gravity(const std::string& text) {
  std::vector<double> g;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) {
    const std::optional<double> x = finite_number(item);
    if (!x) throw InputError(fmt::format("--gravity {}: '{}' is not a finite number", text, item));
    g.push_back(*x);
  }
  if (g.size() != 3)
    throw InputError(fmt::format("--gravity {}: expected three numbers x,y,z", text));
  return {g[0], g[1], g[2]};
}

/// The algorithms fitted to the model's constraints (listed: --algorithms' text, "" when not
/// given): without constraints, "all" leaves out those that need them and naming one is an
/// error; with them, the default set gains contact_dynamics and impulse_dynamics, and
/// contact_dynamics_anchored where Baumgarte's kp would act on a contact.
std::vector<Algorithm> with_constraints(std::vector<Algorithm> algorithms,
                                        const Model<double>& model, const std::string& listed) {
  const auto needs = [](const Algorithm& a) {
    return algorithm_spec(a).needs == Needs::Constraints;
  };
  if (model.nc == 0) {
    const auto it = std::find_if(algorithms.begin(), algorithms.end(), needs);
    if (it != algorithms.end() && listed != "all")
      throw InputError(
          fmt::format("--algorithms: {} needs constraints: give --contacts LINK[:3d|:6d],... "
                      "or a chain spec with loops",
                      *it));
    std::erase_if(algorithms, needs);
    return algorithms;
  }
  if (!listed.empty()) return algorithms;
  // derivatives on request only, as without constraints
  const bool anchored =
      model.constraint_settings.kp > 0 &&
      std::ranges::any_of(model.constraints, [](const auto& k) { return !k.loop; });
  std::vector<Algorithm> out;
  for (const Algorithm& a : algorithm_names())
    if ((needs(a) && !a.ends_with("_derivatives") &&
         (a != "contact_dynamics_anchored" || anchored)) ||
        std::find(algorithms.begin(), algorithms.end(), a) != algorithms.end())
      out.push_back(a);
  return out;
}

/// --baumgarte KP,KD: two finite non-negative gains.
std::pair<double, double> parse_baumgarte(const std::string& text) {
  std::vector<double> k;
  std::stringstream s(text);
  for (std::string item; std::getline(s, item, ',');) {
    const std::optional<double> x = finite_number(item);
    if (!x || *x < 0)
      throw InputError(fmt::format("--baumgarte {}: '{}' is not a finite number >= 0",
                                   safe_text(text), safe_text(item)));
    k.push_back(*x);
  }
  if (k.size() != 2)
    throw InputError(fmt::format("--baumgarte {}: expected KP,KD", safe_text(text)));
  return {k[0], k[1]};
}

/// --armature JOINT=VALUE: the joint (up to the last '=', so a name may hold one) and a finite
/// number.
std::pair<std::string, double> parse_armature(const std::string& text) {
  const std::size_t at = text.rfind('=');
  if (at == std::string::npos || at == 0)
    throw InputError(fmt::format("--armature {}: expected JOINT=VALUE, or all=VALUE",
                                 safe_text(text)));
  const std::string value = text.substr(at + 1);
  const std::optional<double> x = finite_number(value);
  if (!x)
    throw InputError(fmt::format("--armature {}: '{}' is not a finite number", safe_text(text),
                                 safe_text(value)));
  return {text.substr(0, at), *x};
}

/// The suffix of the algorithms that give in a frame's own axes what the algorithm without it
/// gives in the base's (frame_jacobians_local beside frame_jacobians).
constexpr std::string_view local_suffix = "_local";

bool is_local_variant(const Algorithm& a, const std::vector<Algorithm>& known) {
  return a.ends_with(local_suffix) &&
         std::find(known.begin(), known.end(), a.substr(0, a.size() - local_suffix.size())) !=
             known.end();
}

/// The comma-separated list of names in `known`, in `known`'s order whatever the order written;
/// "all" for every one but the local-axes variants, which --jacobian-frame adds. Errors quote
/// `written`, what the user wrote (text with the default set added: with_defaults).
std::vector<Algorithm> parse_algorithms(const std::string& text,
                                        const std::vector<Algorithm>& known,
                                        const std::string& written = "") {
  std::string names;
  for (const Algorithm& a : known) names += (names.empty() ? "" : ", ") + a;
  if (text == "all") {
    std::vector<Algorithm> out;
    for (const Algorithm& a : known)
      if (!is_local_variant(a, known)) out.push_back(a);
    return out;
  }
  std::vector<Algorithm> listed;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ','))
    if (std::find(known.begin(), known.end(), item) == known.end())
      throw InputError(fmt::format("--algorithms {}: unknown algorithm '{}' ({}, or all)",
                                   safe_text(written.empty() ? text : written), safe_text(item),
                                   names));
    else
      listed.push_back(item);
  if (listed.empty()) throw InputError("--algorithms: name at least one of " + names);
  // always in the same order, so the output does not depend on how the list was written
  std::vector<Algorithm> out;
  for (const Algorithm& a : known)
    if (std::find(listed.begin(), listed.end(), a) != listed.end()) out.push_back(a);
  return out;
}

/// The algorithms with --jacobian-frame applied: each listed algorithm that has a local-axes
/// variant is replaced by it (local), kept (world) or joined by it (both), in `known`'s order.
std::vector<Algorithm> with_jacobian_frame(const std::vector<Algorithm>& listed,
                                           const std::string& frame,
                                           const std::vector<Algorithm>& known) {
  std::vector<Algorithm> chosen;
  for (const Algorithm& a : listed) {
    const Algorithm local = a + std::string(local_suffix);
    const bool has_local = std::find(known.begin(), known.end(), local) != known.end();
    if (!has_local || frame != "local") chosen.push_back(a);
    if (has_local && frame != "world") chosen.push_back(local);
  }
  std::vector<Algorithm> out;
  for (const Algorithm& a : known)
    if (std::find(chosen.begin(), chosen.end(), a) != chosen.end()) out.push_back(a);
  return out;
}

std::string comma_list(const std::vector<Algorithm>& names) {
  std::string text;
  for (const Algorithm& a : names) text += (text.empty() ? "" : ",") + a;
  return text;
}

/// --algorithms' text with the default set written out: "+a,+b" adds a and b to `defaults`
/// (every item then starts with '+'); any other text is returned as it is.
std::string with_defaults(const std::string& text, const std::vector<Algorithm>& defaults) {
  if (!text.starts_with('+')) {
    if (text.find(",+") != std::string::npos)
      throw InputError(fmt::format(
          "--algorithms {}: either name the whole set (rnea,crba) or add to the default set "
          "(+rnea_derivatives), not both",
          safe_text(text)));
    return text;
  }
  std::string out = comma_list(defaults);
  std::stringstream s(text);
  for (std::string item; std::getline(s, item, ',');) {
    if (!item.starts_with('+') || item.size() == 1)
      throw InputError(fmt::format(
          "--algorithms {}: '{}': to add to the default set, start every name with +",
          safe_text(text), safe_text(item)));
    out += "," + item.substr(1);
  }
  return out;
}

/// A number in [lo, hi] (an integer if `integer`): CLI11's Range lets NaN through (no
/// comparison with it is true) and calls a word "not in range".
CLI::Validator number_in(double lo, double hi, bool integer = false) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        const std::optional<double> x = finite_number(text);
        if (!x || (integer && *x != std::floor(*x)))
          return fmt::format("'{}' is not {}", text, integer ? "an integer" : "a finite number");
        if (!(*x >= lo && *x <= hi)) return fmt::format("{} is not between {} and {}", text, lo, hi);
        return "";
      },
      fmt::format("{} in [{}, {}]", integer ? "INT" : "NUMBER", lo, hi));
}

/// The number of single-character edits that turn a into b (Levenshtein).
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = above;
    }
  }
  return row[b.size()];
}

/// The option of app that `word` (not one of them) is a slip for: the nearest by edits, if at
/// most a third of its letters differ, or one that begins with word (--floating for
/// --floating-base); "" when none is near.
std::string nearest_option(const CLI::App& app, const std::string& word) {
  std::string best;
  std::size_t best_distance = std::string::npos;
  for (const CLI::Option* option : app.get_options()) {
    std::vector<std::string> names;
    for (const std::string& n : option->get_lnames()) names.push_back("--" + n);
    for (const std::string& n : option->get_snames()) names.push_back("-" + n);
    for (const std::string& name : names) {
      const std::size_t d =
          name.starts_with(word) && word.size() >= 5 ? 1 : edit_distance(word, name);
      if (d <= name.size() / 3 && d < best_distance)
        best = name, best_distance = d;
    }
  }
  return best;
}

/// CLI11 takes the word after an option that needs a value, or after `--option=`, whatever that
/// word is: `--frames --algorithms all` would name a link --algorithms. A value that is missing
/// or is one of the command's options is an error here, naming both.
void check_option_values(const CLI::App& app, int argc, char** argv) {
  for (int k = 1; k < argc; ++k) {
    const std::string_view word = argv[k];
    if (word == "--") return;
    if (word.size() < 2 || word[0] != '-') continue;
    const std::size_t equals = word.find('=');
    const std::string name(word.substr(0, equals));
    const CLI::Option* option = app.get_option_no_throw(name);
    if (!option || option->get_items_expected_max() == 0) continue;  // a flag
    if (equals != std::string_view::npos) {
      if (equals + 1 == word.size())
        throw CLI::ValidationError(name, "no value after the =");
      continue;
    }
    if (k + 1 < argc && argv[k + 1][0] == '-') {
      const std::string_view next = argv[k + 1];
      if (app.get_option_no_throw(std::string(next.substr(0, next.find('=')))))
        throw CLI::ValidationError(name,
                                   fmt::format("no value before {}, which is an option", next));
    }
    ++k;
  }
}

/// The message of a command-line mistake: an unknown option first (with the one it is a slip
/// for), as the other errors often follow from it; an argument left over after the robot with
/// what was taken as the robot.
std::string parse_error_text(const CLI::App& app, const CLI::ParseError& e) {
  std::vector<std::string> unknown, extra;
  for (const std::string& word : app.remaining(false)) {
    // "-1,0,0" and "-.5" are numbers, not options
    const bool option = word.size() > 1 && word[0] == '-' &&
                        !std::isdigit(static_cast<unsigned char>(word[1])) && word[1] != '.';
    if (!option) {
      extra.push_back(word);
      continue;
    }
    const std::string name = word.substr(0, word.find('='));
    const std::string near = nearest_option(app, name);
    unknown.push_back(near.empty() ? name : fmt::format("{} (did you mean {}?)", name, near));
  }
  if (!unknown.empty())
    return fmt::format("unknown option{} {}", unknown.size() > 1 ? "s" : "",
                       fmt::join(unknown, ", "));
  const CLI::Option* robot = app.get_option_no_throw("robot");
  if (!extra.empty() && robot && robot->count() > 0)
    return fmt::format("{} ({} reads one robot file, here '{}'; a list is one value, "
                       "comma-separated: --frames tool0,ee_link)",
                       e.what(), app.get_name(), robot->results().front());
  return e.what();
}

/// Parses the command line. --help and --version print and give exit status 0; a mistake is
/// reported like bad input: `COMMAND: error: ...` and exit status 1. Empty when the command is to
/// run.
std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv) {
  try {
    check_option_values(app, argc, argv);
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    fmt::print(stderr, "{}: error: {}\nRun '{} --help' for the options.\n", app.get_name(),
               safe_text(parse_error_text(app, e)), app.get_name());
    return 1;
  }
  return std::nullopt;
}

/// Where find_package(dyngen) should look: beside the executable in a build tree, or
/// <prefix>/lib/cmake/dyngen for an installed one.
std::string package_dir() {
  std::error_code error;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) return "<dyngen build directory>";
  const std::filesystem::path bin = exe.parent_path();
  if (std::filesystem::exists(bin / "dyngenConfig.cmake")) return bin.string();
  const std::filesystem::path installed = bin.parent_path() / "lib" / "cmake" / "dyngen";
  if (std::filesystem::exists(installed / "dyngenConfig.cmake")) return installed.string();
  return "<dyngen build directory>";
}

/// The items of a comma-separated list, blanks around each trimmed: "a, b" is a and b.
std::vector<std::string> split_names(const std::string& text) {
  std::vector<std::string> names;
  std::stringstream s(text);
  for (std::string item; std::getline(s, item, ',');) {
    const std::size_t first = item.find_first_not_of(" \t"), last = item.find_last_not_of(" \t");
    names.push_back(first == std::string::npos ? "" : item.substr(first, last - first + 1));
  }
  if (text.empty() || text.back() == ',') names.push_back("");  // getline drops the last
  return names;
}

/// --frames' check: a comma-separated list of links with none empty ("a,,b", ",", "a,").
CLI::Validator link_list() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const std::vector<std::string> names = split_names(text);
        if (std::find(names.begin(), names.end(), "") == names.end()) return "";
        return fmt::format("'{}' has an empty name: give links separated by commas, such as "
                           "tool0,ee_link",
                           text);
      },
      "");  // no description: --help shows the option's type name alone
}

/// The options that choose the model, shared by generation and eval.
struct ModelFlags {
  std::string gravity;
  std::vector<std::string> locks, frames, armature, contacts;
  bool no_gravity = false, lock_massless = false, floating_base = false, mimic_independent = false;
  std::optional<double> snap, restitution, damping;
  std::string baumgarte;
  /// --constraint-damping's default: float's rounding (1.2e-7 of A) would leave dependent rows'
  /// pivots near zero under double's 1e-10
  double default_damping = 1e-10;

  void add_to(CLI::App& app) {
    auto* gravity_opt = app.add_option("--gravity", gravity,
                                       "gravity x,y,z in m/s^2, base coordinates (default: the "
                                       "chain spec's or MJCF's <option gravity>, else "
                                       "0,0,-9.81)");
    app.add_flag("--no-gravity", no_gravity, "gravity 0,0,0")->excludes(gravity_opt);
    app.add_flag("--floating-base", floating_base,
                 "put the root link on a free 6-DoF joint (q: position, then unit quaternion "
                 "w,x,y,z; v: linear, then angular velocity in the base frame)");
    app.add_option("--lock", locks, "turn joint JOINT into a fixed joint at q = 0 (repeatable)")
        ->type_name("JOINT");
    app.add_flag("--lock-massless", lock_massless, "lock every joint whose subtree has no mass");
    app.add_option("--armature", armature,
                   "rotor inertia of joint JOINT (kg m^2 about a revolute axis or each of a ball "
                   "joint's, kg along a prismatic one), added to M's diagonal; JOINT all: every "
                   "revolute, prismatic, planar and ball joint, before the others given "
                   "(repeatable)")
        ->type_name("JOINT=VALUE");
    app.add_flag("--mimic-independent", mimic_independent,
                 "treat URDF mimic joints as independent joints, each with its own q, v and tau "
                 "(by default a mimic joint follows its primary: q = multiplier q_primary + "
                 "offset, and has no coordinate of its own)");
    // one value, split here: a vector option would take the robot after it as a link too
    app.add_option_function<std::string>(
           "--frames", [this](const std::string& text) { frames = split_names(text); },
           "comma-separated links whose frames the frame functions compute, in this order "
           "(default: " + std::string(default_frames_rule) + ")")
        ->check(link_list())
        ->type_name("LINKS");
    app.add_option("--snap", snap,
                   "make rotation and axis entries within TOL of 0 or +-1, and inertia products "
                   "and offset components within TOL (relative) of 0, exact; changes the model "
                   "by at most TOL relative, and says so in the banner")
        ->type_name("TOL")
        ->check(number_in(0.0, 1e-3));
    app.add_option_function<std::string>(
           "--contacts", [this](const std::string& text) { contacts = split_names(text); },
           "comma-separated links held to the world, each LINK or LINK:3d (its origin does not "
           "accelerate) or LINK:6d (nor does it rotate); adds contact_dynamics and "
           "impulse_dynamics to the default algorithms")
        ->check(link_list())
        ->type_name("LINKS");
    app.add_option("--baumgarte", baumgarte,
                   "the constraints' Baumgarte gains KP,KD (1/s^2, 1/s): contact_dynamics holds "
                   "J qdd + Jdot v = -KD J v - KP e, e the position error of a loop closure "
                   "(default 0,0)")
        ->type_name("KP,KD");
    app.add_option("--restitution", restitution,
                   "impulse_dynamics' coefficient of restitution: J v_plus = -E J v_minus "
                   "(default 0, perfectly inelastic)")
        ->type_name("E")
        ->check(number_in(0.0, 1.0));
    app.add_option("--constraint-damping", damping,
                   "the proximal solve's damping mu, relative to the mean diagonal of J M^-1 J^T "
                   "(default 1e-10 in double, 1e-5 in float): the step that keeps dependent "
                   "constraints' lambda finite and minimum-norm")
        ->type_name("D")
        ->check(number_in(1e-14, 1e-2));
  }

  LoadOptions load_options() const {
    LoadOptions load;
    load.lock = locks;
    load.lock_massless = lock_massless;
    load.floating_base = floating_base;
    load.mimic_independent = mimic_independent;
    load.snap = snap;
    load.frames = frames;
    std::vector<std::pair<std::string, double>> all, named;
    for (const std::string& text : armature) {
      const auto entry = parse_armature(text);
      (entry.first == "all" ? all : named).push_back(entry);
    }
    load.armature = all;
    load.armature.insert(load.armature.end(), named.begin(), named.end());
    load.contacts = contacts;
    if (!baumgarte.empty())
      std::tie(load.constraint_settings.kp, load.constraint_settings.kd) =
          parse_baumgarte(baumgarte);
    if (restitution) load.constraint_settings.restitution = *restitution;
    load.constraint_settings.damping = damping.value_or(default_damping);
    if (no_gravity) load.gravity = Vec3<double>{0, 0, 0};
    if (!gravity.empty()) load.gravity = parse_gravity(gravity);
    return load;
  }

  /// The flags as dyngen's banner records them (gravity is recorded with its value).
  std::string text() const {
    std::string out;
    if (floating_base) out += " --floating-base";
    for (const std::string& j : locks) out += " --lock " + j;
    for (const std::string& a : armature) out += " --armature " + a;
    if (lock_massless) out += " --lock-massless";
    if (mimic_independent) out += " --mimic-independent";
    if (snap) out += fmt::format(" --snap {}", *snap);
    if (!contacts.empty()) out += " --contacts " + comma_list(contacts);
    if (!baumgarte.empty()) out += " --baumgarte " + baumgarte;
    if (restitution) out += fmt::format(" --restitution {}", *restitution);
    if (damping) out += fmt::format(" --constraint-damping {}", *damping);
    return out;
  }
};

/// The chosen frames as the banner records them, " --frames A,B", where a function computes
/// frames; and a warning when --frames names links and none does.
std::string frames_text(const Robot& robot, const ModelFlags& flags,
                        const std::vector<Algorithm>& algorithms, const char* command) {
  if (std::any_of(algorithms.begin(), algorithms.end(), uses_frames)) {
    std::vector<std::string> names;
    for (const Frame<double>& f : robot.model.frames) names.push_back(f.name);
    return " --frames " + comma_list(names);
  }
  if (!flags.frames.empty()) {
    std::vector<Algorithm> computing;
    for (const Algorithm& a : algorithm_names())
      if (uses_frames(a)) computing.push_back(a);
    fmt::print(stderr,
               "{}: warning: --frames is ignored: none of the algorithms computes frames (add "
               "one of {} to --algorithms)\n",
               command, fmt::join(computing, ", "));
  }
  return "";
}

/// The options that choose the code, shared by generation and firmware-report.
struct CodeFlags {
  std::string algorithms = comma_list(default_algorithm_names()), scalar = "double", name,
              structure = "auto", target = "host", lang = "c++", jacobian_frame = "world";
  int batch = 0;
  bool python = false, torch = false;
  CLI::Option* algorithms_given = nullptr;

  void add_to(CLI::App& app, bool firmware) {
    algorithms_given = app.add_option("--algorithms", algorithms,
                   "comma-separated subset of " + comma_list(algorithm_names()) +
                       ", or all (all but the _local variants, which --jacobian-frame chooses), "
                       "or +NAME,... to add to the default set")
        ->capture_default_str();
    app.add_option("--jacobian-frame", jacobian_frame,
                   "the axes of frame_jacobians and frame_accelerations: world (the base's axes "
                   "at the frame's origin), local (the frame's own axes: the functions named "
                   "_local) or both")
        ->check(CLI::IsMember({"world", "local", "both"}))
        ->capture_default_str();
    app.add_option("--scalar", scalar, "scalar type of the generated code")
        ->check(CLI::IsMember({"double", "float"}))
        ->capture_default_str();
    app.add_option("--name", name,
                   "file prefix, C++ namespace or C name prefix, and CMake target and option "
                   "prefix (default: the robot's name made an identifier that no header the "
                   "package includes defines: README, \"Names\")");
    app.add_option("--lang", lang, language_help())
        ->check(CLI::IsMember(language_names()))
        ->capture_default_str();
    app.add_option("--structure", structure,
                   fmt::format("shared: each section of {} operations or more (one link's work "
                               "in one pass) whose operations match another's up to constants "
                               "calls a function shared with it, over a table of their "
                               "constants; unrolled: every section in place; lanes (C++): every "
                               "section in place, and the sections of limbs at the same depth "
                               "that perform the same operations (a quadruped's legs, a "
                               "humanoid's left and right arms) computed together in vector "
                               "statements, 2 doubles or 4 floats to a statement; auto: on the "
                               "host, lanes (in C++) where a function's limbs repeat and it has "
                               "fewer than {} operations (as the banner counts them), else "
                               "shared in functions of {} operations or more and unrolled "
                               "below; on a Cortex-M target, shared (flash). The same "
                               "operations and bits in each",
                               min_shared_operations, max_lane_function_operations,
                               min_shared_function_operations))
        ->check(CLI::IsMember({"auto", "unrolled", "shared", "lanes"}))
        ->capture_default_str();
    if (firmware) {
      target = "cortex-m4f";
      app.add_option("--target", target, "the microcontroller, emulated by qemu")
          ->check(CLI::IsMember(std::vector<std::string>(std::begin(firmware_report_targets),
                                                         std::end(firmware_report_targets))))
          ->capture_default_str();
    } else {
      app.add_option("--batch", batch,
                     "also emit f_batch and f_many for each function: LANES states at once in "
                     "SIMD lanes (2, 4, 8 or 16; 4 doubles or 8 floats fill AVX2), bit for bit "
                     "with f in every lane; C++ only")
          ->check(CLI::IsMember({2, 4, 8, 16}))
          ->option_text("LANES");
      app.add_flag("--python", python,
                   "also write a Python module (pybind11, NumPy arrays of one or N states) over "
                   "the batch functions, which the package's CMake builds; --batch defaults to "
                   "4 for double and 8 for float");
      app.add_flag("--torch", torch,
                   "also write NAME_torch.py, PyTorch autograd functions over the Python module "
                   "(implies --python) whose backward calls the generated derivatives, which "
                   "the package gets; --algorithms defaults to " +
                       comma_list(torch_default_algorithms()));
      app.add_option("--target", target,
                     "the processor the code is for: dyngen warns where the scalar has no "
                     "hardware there (double on a Cortex-M4F or M33, whose FPU is "
                     "single-precision)")
          ->check(CLI::IsMember(std::vector<std::string>(std::begin(target_names),
                                                         std::end(target_names))))
          ->capture_default_str();
    }
  }

  /// Checks --name and --batch before the robot is read (so that a mistake costs no time).
  void check_options() const {
    GenerateOptions backends;
    backends.language = lang;
    backends.batch = batch;
    backends.python = python || torch;
    backends.torch = torch;
    const std::vector<std::unique_ptr<Backend>> package = package_backends(backends);
    if (structure == "lanes" && !package.front()->dialect()->lane_blocks())
      throw InputError(fmt::format("--structure lanes: vector lanes are C++ (GCC's and clang's "
                                   "vector types); with --lang {} choose auto, shared or unrolled",
                                   lang));
    if (!name.empty() && !is_identifier(name))
      throw InputError(fmt::format(
          "--name {}: not usable as a C++ namespace, C prefix and file prefix (it must be "
          "letters, digits and single underscores, start with a letter, have at most {} "
          "characters, not start with dyngen or cmake, and not be a C or C++ keyword or a name "
          "that the headers of generated code define: README, \"Names\"); for example --name {}",
          name, max_identifier, identifier(name)));
  }

  /// "functions: ...", the set generated, and what a list given whole left out of the default
  /// set (--algorithms rnea_derivatives drops rnea, crba and aba; +NAME adds instead).
  std::string functions_text(const std::vector<Algorithm>& generated) const {
    std::string text = fmt::format("functions: {}", fmt::join(generated, ", "));
    if (algorithms_given->count() == 0 || algorithms.starts_with('+') || algorithms == "all")
      return text + "\n";
    std::vector<Algorithm> left_out;
    for (const Algorithm& a : torch ? torch_default_algorithms() : default_algorithm_names())
      if (std::find(generated.begin(), generated.end(), a) == generated.end())
        left_out.push_back(a);
    if (left_out.empty()) return text + "\n";
    return text + fmt::format(" (not the default {}: --algorithms +NAME adds to the default set)\n",
                              fmt::join(left_out, ", "));
  }

  /// The options for generate(); `command` names who warns about --frames (frames_text).
  GenerateOptions options(const Robot& robot, const ModelFlags& model,
                          const char* command) const {
    GenerateOptions options;
    const std::vector<Algorithm> defaults =
        torch ? torch_default_algorithms() : default_algorithm_names();
    const bool given = algorithms_given->count() > 0, adding = given && algorithms.starts_with('+');
    const std::string listed = given ? with_defaults(algorithms, defaults) : comma_list(defaults);
    options.algorithms =
        with_jacobian_frame(parse_algorithms(listed, algorithm_names(), algorithms),
                            jacobian_frame, algorithm_names());
    if (torch) options.algorithms = with_torch_backwards(options.algorithms, algorithm_names());
    // added to, the default set gains the constraints' algorithms as it does untouched
    options.algorithms =
        with_constraints(options.algorithms, robot.model, given && !adding ? listed : "");
    options.single_precision = scalar == "float";
    options.language = lang;
    options.target = static_cast<Target>(
        std::find(std::begin(target_names), std::end(target_names), target) -
        std::begin(target_names));
    options.structure = structure == "shared"     ? Structure::Shared
                        : structure == "unrolled" ? Structure::Unrolled
                        : structure == "lanes"    ? Structure::Lanes
                        : options.target == Target::Host ? Structure::Auto
                                                         : Structure::Shared;
    options.measure = options.target != Target::Host;
    options.python = python || torch;
    options.torch = torch;
    options.batch = batch > 0 || !options.python ? batch : options.single_precision ? 8 : 4;
    options.name = identifier(name.empty() ? robot.name : name);
    const Vec3<double>& g = robot.model.gravity;
    options.options_text =
        fmt::format("--algorithms {} --scalar {} --lang {} --structure {} --target {} "
                    "--gravity {},{},{} --name {}",
                    comma_list(options.algorithms), scalar, lang, structure, target, g.x, g.y,
                    g.z, options.name) +
        (options.batch > 0 ? fmt::format(" --batch {}", options.batch) : "") +
        (torch ? " --torch" : python ? " --python" : "") + model.text() +
        frames_text(robot, model, options.algorithms, command);
    return options;
  }
};

/// The robot file read with the model options, its warnings printed; unless quiet, first
/// "dyngen VERSION COMMAND: reading FILE" (command: "" for the main one, " report", ...).
Robot read_robot(const std::string& input, const ModelFlags& flags, const char* command,
                 bool quiet) {
  if (!quiet) fmt::print("dyngen {}{}: reading {}\n", version, command, input);
  Robot robot = load_robot(input, flags.load_options());
  for (const std::string& w : robot.warnings)
    fmt::print(stderr, "dyngen: warning: {}\n", safe_text(w, true));
  return robot;
}

/// A subcommand's command line (argv[0] is its name) as a shell reads it back, for a report's
/// record: "dyngen", the subcommand and each argument, quoted where it must be.
std::string command_line(int argc, char** argv) {
  std::string text = "dyngen";
  for (int k = 0; k < argc; ++k) text += ' ' + shell_word(argv[k]);
  return text;
}

/// Runs a command's work, with its message on stderr after `command: error:`: bad input
/// (InputError) and files that cannot be read or written (FileError, or the file system's own
/// error) exit with 1, a failure of dyngen itself with 2.
template <class Work>
int run_reporting_errors(const char* command, Work work) {
  try {
    work();
  } catch (const InputError& e) {
    fmt::print(stderr, "{}: error: {}\n", command, safe_text(e.what(), true));
    return 1;
  } catch (const FileError& e) {
    fmt::print(stderr, "{}: error: {}\n", command, safe_text(e.what(), true));
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {
    fmt::print(stderr, "{}: error: {}: {}\n", command, safe_text(e.path1().string()),
               e.code().message());
    return 1;
  } catch (const std::bad_alloc&) {
    fmt::print(stderr, "{}: error: out of memory\n", command);
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}: error: {}\n", command, safe_text(e.what(), true));
    return 2;
  }
  return 0;
}

/// dyngen eval ROBOT --states FILE: the runtime's results as JSON on stdout.
int eval_main(int argc, char** argv) {
  CLI::App app{"dyngen eval: computes RNEA, CRBA and ABA with the runtime at the states in a JSON "
               "file and prints the results as JSON"};
  app.name("dyngen eval");
  std::string input, states;
  ModelFlags flags;
  app.add_option("robot", input, robot_file_formats())->required();
  app.add_option("--states", states,
                 "JSON array of states {\"q\": [...], \"v\": [...], \"a\": [...]} or with "
                 "\"tau\" instead of \"a\"; - reads standard input")
      ->required();
  bool derivatives = false;
  app.add_flag("--derivatives", derivatives,
               "add Minv, and the derivatives of ABA (dqdd_dq, dqdd_dv) where tau is given (with "
               "--contacts those of contact_dynamics: also dqdd_dtau and dlambda_dq, dlambda_dv, "
               "dlambda_dtau) and of RNEA (dtau_dq, dtau_dv) where a is given");
  bool regressor = false;
  app.add_flag("--regressor", regressor,
               "add Y, the inertial-parameter regressor (tau = Y pi + armature a), where a is "
               "given");
  flags.add_to(app);
  if (const auto status = parse_command_line(app, argc, argv)) return *status;
  return run_reporting_errors("dyngen eval", [&] {
    const Robot robot = read_robot(input, flags, " eval", true);
    evaluate(robot.model, states, stdout, {derivatives, !flags.frames.empty(), regressor});
  });
}

/// dyngen report ROBOT -o DIR: error against run time of every variant, as Markdown, JSON and a
/// plot.
int report_main(int argc, char** argv) {
  CLI::App app{"dyngen report: measures the error (against an MPFR reference) and the run time "
               "of each algorithm by the runtime and the generated code in double and float, "
               "with FMA and with -ffast-math, and of CRBA+LDLT, and writes report.md, "
               "report.json and report.svg"};
  app.name("dyngen report");
  std::string input, output, algorithms = comma_list(default_algorithm_names());
  ModelFlags flags;
  ReportOptions options;
  app.add_option("robot", input, robot_file_formats())->required();
  app.add_option("-o,--output", output,
                 "output directory (created if missing); the harness is built in DIR/harness")
      ->required();
  app.add_option("--algorithms", algorithms,
                 "comma-separated subset of " + comma_list(algorithm_names()) +
                     ", or all, or +NAME,... to add to the default set")
      ->capture_default_str();
  app.add_option("--states", options.states, "random states for the errors")
      ->check(number_in(1, 10000000, true))
      ->capture_default_str();
  app.add_option("--seed", options.seed, "seed of the random states")->capture_default_str();
  app.add_option("--min-time", options.min_time, "seconds per benchmark repetition")
      ->check(number_in(0.001, 60.0))
      ->capture_default_str();
  app.add_option("--repetitions", options.repetitions,
                 "benchmark repetitions; the time reported is their median")
      ->check(number_in(1, 1000, true))
      ->capture_default_str();
  flags.add_to(app);
  app.add_flag("--force", options.force,
               "write into DIR even when it holds files that dyngen report did not write (its "
               "report files and harness/ are replaced, the rest kept)");
  app.add_flag("-q,--quiet", options.quiet, "print errors and warnings only");
  if (const auto status = parse_command_line(app, argc, argv)) return *status;
  return run_reporting_errors("dyngen report", [&] {
    options.algorithms =
        parse_algorithms(with_defaults(algorithms, default_algorithm_names()), algorithm_names(),
                         algorithms);
    options.package_dir = package_dir();
    options.command = command_line(argc, argv);
    const Robot robot = read_robot(input, flags, " report", options.quiet);
    options.algorithms = with_constraints(options.algorithms, robot.model, algorithms);
    options.model_flags =
        flags.text() + frames_text(robot, flags, options.algorithms, "dyngen report");
    make_report(robot, options, output);
  });
}

/// dyngen firmware-report ROBOT -o DIR: the package on an emulated Cortex-M, measured.
int firmware_report_main(int argc, char** argv) {
  CLI::App app{"dyngen firmware-report: generates the package for a Cortex-M, cross-compiles it "
               "with a harness, runs it under qemu and on the host, and writes "
               "firmware-report.md and .json: per function its code bytes, stack bound and "
               "measured stack, instructions per call, and whether its outputs equal the host's "
               "bit for bit. Needs gcc-arm-none-eabi and qemu-system-arm."};
  app.name("dyngen firmware-report");
  std::string input, output;
  CodeFlags code;
  code.scalar = "float";
  ModelFlags flags;
  FirmwareReportOptions options;
  app.add_option("robot", input, robot_file_formats())->required();
  app.add_option("-o,--output", output,
                 "output directory (created if missing): the report, package/ and build/")
      ->required();
  code.add_to(app, true);
  app.add_option("--states", options.states, "states each function runs on")
      ->check(number_in(1, 9, true))
      ->capture_default_str();
  flags.add_to(app);
  app.add_flag("--force", options.force,
               "write into DIR even when it holds files that dyngen firmware-report did not "
               "write (its report files, package/ and build/ are replaced, the rest kept)");
  app.add_flag("-q,--quiet", options.quiet, "print errors and warnings only");
  if (const auto status = parse_command_line(app, argc, argv)) return *status;
  int status = 0;
  const int error = run_reporting_errors("dyngen firmware-report", [&] {
    code.check_options();
    options.command = command_line(argc, argv);
    const Robot robot = read_robot(input, flags, " firmware-report", options.quiet);
    options.generate = code.options(robot, flags, "dyngen firmware-report");
    const std::vector<std::string> failed = make_firmware_report(robot, options, output);
    for (const std::string& f : failed)
      fmt::print(stderr, "dyngen firmware-report: check failed: {}\n", safe_text(f, true));
    status = failed.empty() ? 0 : 3;
  });
  return error != 0 ? error : status;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string_view(argv[1]) == "eval") return eval_main(argc - 1, argv + 1);
  if (argc > 1 && std::string_view(argv[1]) == "report") return report_main(argc - 1, argv + 1);
  if (argc > 1 && std::string_view(argv[1]) == "firmware-report")
    return firmware_report_main(argc - 1, argv + 1);
  CLI::App app{"dyngen: generates unrolled, allocation-free C++ for the inverse dynamics (RNEA), "
               "mass matrix (CRBA) and forward dynamics (ABA) of one robot.\n"
               "dyngen eval ROBOT --states FILE: the runtime's results at given states, as JSON "
               "(dyngen eval --help)\n"
               "dyngen report ROBOT -o DIR: error against run time of every variant "
               "(dyngen report --help)\n"
               "dyngen firmware-report ROBOT -o DIR: code, stack and instructions on an emulated "
               "Cortex-M, checked against the host (dyngen firmware-report --help)"};
  app.name("dyngen");
  std::string input, output;
  CodeFlags code;
  ModelFlags flags;
  bool quiet = false, force = false;
  app.add_option("robot", input, robot_file_formats())->required();
  app.add_option("-o,--output", output, "output directory (created if missing)")->required();
  code.add_to(app, false);
  bool measure = false;
  app.add_flag("--measure,!--no-measure", measure,
               "compile the code with the target's GCC (the host's cc/c++, or arm-none-eabi-gcc) "
               "and record in the banner each function's code bytes and stack bound (default: "
               "on for a Cortex-M target, off for the host)");
  flags.add_to(app);
  app.add_flag("--force", force,
               "write into DIR even when it holds files dyngen did not write (files of the same "
               "names are replaced, the rest kept); without it DIR must be new, empty or a "
               "package dyngen wrote, which is replaced whole");
  app.add_flag("-q,--quiet", quiet, "print errors and warnings only");
  app.set_version_flag("--version", std::string("dyngen ") + version);
  if (const auto status = parse_command_line(app, argc, argv)) return *status;

  return run_reporting_errors("dyngen", [&] {
    code.check_options();
    check_output_dir(output, force);
    if (code.scalar == "float") flags.default_damping = 1e-5;
    const Robot robot = read_robot(input, flags, "", quiet);
    GenerateOptions options = code.options(robot, flags, "dyngen");
    if (app.count("--measure") + app.count("--no-measure") > 0) options.measure = measure;

    if (!quiet) {
      fmt::print("robot '{}': {} degrees of freedom in {} bodies", safe_text(robot.name),
                 robot.model.nv,
                 robot.model.nbodies);
      if (!robot.locked.empty()) fmt::print(", {} joints locked", robot.locked.size());
      fmt::print("\n{}", code.functions_text(options.algorithms));
      if (std::any_of(options.algorithms.begin(), options.algorithms.end(), uses_frames)) {
        std::vector<std::string> names;
        for (const Frame<double>& f : robot.model.frames) names.push_back(safe_text(f.name));
        fmt::print("frames: {}{}\n", fmt::join(names, ", "),
                   flags.frames.empty()
                       ? fmt::format(" (the default: {}; --frames names others)",
                                     default_frames_rule)
                       : "");
      }
      // each step as it starts: a big robot takes seconds per step
      options.progress = [](const std::string& step) {
        fmt::print("{} ...\n", step);
        std::fflush(stdout);
      };
    }
    const Generated generated = generate(robot, options);
    write_package(output, generated.files, force);
    for (const std::string& w : generated.warnings)
      fmt::print(stderr, "dyngen: warning: {}\n", safe_text(w, true));

    if (!quiet) {
      fmt::print("operations per call, generated vs runtime (add+sub, mul, div, neg, sin, cos):\n");
      std::size_t width = 0;
      for (const FunctionCounts& c : generated.counts) width = std::max(width, c.algorithm.size());
      for (const FunctionCounts& c : generated.counts)
        fmt::print("  {:<{}} {:>7} vs {:>7}  ({:.0f}% removed)   generated: {}\n",
                   c.algorithm, width, c.generated.total(), c.runtime.total(),
                   100.0 * (1.0 - double(c.generated.total()) / double(c.runtime.total())),
                   to_string(c.generated));
      if (robot.snapped) fmt::print("{}\n", snap_text(*robot.snapped));
      else if (const std::string note = snap_note(robot.model); !note.empty())
        fmt::print("{}\n", note);
      fmt::print("{}\n", generated.conditioning_text);
      if (generated.footprint) fmt::print("{}\n", footprint_text(*generated.footprint));
      fmt::print("wrote {} files to {}:", generated.files.size(), output);
      for (const GeneratedFile& f : generated.files) fmt::print(" {}", f.name);
      fmt::print("\nbuild and check it against the runtime:\n"
                 "  cmake -S {0} -B {0}/build -Ddyngen_DIR={1} && cmake --build {0}/build && "
                 "ctest --test-dir {0}/build\n",
                 output, package_dir());
    }
  });
}
