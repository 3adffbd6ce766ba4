// The template substituter is strict (STYLE.md B2): a placeholder without a value and a value
// without a placeholder are errors, so a renamed key cannot silently leave "@key@" in emitted
// code or drop a value. Values are inserted verbatim.
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "files.hpp"
#include "pattern.hpp"
#include "template.hpp"

namespace {

namespace fs = std::filesystem;
using namespace dyngen::gen;
using dyngen::test::Groups;
using dyngen::test::Pattern;
using dyngen::test::read;

const fs::path template_dir = fs::path(DYNGEN_SOURCE_DIR) / "templates";

std::set<std::string> template_names() {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(template_dir))
    if (e.path().extension() == ".in") names.insert(e.path().filename().string());
  return names;
}

std::set<std::string> placeholders(const std::string& text) {
  std::set<std::string> keys;
  for (const Groups& key : Pattern("@([A-Za-z_]+)@").find_all(text)) keys.insert(key[1]);
  return keys;
}

/// The expected result, computed independently of fill().
std::string replaced(std::string text, const std::map<std::string, std::string>& values) {
  for (const auto& [key, value] : values)
    for (std::size_t at = text.find("@" + key + "@"); at != std::string::npos;
         at = text.find("@" + key + "@", at + value.size()))
      text.replace(at, key.size() + 2, value);
  return text;
}

/// The message of the std::logic_error that `f` throws.
template <class F>
std::string logic_error_of(F f) {
  try {
    f();
  } catch (const std::logic_error& e) {
    return e.what();
  }
  return "(no std::logic_error)";
}

TEST(Template, EmbeddedTextIsTheTemplateFile) {
  const std::set<std::string> names = template_names();
  ASSERT_GE(names.size(), 10u);
  for (const std::string& name : names)
    EXPECT_EQ(template_text(name), read(template_dir / name)) << name;
}

TEST(Template, FillsEveryPlaceholderOfEveryTemplate) {
  for (const std::string& name : template_names()) {
    const std::string text(template_text(name));
    std::map<std::string, std::string> values;
    for (const std::string& key : placeholders(text)) values[key] = "<" + key + " value>";
    ASSERT_FALSE(values.empty()) << name << " has no placeholder";
    const std::string out = fill(name, values);
    EXPECT_EQ(out, replaced(text, values)) << name;
    EXPECT_EQ(out.find('@'), std::string::npos) << name;
  }
}

const std::map<std::string, std::string> check_values{
    {"name", "gravity"},
    {"namespace", "ur5"},
    {"call", "ur5::gravity"},
    {"arguments", "x[0].data(), y[0].data()"}};

TEST(Template, ReplacesEveryOccurrenceOfAKey) {
  const std::string text(template_text("function_check.cpp.in"));
  const std::string out = fill("function_check.cpp.in", check_values);
  EXPECT_EQ(out, replaced(text, check_values));
  EXPECT_NE(out.find("TEST(ur5, gravity_matches_runtime_bit_for_bit)"), std::string::npos) << out;
  EXPECT_NE(out.find("ur5::gravity(x[0].data(), y[0].data())"), std::string::npos) << out;
}

TEST(Template, InsertsValuesVerbatimWithoutRescanningThem) {
  std::map<std::string, std::string> values = check_values;
  values["name"] = "@arguments@ {}\\n\n%s $1 \"@\"";
  const std::string out = fill("function_check.cpp.in", values);
  EXPECT_EQ(out, replaced(std::string(template_text("function_check.cpp.in")), values));
  EXPECT_NE(out.find(values["name"]), std::string::npos);
}

TEST(Template, RejectsAPlaceholderWithoutAValue) {
  std::map<std::string, std::string> values = check_values;
  values.erase("namespace");
  const std::string message = logic_error_of([&] { fill("function_check.cpp.in", values); });
  EXPECT_NE(message.find("function_check.cpp.in"), std::string::npos) << message;
  EXPECT_NE(message.find("no value for @namespace@"), std::string::npos) << message;
  // a misspelt key is both: the placeholder lacks its value
  values["namespce"] = "ur5";
  const std::string misspelt = logic_error_of([&] { fill("function_check.cpp.in", values); });
  EXPECT_NE(misspelt.find("@namespace@"), std::string::npos) << misspelt;
}

TEST(Template, RejectsAValueWithoutAPlaceholder) {
  std::map<std::string, std::string> values = check_values;
  values["body"] = "tau[0] = 0;";
  const std::string message = logic_error_of([&] { fill("function_check.cpp.in", values); });
  EXPECT_NE(message.find("function_check.cpp.in"), std::string::npos) << message;
  EXPECT_NE(message.find("@body@ is not used"), std::string::npos) << message;
}

TEST(Template, RejectsAnUnknownTemplate) {
  EXPECT_NE(logic_error_of([] { template_text("no_such.hpp.in"); }).find("no_such.hpp.in"),
            std::string::npos);
  EXPECT_NE(logic_error_of([] { fill("no_such.hpp.in", {}); }).find("no_such.hpp.in"),
            std::string::npos);
}

}  // namespace
