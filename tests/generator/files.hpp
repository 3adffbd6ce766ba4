// File helpers shared by the generator tests: reading files, listing directories, a scratch
// directory per test process (ctest runs each test in its own process), and running the built
// dyngen command.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "robot.hpp"

namespace dyngen::test {

inline std::string read(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Every entry under dir with its contents (directories as "<dir>").
inline std::map<std::string, std::string> snapshot(const std::filesystem::path& dir) {
  std::map<std::string, std::string> entries;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    entries[std::filesystem::relative(e.path(), dir).string()] =
        e.is_directory() ? std::string("<dir>") : read(e.path());
  return entries;
}

/// The names directly in dir, sorted.
inline std::vector<std::string> entries_of(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

/// A fresh empty directory `dir` for each test, removed afterwards.
class ScratchTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = std::filesystem::temp_directory_path() / ("dyngen-test-" + std::to_string(getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
  }
  void TearDown() override { std::filesystem::remove_all(dir); }
  std::filesystem::path dir;
};

/// Load options accepting mimic joints (panda, pr2, baxter and romeo have them).
inline gen::LoadOptions independent_mimics() {
  gen::LoadOptions options;
  options.mimic_independent = true;
  return options;
}

inline gen::LoadOptions floating_base() {
  gen::LoadOptions options;
  options.floating_base = true;
  return options;
}

struct CliResult {
  int status;  // exit status, -1 if dyngen did not exit normally (a crash)
  std::string out, err;
};

inline std::string shell_quoted(const std::string& s) {
  std::string out = "'";
  for (const char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

/// Runs the built dyngen (DYNGEN_EXECUTABLE); stdin from `input` if not empty; its stdout and
/// stderr go to files in `scratch`.
inline CliResult run_dyngen(const std::vector<std::string>& args,
                            const std::filesystem::path& scratch, const std::string& input = "") {
  std::string command = shell_quoted(DYNGEN_EXECUTABLE);
  // appended piecewise: GCC 12's -Wrestrict misfires on `" " + std::string`
  for (const std::string& a : args) command.append(" ").append(shell_quoted(a));
  const std::filesystem::path out = scratch / "stdout.txt", err = scratch / "stderr.txt",
                              in = scratch / "stdin.txt";
  if (!input.empty()) {
    std::ofstream(in) << input;
    command.append(" <").append(shell_quoted(in));
  }
  command.append(" >").append(shell_quoted(out)).append(" 2>").append(shell_quoted(err));
  const int raw = std::system(command.c_str());
  CliResult r{WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, read(out), read(err)};
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  std::filesystem::remove(in);
  return r;
}

}  // namespace dyngen::test
