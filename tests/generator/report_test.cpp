// dyngen report end to end: it builds its harness against this build of dyngen, measures
// every variant and writes the four report files. The figures are checked against what must
// hold independently of the measurement: the generated code computes the runtime's bits, so
// their errors are identical; RNEA and CRBA stay within a few dozen units of roundoff; forward
// dynamics stays within the loss that the conditioning estimate (long double ABA pivots, not the
// MPFR reference) predicts; and times are positive. And every text a hostile name reaches in
// the reports (Markdown, JSON, gnuplot, SVG) shows it as written, and runs nothing.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "dyngen/crba.hpp"
#include "dyngen/rnea.hpp"
#include "files.hpp"
#include "report.hpp"

namespace {

using dyngen::test::CliResult;
using dyngen::test::read;
using dyngen::test::run_dyngen;
using dyngen::test::ScratchTest;
using dyngen::test::shell_quoted;
using dyngen::test::snapshot;

const std::string models = DYNGEN_TEST_MODELS;

/// The result of one variant of one algorithm in report.json.
const nlohmann::json& result(const nlohmann::json& report, const std::string& algorithm,
                             const std::string& variant) {
  for (const nlohmann::json& r : report["results"])
    if (r["algorithm"] == algorithm && r["variant"] == variant) return r;
  ADD_FAILURE() << "no result for " << algorithm << " / " << variant;
  static const nlohmann::json none;
  return none;
}

/// Markdown's text outside code, by CommonMark's rules: a fenced block opens with a line that
/// starts with three or more backticks and closes at a line of at least as many and nothing
/// else; a code span opens with a run of n backticks and closes at the next run of exactly n
/// (an unclosed run is literal text). Names here hold no newline, so spans stay on one line.
std::string outside_code(const std::string& markdown) {
  constexpr std::size_t none = std::string::npos;
  const auto run_at = [](const std::string& line, std::size_t k) {
    return std::min(line.find_first_not_of('`', k), line.size()) - k;
  };
  std::string out;
  std::istringstream in(markdown);
  std::size_t fence = 0;
  for (std::string line; std::getline(in, line);) {
    const std::size_t run = run_at(line, 0);
    if (fence > 0) {
      if (run >= fence && line.find_first_not_of(' ', run) == none) fence = 0;
      continue;
    }
    if (run >= 3) {
      fence = run;
      continue;
    }
    for (std::size_t k = 0; k < line.size();) {
      if (line[k] != '`') {
        out += line[k++];
        continue;
      }
      const std::size_t n = run_at(line, k);
      std::size_t close = line.find('`', k + n);
      while (close != none && run_at(line, close) != n)
        close = line.find('`', close + run_at(line, close));
      if (close == none) out += line.substr(k, n);
      k = close == none ? k + n : close + n;
    }
    out += '\n';
  }
  EXPECT_EQ(fence, 0u) << "a code block is left open";
  return out;
}

/// Checks Markdown that shows the hostile texts: each is there, and only inside code, so that
/// neither their backticks, newlines nor HTML act as Markdown.
void expect_only_in_code(const std::string& markdown, const std::vector<std::string>& texts) {
  const std::string outside = outside_code(markdown);
  for (const std::string& t : texts) {
    EXPECT_NE(markdown.find(t), std::string::npos) << t << " is shown\n" << markdown;
    EXPECT_EQ(outside.find(t), std::string::npos) << t << " only in code\n" << outside;
  }
  for (const char c : {'<', '&', '`'})
    EXPECT_EQ(outside.find(c), std::string::npos) << c << " outside code:\n" << outside;
}

/// Whether python3's XML parser (expat, which refuses what XML 1.0 does not allow) reads file.
bool parses_as_xml(const std::filesystem::path& file) {
  const std::string command =
      "python3 -c 'import sys, xml.etree.ElementTree as E; E.parse(sys.argv[1])' " +
      shell_quoted(file.string());
  return std::system(command.c_str()) == 0;
}

/// A robot name that runs a command wherever a shell or gnuplot substitutes `...` or $(...):
/// each would create a file in dir.
std::string command_name(const std::filesystem::path& dir) {
  return "arm `touch " + (dir / "ran_backquote").string() + "` $(touch " +
         (dir / "ran_dollar").string() + ")";
}

/// Nothing that a hostile name holds has run.
void expect_nothing_ran(const std::filesystem::path& dir) {
  EXPECT_FALSE(std::filesystem::exists(dir / "ran_backquote"));
  EXPECT_FALSE(std::filesystem::exists(dir / "ran_dollar"));
}

/// A copy of a URDF in dir, as file_name, with `more` (XML) added to the start of its robot's
/// name.
std::filesystem::path renamed_urdf(const std::string& urdf_path, const std::filesystem::path& dir,
                                   const std::string& file_name, const std::string& more) {
  std::string urdf = read(urdf_path);
  const std::size_t at = urdf.find("name=\"", urdf.find("<robot"));
  EXPECT_NE(at, std::string::npos) << urdf_path;
  urdf.insert(at + 6, more);
  const std::filesystem::path path = dir / file_name;
  std::ofstream(path, std::ios::binary) << urdf;
  return path;
}

/// The robot name that renamed_urdf makes from `more` (XML with &lt; &gt; &amp; and &#10; as its
/// only references) and the name in the file, with invalid UTF-8's bytes as JSON shows them
/// (U+FFFD).
std::string json_name(std::string more, const std::string& name) {
  for (const auto& [from, to] : {std::pair{"&lt;", "<"}, std::pair{"&gt;", ">"},
                                 std::pair{"&#10;", "\n"}, std::pair{"&amp;", "&"},
                                 std::pair{"\xff", "\xef\xbf\xbd"}})
    for (std::size_t k = more.find(from); k != std::string::npos; k = more.find(from, k + 1))
      more.replace(k, std::string_view(from).size(), to);
  return more + name;
}

using Report = ScratchTest;

TEST_F(Report, MeasuresEveryVariantOfEveryAlgorithm) {
  // the pendulum, under a hostile name in a hostile file name: the name reaches the harness's
  // C++ and CMake, and every report file
  const std::string more = command_name(dir) + " &lt;b&gt;x&lt;/b&gt;&#10;# line \xff ";
  const std::filesystem::path robot = renamed_urdf(models + "/double_pendulum.urdf", dir,
                                                   "pendulum `x` <i>\n.urdf", more);
  const std::filesystem::path out = dir / "report";
  const CliResult r = run_dyngen({"report", robot.string(), "-o", out.string(), "--states", "40",
                                  "--min-time", "0.01", "--repetitions", "2", "--algorithms",
                                  "all"},
                                 dir);
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  expect_nothing_ran(dir);
  EXPECT_TRUE(parses_as_xml(out / "report.svg"));
  EXPECT_NE(r.out.find("[5/5] writing the report"), std::string::npos) << "progress is printed";

  const nlohmann::json report = nlohmann::json::parse(read(out / "report.json"));
  EXPECT_EQ(report["states"], 40);
  EXPECT_EQ(report["robot"], json_name(more, "2dof_planar"));  // the name in the URDF
  // the command line as a shell takes it back: the file's name quoted, the plain words not
  EXPECT_NE(report["command"].get<std::string>().find("dyngen report " +
                                                      shell_quoted(robot.string()) + " -o "),
            std::string::npos)
      << report["command"];
  EXPECT_NE(report["command"].get<std::string>().find(" --states 40 "), std::string::npos);
  const std::string markdown = read(out / "report.md");
  expect_only_in_code(markdown, {"`touch ", "$(touch ", "<b>x</b>", "\\x0a# line", "<i>\\x0a.urdf"});
  const double aba_loss = std::pow(10.0, report["conditioning"]["aba_digits_lost"].get<double>());
  for (const char* a : {"rnea", "crba", "aba", "gravity", "nle", "minv", "rnea_derivatives",
                        "aba_derivatives"}) {
    for (const char* scalar : {"double", "float"}) {
      const nlohmann::json& runtime = result(report, a, std::string("runtime ") + scalar);
      const nlohmann::json& generated = result(report, a, std::string("generated ") + scalar);
      // bit for bit: the same outputs, so exactly the same errors
      EXPECT_EQ(generated["median_error"], runtime["median_error"]) << a << " " << scalar;
      EXPECT_EQ(generated["worst_error"], runtime["worst_error"]) << a << " " << scalar;
      EXPECT_DOUBLE_EQ(runtime["speed_up"].get<double>(), 1.0);
    }
    for (const nlohmann::json& v : report["results"]) {
      if (v["algorithm"] != a) continue;
      const double eps = v["scalar"] == "float" ? 0x1p-24 : 0x1p-53;
      // measured: RNEA and CRBA 1.3e-15 / 4e-7 at worst; ABA 1.3e-13 / 5.7e-5 against an
      // estimated loss of 10^2.6, and what divides by ABA's pivots may lose as much;
      // rnea_derivatives 5.9e-15 (53 eps, at one of the 40 states; the median is 2 eps) and
      // 7.9e-7
      const std::string name = a;
      const bool pivots = name == "aba" || name == "minv" || name == "aba_derivatives";
      const double bound = (name == "rnea_derivatives" ? 100 : 50) * eps * (pivots ? aba_loss : 1.0);
      EXPECT_LT(v["worst_error"].get<double>(), bound) << a << " " << v["variant"];
      EXPECT_GT(v["median_ns"].get<double>(), 0.0);
      EXPECT_EQ(v["nonfinite"], 0);
      EXPECT_NE(markdown.find("| " + v["variant"].get<std::string>() + " |"), std::string::npos);
    }
  }
  EXPECT_EQ(result(report, "aba", "generated CRBA+LDLT double")["scalar"], "double");
  EXPECT_GT(report["conditioning"]["cond_M_max"].get<double>(), 1.0);
}

TEST_F(Report, OnlyTheRequestedAlgorithmsAndNonFiniteOutputs) {
  // the tip's inertia (1e-48 kg m^2) rounds to zero in float: the runtime's float ABA divides
  // by zero, and no float ABA can be generated. The robot is named "report", like the harness's
  // own namespace once was: the package's namespace and the harness's stay apart.
  std::string spec = read(models + "/coverage/tiny_tip.yaml");
  spec.replace(spec.find("name: tiny_tip"), 14, "name: report");
  const std::filesystem::path robot = dir / "report.yaml", out = dir / "report";
  std::ofstream(robot) << spec;
  const CliResult r = run_dyngen({"report", robot.string(), "-o", out.string(), "--algorithms",
                                  "rnea,aba", "--states", "10", "--min-time", "0.01",
                                  "--repetitions", "1", "--quiet"},
                                 dir);
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_EQ(r.out, "") << "--quiet prints nothing";
  const nlohmann::json report = nlohmann::json::parse(read(out / "report.json"));
  ASSERT_FALSE(report["results"].empty());
  for (const nlohmann::json& v : report["results"]) EXPECT_NE(v["algorithm"], "crba");
  EXPECT_GE(report["conditioning"]["float_unrepresentable"].get<int>(), 1);
  EXPECT_EQ(result(report, "aba", "runtime float")["nonfinite"], 10);
  EXPECT_LT(result(report, "aba", "generated double")["worst_error"].get<double>(), 1e-6);
  const std::string markdown = read(out / "report.md");
  EXPECT_NE(markdown.find("| runtime float | inf | 10 non-finite |"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("No generated float ABA"), std::string::npos) << markdown;
  for (const nlohmann::json& v : report["results"])
    EXPECT_FALSE(v["algorithm"] == "aba" && v["variant"] == "generated float");
}

// A robot whose float values overflow at typical states everywhere: the report is made, with no
// generated float variant (CRBA+LDLT float included, which needs float's CRBA and RNEA), and
// report.json says why each is left out.
TEST_F(Report, LeavesOutGeneratedFloatThatOverflows) {
  const std::filesystem::path out = dir / "report";
  const CliResult r = run_dyngen({"report", std::string(DYNGEN_TEST_BAD) +
                                      "/float_overflow_typical.yaml", "-o", out.string(),
                                  "--algorithms", "rnea,crba,aba", "--states", "10",
                                  "--min-time", "0.01", "--repetitions", "1", "--quiet"},
                                 dir);
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  const nlohmann::json report = nlohmann::json::parse(read(out / "report.json"));
  ASSERT_EQ(report["float_left_out"].size(), 3u) << report["float_left_out"];
  for (const nlohmann::json& v : report["results"])
    EXPECT_TRUE(v["variant"].get<std::string>().find("generated") == std::string::npos ||
                v["scalar"] == "double")
        << v;
  EXPECT_EQ(result(report, "aba", "generated CRBA+LDLT double")["scalar"], "double");
  EXPECT_NE(read(out / "report.md").find("No generated float crba: its values overflow float"),
            std::string::npos);
}

/// What the harness would measure of every variant of each algorithm, made up.
nlohmann::json made_up_measurements(const std::vector<std::string>& algorithms) {
  nlohmann::json results = nlohmann::json::array();
  double ns = 100;
  for (const std::string& a : algorithms)
    for (const std::string v : {"runtime double", "generated double", "generated double, FMA",
                                "generated double, fast-math", "runtime float", "generated float",
                                "generated CRBA+LDLT double", "generated CRBA+LDLT float"}) {
      if (v.find("LDLT") != std::string::npos && a != "aba") continue;
      const bool single = v.ends_with("float");
      results.push_back({{"algorithm", a},
                         {"variant", v},
                         {"scalar", single ? "float" : "double"},
                         {"median_error", single ? 1e-7 : 2e-16},
                         {"worst_error", single ? 6e-7 : 1e-15},
                         {"nonfinite", 0},
                         {"median_ns", ns *= 1.3}});
    }
  return {{"states", 7},   {"timed_states", 7},    {"reference_bits", 256}, {"error_floor", 1e-300},
          {"cpus", 2},     {"cpu_mhz", 2000.0},    {"results", results}};
}

TEST_F(Report, ShowsHostileNamesAsWrittenAndRunsNothing) {
  // the hostile-names model (newlines, quotes, a backslash, */, ??/, U+2028, C1 controls in its
  // names), with a command in backquotes and in $(...), HTML, a pipe, gnuplot's enhanced-text
  // and macro characters, invalid UTF-8 and U+FFFF (which XML cannot hold) added to its name
  using namespace dyngen::gen;
  Robot robot = load_robot(models + "/coverage/hostile_names.urdf");
  const std::string original = robot.name;
  robot.name += command_name(dir) + " <b>x</b> &amp; | ^_@{}~ \xff \xef\xbf\xbf";
  robot.path = dir / "a `b` <img src=x>\n.urdf";
  ReportOptions options;
  options.algorithms = {"rnea", "aba"};
  options.command = "dyngen report `touch x` <script>y</script> |\n# z";
  options.quiet = true;
  dyngen::numerics::Conditioning c;
  c.pivot_joint = "j\n```\n# escaped the block <b>";  // a joint name that would close a fence
  const std::filesystem::path out = dir / "report";
  std::filesystem::create_directories(out);
  // and in why generated float leaves an algorithm out: a joint's name, a link's in the detail
  nlohmann::json measured = made_up_measurements({"rnea", "aba"});
  measured["float_left_out"] = {
      {{"algorithm", "aba"},
       {"reason", "pivots"},
       {"joints", nlohmann::json::array({"j <i>pivot</i>"})}},
      {{"algorithm", "rnea"},
       {"reason", "overflow"},
       {"detail", "rnea overflows in float at link '<u>l\n```\n# closed</u>'"}}};
  write_report(robot, options, c, measured, out.string());
  expect_nothing_ran(dir);

  const std::string markdown = read(out / "report.md");
  expect_only_in_code(markdown, {"`touch ", "$(touch ", "<b>x</b>", "&amp;", "<script>",
                                 "<img src=x>", "escaped the block", "<i>pivot</i>", "<u>l"});
  EXPECT_NE(markdown.find("No generated float ABA (aba)"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("No generated float rnea: its values overflow float"),
            std::string::npos)
      << markdown;
  // safe_text's escapes: a name stays on its line
  EXPECT_NE(markdown.find("evil\\x0amessage(FATAL_ERROR injected)"), std::string::npos);
  EXPECT_EQ(markdown.find("\n# z"), std::string::npos);

  // JSON: names as strings, exactly, but for the invalid byte (U+FFFD)
  const nlohmann::json report = nlohmann::json::parse(read(out / "report.json"));
  std::string expected = robot.name;
  expected.replace(expected.find('\xff'), 1, "\xef\xbf\xbd");
  EXPECT_EQ(report["robot"], expected);
  EXPECT_EQ(report["command"], options.command);
  EXPECT_EQ(report["robot_file"], std::string("a `b` <img src=x>\n.urdf"));
  EXPECT_EQ(report["conditioning"]["pivot_joint"], c.pivot_joint);

  // gnuplot drew the name in the title as plain text (SVG escapes < and &)
  const std::string svg = read(out / "report.svg");
  EXPECT_TRUE(parses_as_xml(out / "report.svg")) << svg;
  EXPECT_NE(svg.find("`touch " + (dir / "ran_backquote").string() + "` $(touch"),
            std::string::npos);
  EXPECT_NE(svg.find("&lt;b>x&lt;/b> &amp;amp; | ^_@{}~ \\xff \\uffff"), std::string::npos);
  EXPECT_EQ(svg.find(original), std::string::npos) << "newlines are escaped";
}

// report.md heads each algorithm's table with its title from the runtime's table, in the order
// measured; one without a title by its name and outputs
TEST_F(Report, HeadsEachAlgorithmWithItsTitle) {
  using namespace dyngen::gen;
  const Robot robot = load_robot(models + "/double_pendulum.urdf");
  ReportOptions options;
  options.algorithms = {"rnea", "crba", "aba", "rnea_derivatives"};
  options.quiet = true;
  const std::filesystem::path out = dir / "report";
  std::filesystem::create_directories(out);
  write_report(robot, options, {}, made_up_measurements(options.algorithms), out.string());
  std::string headings;
  std::istringstream in(read(out / "report.md"));
  for (std::string line; std::getline(in, line);)
    if (line.starts_with("## ")) headings += line + "\n";
  EXPECT_EQ(headings,
            "## RNEA (inverse dynamics, tau)\n## CRBA (mass matrix, M)\n"
            "## ABA (forward dynamics, qdd)\n## rnea_derivatives (dtau_dq, dtau_dv)\n");
}

TEST_F(Report, FirmwareReportShowsHostileNamesAsWritten) {
  if (std::system("command -v qemu-system-arm arm-none-eabi-g++ >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "no qemu-system-arm or arm-none-eabi-g++ (the test firmware_tools_present fails)";
  // the hostile-names model, with a command, HTML and invalid UTF-8 (which made nlohmann's
  // dump throw after firmware-report.md was written) added to its name
  const std::string more = command_name(dir) + " &lt;b&gt;x&lt;/b&gt; \xff ";
  const std::filesystem::path robot =
      renamed_urdf(models + "/coverage/hostile_names.urdf", dir, "hostile `x` <i>.urdf", more);
  const std::filesystem::path out = dir / "firmware";
  const CliResult r = run_dyngen({"firmware-report", robot.string(), "-o", out.string(),
                                  "--target", "cortex-m4f", "--algorithms", "rnea", "--quiet"},
                                 dir);
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  expect_nothing_ran(dir);
  expect_only_in_code(read(out / "firmware-report.md"),
                      {"`touch ", "$(touch ", "<b>x</b>", "\\x0amessage(FATAL_ERROR", "<i>.urdf"});
  const nlohmann::json report = nlohmann::json::parse(read(out / "firmware-report.json"));
  const std::string name = dyngen::gen::load_robot(models + "/coverage/hostile_names.urdf").name;
  EXPECT_EQ(report["robot"], json_name(more, name));
}

TEST_F(Report, RefusesAbaOnMasslessJointsAndWritesNothing) {
  const std::filesystem::path out = dir / "report";
  const CliResult r = run_dyngen(
      {"report", models + "/romeo.urdf", "-o", out.string(), "--mimic-independent"}, dir);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("ABA is undefined"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--lock-massless"), std::string::npos) << r.err;
  for (const char* f : {"report.md", "report.json", "report.gp", "report.svg"})
    EXPECT_FALSE(std::filesystem::exists(out / f)) << f;
}

// A directory that holds files of someone else's: both reports refuse it, name what is in the way
// and leave it as it was
TEST_F(Report, RefusesADirectoryOfOtherFilesAndNamesThem) {
  const std::filesystem::path out = dir / "mine";
  std::filesystem::create_directories(out / "notes");
  std::ofstream(out / "notes.txt") << "mine";
  const auto before = snapshot(out);
  for (const std::vector<std::string>& command :
       {std::vector<std::string>{"report", models + "/double_pendulum.urdf", "-o", out.string()},
        {"firmware-report", models + "/double_pendulum.urdf", "-o", out.string(), "--target",
         "cortex-m4f"}}) {
    const CliResult r = run_dyngen(command, dir);
    EXPECT_EQ(r.status, 1) << command[0];
    EXPECT_NE(r.err.find(out.string() + ": exists and holds files that dyngen " + command[0] +
                         " did not write (notes.txt, notes/);"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(snapshot(out), before) << command[0];
  }
}

// tests/generator/bad/float_overflow_typical.yaml's values overflow float at typical states:
// the report leaves RNEA, CRBA and ABA out of generated float and says where each overflows.
// The runtime in float agrees: at q = 0, v = a = 1, its tau and M are not finite. The double
// pendulum loses nothing.
TEST(ReportFloatPlan, LeavesOutWhatOverflowsFloatAtTypicalStates) {
  const dyngen::gen::Robot robot =
      dyngen::gen::load_robot(std::string(DYNGEN_TEST_BAD) + "/float_overflow_typical.yaml");
  const dyngen::gen::FloatPlan plan = dyngen::gen::float_plan(robot, {"rnea", "crba", "aba"});
  EXPECT_TRUE(plan.kept.empty());
  ASSERT_EQ(plan.left_out.size(), 3u) << plan.left_out.dump();
  for (const nlohmann::json& left : plan.left_out) {
    EXPECT_EQ(left["reason"], "overflow");
    EXPECT_NE(left["detail"].get<std::string>().find(left["algorithm"].get<std::string>() +
                                                     " overflows in float at typical states"),
              std::string::npos)
        << left["detail"];
  }
  const dyngen::Model<float> model = robot.model.cast<float>();
  dyngen::Workspace<float> ws(model);
  const std::vector<float> q(2, 0.0f), v(2, 1.0f), a(2, 1.0f);
  std::vector<float> tau(2), M(4);
  dyngen::rnea<float>(model, ws, q, v, a, tau);
  dyngen::crba<float>(model, ws, q, M);
  EXPECT_FALSE(std::isfinite(tau[0]) && std::isfinite(tau[1]));
  EXPECT_FALSE(std::all_of(M.begin(), M.end(), [](float m) { return std::isfinite(m); }));

  const dyngen::gen::Robot pendulum = dyngen::gen::load_robot(models + "/double_pendulum.urdf");
  const std::vector<std::string> all = {"rnea", "crba", "aba"};
  EXPECT_EQ(dyngen::gen::float_plan(pendulum, all).kept, all);
}

}  // namespace
