// --measure: the banner's code bytes and stack bounds come from compiling the package with the
// target's GCC. That the bounds hold is checked where the stack can be measured, on the
// Cortex-M under qemu (tests/firmware); here, that measuring works for C++ and C on the host,
// that what it records is consistent, and that a missing compiler is a clear error.
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "generate.hpp"
#include "robot.hpp"

namespace {

using namespace dyngen::gen;

Generated measured(Language language) {
  const Robot robot = load_robot(DYNGEN_TEST_MODELS "/ur5.urdf", LoadOptions{});
  GenerateOptions options;
  options.name = "ur5";
  options.language = language;
  options.measure = true;
  return generate(robot, options);
}

TEST(Footprint, RecordsEveryFunctionOfCppAndC) {
  for (const Language language : {Language::Cpp, Language::C}) {
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

TEST(Footprint, MissingCompilerIsAnInputError) {
  const char* saved = std::getenv("CXX");
  const std::string restore = saved ? saved : "";
  ::setenv("CXX", "/nonexistent/g++", 1);
  try {
    measured(Language::Cpp);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("measuring the code needs /nonexistent/g++"),
              std::string::npos)
        << e.what();
  }
  if (saved) ::setenv("CXX", restore.c_str(), 1);
  else ::unsetenv("CXX");
}

}  // namespace
