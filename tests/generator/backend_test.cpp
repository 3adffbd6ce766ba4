// The backend registry: which backends a package holds, in which order, and what each refuses;
// and how the dialects spell what the header declares.
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "backend.hpp"
#include "names.hpp"

namespace {

using namespace dyngen::gen;

GenerateOptions package(const std::string& language, int batch, bool python) {
  GenerateOptions options;
  options.name = "ur5";
  options.language = language;
  options.batch = batch;
  options.python = python;
  return options;
}

std::string refusal(const GenerateOptions& options) {
  try {
    package_backends(options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Backends, LanguagesAreTheRegistrysInItsOrder) {
  EXPECT_EQ(language_names(), (std::vector<std::string>{"c++", "c"}));
  EXPECT_NE(language_help().find("c++ (C++17"), std::string::npos) << language_help();
  EXPECT_NE(language_help().find(" or c (C99"), std::string::npos) << language_help();
}

// the language first, then what the options add; only printing backends have a dialect
TEST(Backends, APackageHoldsItsLanguageThenWhatTheOptionsAdd) {
  const auto backends = package_backends(package("c++", 4, true));
  ASSERT_EQ(backends.size(), 4u);  // c++, batch, python, eigen
  ASSERT_NE(backends[0]->dialect(), nullptr);
  EXPECT_EQ(backends[0]->dialect()->lanes(), 0);
  ASSERT_NE(backends[1]->dialect(), nullptr);
  EXPECT_EQ(backends[1]->dialect()->lanes(), 4);
  EXPECT_EQ(backends[2]->dialect(), nullptr);
  EXPECT_EQ(backends[3]->dialect(), nullptr);
  EXPECT_EQ(package_backends(package("c", 0, false)).size(), 1u);  // no Eigen header in C
}

TEST(Backends, RefusesAnUnknownLanguageAndBatchesOutsideCpp) {
  EXPECT_NE(refusal(package("rust", 0, false)).find("no language 'rust': dyngen prints c++, c"),
            std::string::npos);
  EXPECT_NE(refusal(package("c", 4, false)).find("--batch: batch functions are C++"),
            std::string::npos);
  EXPECT_NE(refusal(package("c", 0, true)).find("--python: batch functions are C++"),
            std::string::npos);
  EXPECT_EQ(refusal(package("c++", 4, true)), "");
}

// the names of the generated headers' API (README, "Generated code")
TEST(Dialects, SpellTheHeadersNamesAsEachLanguageDeclaresThem) {
  const auto cpp = language_backend("c++", "ur5"), c = language_backend("c", "ur5");
  const auto batch = std::move(package_backends(package("c++", 4, false))[1]);  // after c++
  const Dialect &d_cpp = *cpp->dialect(), &d_c = *c->dialect(), &d_batch = *batch->dialect();
  EXPECT_EQ(d_cpp.qualified("rnea"), "::ur5::rnea");
  EXPECT_EQ(d_c.qualified("rnea"), "::ur5_rnea");
  EXPECT_EQ(d_batch.function("rnea"), "rnea_batch");
  EXPECT_EQ(d_cpp.size_outside("nq"), "::ur5::nq");
  EXPECT_EQ(d_c.size_outside("nq"), "UR5_NQ");
  EXPECT_EQ(d_cpp.source(), "ur5_dynamics.cpp");
  EXPECT_EQ(d_c.header(), "ur5_dynamics.h");
  EXPECT_EQ(d_c.trig_parameter(), "const ur5_JointTrig* trig");
  EXPECT_EQ(d_batch.trig_parameter(), "const JointTrigBatch& trig");
  EXPECT_FALSE(d_c.kernel_calls());
  EXPECT_FALSE(d_batch.lane_blocks());
  EXPECT_TRUE(d_cpp.lane_blocks());
}

}  // namespace
