// --measure: the banner's code bytes and stack bounds come from compiling the package with the
// target's GCC. That the bounds hold is checked where the stack can be measured, on the
// Cortex-M under qemu (tests/firmware); here, that measuring works for C++ and C on the host,
// that what it records is consistent, that $CXX is words run without a shell, and that a
// missing compiler or command is a clear error.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "footprint.hpp"
#include "generate.hpp"
#include "process.hpp"
#include "robot.hpp"

namespace {

using namespace dyngen::gen;

Generated measured(const std::string& language) {
  const Robot robot = load_robot(DYNGEN_TEST_MODELS "/ur5.urdf", LoadOptions{});
  GenerateOptions options;
  options.name = "ur5";
  options.language = language;
  options.measure = true;
  return generate(robot, options);
}

TEST(Footprint, RecordsEveryFunctionOfCppAndC) {
  for (const std::string language : {"c++", "c"}) {
    const Generated g = measured(language);
    ASSERT_TRUE(g.footprint.has_value());
    ASSERT_EQ(g.footprint->functions.size(), 3u);
    for (const FunctionFootprint& f : g.footprint->functions) {
      SCOPED_TRACE(f.algorithm);
      EXPECT_GT(f.code_bytes, 100);
      ASSERT_TRUE(f.stack_bound.has_value());
      ASSERT_TRUE(f.trig_stack_bound.has_value());
      // f(q, ...) calls f_trig(q, trig, ...) from a frame that holds the trig
      EXPECT_GT(*f.stack_bound, *f.trig_stack_bound);
      EXPECT_GE(*f.stack_bound - *f.trig_stack_bound,
                static_cast<long>(2 * 6 * sizeof(double)));
    }
    EXPECT_GT(g.footprint->common_code_bytes, 0);
    // aba does more work than rnea, and its code is larger
    EXPECT_GT(g.footprint->functions[2].code_bytes, g.footprint->functions[0].code_bytes);
    const std::string& banner = g.files.front().text;
    EXPECT_NE(banner.find("// Code and stack in bytes"), std::string::npos);
    EXPECT_NE(banner.find(fmt::format("//   aba                code {:>7}   stack {:>6} / {}",
                                      g.footprint->functions[2].code_bytes,
                                      *g.footprint->functions[2].stack_bound,
                                      *g.footprint->functions[2].trig_stack_bound)),
              std::string::npos)
        << banner.substr(0, 3000);
  }
}

/// $CXX set to `value` for the scope, then restored.
class ScopedCxx {
 public:
  explicit ScopedCxx(const std::string& value) {
    if (const char* saved = std::getenv("CXX")) saved_ = saved;
    ::setenv("CXX", value.c_str(), 1);
  }
  ~ScopedCxx() {
    if (saved_) ::setenv("CXX", saved_->c_str(), 1);
    else ::unsetenv("CXX");
  }

 private:
  std::optional<std::string> saved_;
};

/// The footprint of a one-line C++ source with the host's toolchain: quicker than a package.
Footprint measured_line() {
  return measure_footprint({{"line_dynamics.cpp", "int f() { return 1; }\n"}}, Dialect("line"), {},
                           toolchain("host"));
}

/// The InputError message of measured_line().
std::string measuring_error() {
  try {
    measured_line();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Footprint, CompilerVariableIsWordsRunWithoutAShell) {
  // as make and CMake take $CXX: the compiler and its first arguments ("ccache g++")
  {
    ScopedCxx cxx(std::string(" ") + DYNGEN_CXX_COMPILER + "\t -Wall ");
    const std::string compiler = measured_line().compiler;
    EXPECT_EQ(compiler.rfind(std::string(DYNGEN_CXX_COMPILER) + " -Wall ", 0), 0u) << compiler;
  }
  // no shell reads it: $(...) reaches the compiler as two arguments, which it refuses
  const std::filesystem::path touched = std::filesystem::temp_directory_path() /
                                        ("dyngen-footprint-test-" + std::to_string(getpid()));
  ScopedCxx cxx(std::string(DYNGEN_CXX_COMPILER) + " $(touch " + touched.string() + ")");
  const std::string message = measuring_error();
  EXPECT_NE(message.find("failed (exit status 1): "), std::string::npos) << message;
  EXPECT_FALSE(std::filesystem::exists(touched));
}

TEST(Footprint, MissingCompilerIsNotFound) {
  ScopedCxx cxx("/nonexistent/g++");
  EXPECT_EQ(measuring_error(),
            "measuring the code needs /nonexistent/g++ (GCC): /nonexistent/g++: not found");
  ScopedCxx launcher("dyngen-no-such-launcher g++");
  EXPECT_EQ(measuring_error(), "measuring the code needs dyngen-no-such-launcher g++ (GCC): "
                               "dyngen-no-such-launcher: not found");
}

// the shell's commands (CMake, qemu, gnuplot): how they ended, not the raw wait status
TEST(Process, SaysNotFoundAndNamesTheSignal) {
  try {
    output_of("dyngen-no-such-command --version", "running it");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(
        std::string(e.what()).rfind("running it failed (not found): dyngen-no-such-command", 0),
        0u)
        << e.what();
  }
  try {
    output_of(std::vector<std::string>{"sh", "-c", "kill -9 $$"}, "running it");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("running it failed (killed by signal 9 (Killed)): sh -c "
                                          "'kill -9 $$'",
                                          0),
              0u)
        << e.what();
  }
}

TEST(Process, CommandWordsSplitAtBlanks) {
  using Words = std::vector<std::string>;
  EXPECT_EQ(command_words("ccache g++"), (Words{"ccache", "g++"}));
  EXPECT_EQ(command_words("  gcc\t-m32 \n"), (Words{"gcc", "-m32"}));
  EXPECT_EQ(command_words(" \t"), Words{});
}

}  // namespace
