// Names from a robot file reach comments, string literals, identifiers and scripts. The C++
// compiler is the independent judge here: a string literal it reads back must hold the name's
// bytes, and a package generated from tests/models/coverage/hostile_names.urdf, whose names
// carry "#error" lines behind newlines, "*/", trailing backslashes, trigraphs and Unicode line
// separators, must compile with every warning an error (-Wcomment catches a spliced line).
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "files.hpp"
#include "names.hpp"
#include "pattern.hpp"

namespace dyngen::gen {
namespace {

namespace fs = std::filesystem;
using test::CliResult;
using test::Groups;
using test::Pattern;
using test::read;
using test::run_dyngen;
using test::ScratchTest;

TEST(SafeText, EscapesWhatCouldEndOrSpliceALine) {
  EXPECT_EQ(safe_text("ur5 arm_1 (v2) ~ok"), "ur5 arm_1 (v2) ~ok");
  EXPECT_EQ(safe_text("a\nb\rc\td"), "a\\x0ab\\x0dc\\x09d");
  EXPECT_EQ(safe_text("a\nb", true), "a\nb");
  EXPECT_EQ(safe_text("end\\"), "end\\x5c");
  EXPECT_EQ(safe_text("x */ y /* z"), "x *\\x2f y /* z");
  EXPECT_EQ(safe_text("what?\?/"), "what?\\x3f/");
  EXPECT_EQ(safe_text(std::string("nul\0x", 5)), "nul\\x00x");
  EXPECT_EQ(safe_text("del\x7f"), "del\\x7f");
  // UTF-8 letters stay; U+2028, U+2029 and C1 controls (U+0085) end lines for some tools
  EXPECT_EQ(safe_text("\xce\xb1/\xce\xb2"), "\xce\xb1/\xce\xb2");
  EXPECT_EQ(safe_text("a\xe2\x80\xa8" "b\xe2\x80\xa9" "c\xc2\x85"), "a\\u2028b\\u2029c\\u0085");
  // invalid UTF-8: a lone continuation byte, a truncated sequence, an overlong '/', a surrogate
  EXPECT_EQ(safe_text("\x80|\xe2\x80|\xc0\xaf|\xed\xa0\x80"),
            "\\x80|\\xe2\\x80|\\xc0\\xaf|\\xed\\xa0\\x80");
}

TEST(Identifier, IsAPlainNameThatIsNotReserved) {
  EXPECT_EQ(identifier("ur5"), "ur5");
  EXPECT_EQ(identifier("my-robot v2"), "my_robot_v2");
  EXPECT_EQ(identifier("__x__y__"), "x_y");
  EXPECT_EQ(identifier("2dof_planar"), "robot_2dof_planar");
  EXPECT_EQ(identifier(""), "robot");
  EXPECT_EQ(identifier("\xce\xb1\xce\xb2"), "robot");
  EXPECT_EQ(identifier("int"), "int_robot");
  EXPECT_EQ(identifier("std"), "std_robot");
  EXPECT_EQ(identifier("sin"), "sin_robot");
  EXPECT_EQ(identifier("main"), "main_robot");
  // long names are cut, and keep apart by a hash of the whole
  const std::string a = identifier(std::string(300, 'L') + "a");
  const std::string b = identifier(std::string(300, 'L') + "b");
  EXPECT_EQ(a.size(), max_identifier);
  EXPECT_EQ(b.size(), max_identifier);
  EXPECT_NE(a, b);
  for (const char* name : {"ur5", "robot_2dof_planar", "a_b"})
    EXPECT_TRUE(is_identifier(name)) << name;
  for (const char* name : {"int", "2dof", "a__b", "_a", "a-b", "", "sin"})
    EXPECT_FALSE(is_identifier(name)) << name;
}

// Issue 40: packages of robots with these names did not compile, as the headers that their
// files include (POSIX through GoogleTest, GoogleTest, Python.h) declare or define them.
TEST(Identifier, AppendsRobotToWhatTheHeadersDefine) {
  for (const char* name :
       {"pid_t", "ssize_t", "uint", "timespec", "pthread_t", "M_PI", "DBL_MAX", "LITTLE_ENDIAN",
        "EINTR", "GTEST_OS_LINUX", "HAVE_UNISTD_H", "INT32_MAX", "SEEK_SET", "PATH_MAX", "WEOF",
        "SIGINT", "SIZEOF_INT", "testing", "pybind11", "nlohmann", "Eigen", "benchmark"}) {
    EXPECT_EQ(identifier(name), std::string(name) + "_robot");
    EXPECT_TRUE(is_identifier(identifier(name))) << name;
  }
  // the check's and the Python module's own names stay: the templates keep theirs apart
  for (const char* name :
       {"model", "Arrays", "Spec", "py", "Scalar", "Array", "Argument", "Function", "call"})
    EXPECT_EQ(identifier(name), name);
  // a name the headers leave alone, but whose C package would not: gmp.h (the report
  // harness's, through MPFR) defines mpz_com, the C function com of a robot named mpz
  EXPECT_EQ(identifier("mpz"), "mpz_robot");
  // a reserved name near the limit keeps within it, and stays apart from the name cut there
  const std::string eigen = "EIGEN_DEFAULT_EMPTY_CONSTRUCTOR_AND_DESTRUCTOR";
  EXPECT_LE(identifier(eigen).size(), max_identifier);
  EXPECT_NE(identifier(eigen), identifier(eigen + "_robot_x"));
  EXPECT_TRUE(is_identifier(identifier(eigen)));
}

TEST(Identifier, PrefixesTheProjectsAndCMakesOwnNames) {
  EXPECT_EQ(identifier("dyngen_sincos"), "robot_dyngen_sincos");
  EXPECT_EQ(identifier("dyngen"), "robot_dyngen");
  EXPECT_EQ(identifier("DynGen arm"), "robot_DynGen_arm");
  EXPECT_EQ(identifier("dyngenx"), "robot_dyngenx");
  // CMake reserves every variable that starts with CMAKE_, in any case: cmake_arm's options
  // would be CMAKE_ARM_ISA and CMAKE_ARM_BUILD_CHECK
  EXPECT_EQ(identifier("cmake"), "robot_cmake");
  EXPECT_EQ(identifier("CMake arm"), "robot_CMake_arm");
  EXPECT_EQ(identifier("cmakearm"), "cmakearm");
  const std::string cut = identifier("dyngen" + std::string(100, 'x'));
  EXPECT_EQ(cut.size(), max_identifier);
  EXPECT_EQ(cut.rfind("robot_dyngen", 0), 0u) << cut;
}

class CNames : public ScratchTest {};

// c_names lists every name a C package declares outside its files: the generated header
// declares no other with the package's prefix.
TEST_F(CNames, CoverWhatTheCHeaderDeclares) {
  ASSERT_EQ(run_dyngen({fs::path(DYNGEN_TEST_MODELS) / "double_pendulum.urdf", "--lang", "c",
                        "--algorithms", "all", "--jacobian-frame", "both", "--name", "dp", "-o",
                        (dir / "gen").string(), "--quiet"},
                       dir)
                .status,
            0);
  const std::string header = read(dir / "gen" / "dp_dynamics.h");
  const std::vector<std::string> names = c_names("dp");
  const std::vector<Groups> declared = Pattern(R"(\b(dp|DP)_[A-Za-z0-9_]+)").find_all(header);
  for (const Groups& m : declared)
    EXPECT_NE(std::find(names.begin(), names.end(), m[0]), names.end()) << m[0];
  EXPECT_GT(declared.size(), 30u);
}

class NameOption : public ScratchTest {};

TEST_F(NameOption, RefusesAReservedNameAndSuggestsOne) {
  for (const auto& [name, suggestion] : {std::pair{"pid_t", "pid_t_robot"},
                                         std::pair{"dyngen_sincos", "robot_dyngen_sincos"}}) {
    const CliResult r = run_dyngen(
        {fs::path(DYNGEN_TEST_MODELS) / "double_pendulum.urdf", "--name", name, "-o",
         (dir / "gen").string()},
        dir);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find(fmt::format("--name {}: not usable", name)), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(fmt::format("for example --name {}\n", suggestion)), std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(dir / "gen"));
  }
}

TEST(MarkdownAndGnuplot, KeepTheirQuoting) {
  // CommonMark: a code span ends at the first backtick run as long as its opening one, so the
  // fence is one longer than any run inside; a space pads a span that starts or ends with a
  // backtick or a space (one such space is dropped from each end when rendered)
  EXPECT_EQ(markdown_code("ur5"), "`ur5`");
  EXPECT_EQ(markdown_code("a`b``c<i>&amp;|\nd"), "```a`b``c<i>&amp;|\\x0ad```");
  EXPECT_EQ(markdown_code("`touch x`"), "`` `touch x` ``");
  EXPECT_EQ(markdown_code(" x"), "`  x `");
  EXPECT_EQ(markdown_block("a\n```b\n"), "````\na\n```b\n````");
  EXPECT_EQ(markdown_block("a\x01"), "```\na\\x01\n```");
  // gnuplot: in single quotes only '' is special (no backslash escape, no `command`, no @macro)
  EXPECT_EQ(gnuplot_string("say \"hi\" `id` @x 'q'\\"), "'say \"hi\" `id` @x ''q''\\x5c'");
  EXPECT_EQ(gnuplot_string("a\nb\xff"), "'a\\x0ab\\xff'");
  // XML 1.0 has no U+FFFE or U+FFFF, so gnuplot's SVG must not get them
  EXPECT_EQ(gnuplot_string("x\xef\xbf\xbe\xef\xbf\xbf\xef\xbf\xbd"), "'x\\ufffe\\uffff\xef\xbf\xbd'");
}

/// Compiles source with the C++ compiler that built the tests, with trigraphs on and every
/// warning an error, and runs the program when output is given. Returns "" or what went wrong.
std::string compile(const fs::path& dir, const std::string& source, const std::string& flags,
                    std::string* output = nullptr) {
  const fs::path cpp = dir / "probe.cpp", exe = dir / "probe", out = dir / "probe.out";
  std::ofstream(cpp) << source;
  const std::string command =
      fmt::format("{} -trigraphs -Wall -Wextra -Werror {} {} {} > {} 2>&1", DYNGEN_CXX_COMPILER,
                  flags, cpp.string(), output ? fmt::format("-o {}", exe.string()) : "-fsyntax-only",
                  out.string());
  if (std::system(command.c_str()) != 0) return fmt::format("compile failed: {}", read(out));
  if (!output) return "";
  if (std::system(fmt::format("{} > {}", exe.string(), out.string()).c_str()) != 0)
    return "run failed";
  *output = read(out);
  return "";
}

class StringLiteral : public ScratchTest {};

TEST_F(StringLiteral, TheCompilerReadsBackEveryByte) {
  std::string text;
  for (int c = 1; c < 256; ++c) text += static_cast<char>(c);
  // NUL bytes, trigraphs, quotes and backslashes; ?\? is how this file spells two ?s
  text += std::string(1, '\0') + " ?\?/ ?\?= ?\?' \" \\ \\n\n?" + std::string(1, '\0') + "?\?7";
  const std::string source = fmt::format(
      "#include <cstdio>\nstatic const char s[] = {};\n"
      "int main() {{ std::fwrite(s, 1, sizeof s - 1, stdout); }}\n",
      string_literal(text));
  std::string printed;
  ASSERT_EQ(compile(dir, source, "-std=c++17", &printed), "");
  EXPECT_EQ(printed, text);
}

TEST_F(StringLiteral, PythonGetsValidUtf8WithTheInvalidBytesWritten) {
  // NUL, quotes, a backslash, controls, U+2028 and letters are text; then a lone continuation
  // byte, a truncated sequence, an overlong '/', a surrogate, a code point past U+10FFFF, 0xFF
  const std::string valid = std::string("q\"\\ \n\t\0 ", 8) + "\xce\xb1\xe2\x80\xa8 ";
  const std::string text = valid + "\x80|\xe2\x80|\xc0\xaf|\xed\xa0\x80|\xf4\x90\x80\x80|\xff";
  // what Python's bytes.decode("utf-8", "backslashreplace") gives for text, in UTF-8
  const std::string python =
      valid + "\\x80|\\xe2\\x80|\\xc0\\xaf|\\xed\\xa0\\x80|\\xf4\\x90\\x80\\x80|\\xff";
  const std::string source = fmt::format(
      "#include <cstdio>\nstatic const char s[] = {};\n"
      "int main() {{ std::fwrite(s, 1, sizeof s - 1, stdout); }}\n",
      python_literal(text));
  std::string printed;
  ASSERT_EQ(compile(dir, source, "-std=c++17", &printed), "");
  EXPECT_EQ(printed, python);
}

class HostileNames : public ScratchTest {};

TEST_F(HostileNames, NeverBecomeCode) {
  // the file's own name reaches the banner too (it cannot hold a '/')
  const fs::path urdf = dir / "robot \\\n#error file name.urdf";
  fs::copy_file(fs::path(DYNGEN_TEST_MODELS) / "coverage" / "hostile_names.urdf", urdf);
  const fs::path gen = dir / "gen";
  const std::string command = fmt::format("{} '{}' -o {} --quiet 2>{}", DYNGEN_EXECUTABLE,
                                          urdf.string(), gen.string(),
                                          (dir / "stderr").string());
  ASSERT_EQ(std::system(command.c_str()), 0) << read(dir / "stderr");

  std::vector<fs::path> sources;
  for (const auto& e : fs::directory_iterator(gen)) {
    const std::string text = read(e.path());
    for (const char c : text)
      EXPECT_FALSE((static_cast<unsigned char>(c) < 0x20 && c != '\n') || c == 0x7f)
          << e.path().filename() << " holds control character " << int(c);
    EXPECT_EQ(text.find("\\\n"), std::string::npos) << e.path().filename();
    EXPECT_EQ(text.find("\xe2\x80\xa8"), std::string::npos) << e.path().filename();
    if (e.path().extension() == ".cpp") sources.push_back(e.path());
  }
  // the generated code with its header (C++17 and later), and the check with the model tables
  // and the runtime (C++20)
  ASSERT_EQ(sources.size(), 2u);
  for (const fs::path& source : sources)
    EXPECT_EQ(compile(dir, fmt::format("#include \"{}\"\n", source.string()),
                      fmt::format("-std=c++{} -I{} -I{}/runtime/include",
                                  source.string().ends_with("_check.cpp") ? 20 : 17,
                                  gen.string(), DYNGEN_SOURCE_DIR)),
              "")
        << source.filename();

  // the package's CMakeLists.txt: the robot name's "message(FATAL_ERROR injected)" line stays
  // in a line comment, and no bracket comment swallows the lines after it
  const std::string cmake = read(gen / "CMakeLists.txt");
  const std::string payload = "message(FATAL_ERROR injected)";
  EXPECT_NE(cmake.find(payload), std::string::npos);
  std::istringstream lines(cmake);
  for (std::string line; std::getline(lines, line);) {
    if (line.find(payload) != std::string::npos) {
      EXPECT_EQ(line.rfind("#", 0), 0u) << line;
    }
    EXPECT_EQ(line.find("#["), std::string::npos) << line;
  }
}

}  // namespace
}  // namespace dyngen::gen
