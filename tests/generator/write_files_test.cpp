// write_files never leaves partial output: a new directory appears whole (assembled under a
// temporary name and renamed), files in an existing directory are replaced one by one by rename,
// and everything else in that directory (the user's build/ folder) is left alone.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "files.hpp"
#include "generate.hpp"

namespace {

namespace fs = std::filesystem;
using namespace dyngen::gen;
using dyngen::test::read;
using dyngen::test::entries_of;
using dyngen::test::snapshot;

void write(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

const std::vector<GeneratedFile> files = {{"robot_dynamics.hpp", "// header\n"},
                                          {"robot_dynamics.cpp", "// source\n"},
                                          {"CMakeLists.txt", "project(robot)\n"}};

const std::map<std::string, std::string> written = {{"robot_dynamics.hpp", "// header\n"},
                                                    {"robot_dynamics.cpp", "// source\n"},
                                                    {"CMakeLists.txt", "project(robot)\n"}};

using WriteFiles = dyngen::test::ScratchTest;

TEST_F(WriteFiles, CreatesANewDirectoryWithExactlyTheFilesAndNoLeftovers) {
  write_files((dir / "gen").string(), files);
  EXPECT_EQ(entries_of(dir), std::vector<std::string>{"gen"}) << "a staging directory is left";
  EXPECT_EQ(snapshot(dir / "gen"), written);
}

TEST_F(WriteFiles, ANewDirectoryAppearsWhole) {
  // an observer polling while the files are written sees no directory or all of it
  const std::size_t count = 300;
  std::vector<GeneratedFile> many;
  for (std::size_t k = 0; k < count; ++k) many.push_back({std::to_string(k) + ".cpp", "x"});
  const fs::path gen = dir / "gen";
  std::atomic<bool> done = false;
  std::thread writer([&] {
    write_files(gen.string(), many);
    done = true;
  });
  std::size_t partial = 0;
  while (!done) {
    std::error_code error;
    std::size_t seen = 0;
    for (auto it = fs::directory_iterator(gen, error); !error && it != fs::directory_iterator();
         it.increment(error))
      ++seen;
    if (!error && seen != count) ++partial;
  }
  writer.join();
  EXPECT_EQ(partial, 0u) << "times the directory was seen partly written";
  EXPECT_EQ(entries_of(gen).size(), count);
}

TEST_F(WriteFiles, CreatesMissingParentDirectories) {
  write_files((dir / "a" / "b" / "gen").string(), files);
  EXPECT_EQ(snapshot(dir / "a" / "b" / "gen"), written);
  EXPECT_EQ(entries_of(dir / "a" / "b"), std::vector<std::string>{"gen"});
}

TEST_F(WriteFiles, OverwritesItsFilesInAnExistingDirectoryAndLeavesTheRest) {
  const fs::path gen = dir / "gen";
  write(gen / "robot_dynamics.hpp", "// an older header, longer than the new one\n");
  write(gen / "notes.txt", "the user's\n");
  write(gen / "build" / "CMakeCache.txt", "CMAKE_BUILD_TYPE:STRING=Release\n");
  write(gen / "build" / "CMakeFiles" / "robot.dir" / "robot_dynamics.cpp.o", "object");
  auto expected = snapshot(gen);
  for (const auto& [name, text] : written) expected[name] = text;
  write_files(gen.string(), files);
  EXPECT_EQ(snapshot(gen), expected);
  EXPECT_EQ(entries_of(dir), std::vector<std::string>{"gen"});
}

TEST_F(WriteFiles, WritesTheTextByteForByte) {
  const std::string text = std::string("line\r\nnul:") + '\0' + "\xc3\xa9\n\n  trailing";
  write_files((dir / "gen").string(), {{"odd.txt", text}});
  EXPECT_EQ(read(dir / "gen" / "odd.txt"), text);
}

TEST_F(WriteFiles, WritingTwiceGivesTheSameDirectory) {
  write_files((dir / "gen").string(), files);
  write_files((dir / "gen").string(), files);
  EXPECT_EQ(snapshot(dir / "gen"), written);
}

TEST_F(WriteFiles, RefusesAnOutputPathThatIsAFile) {
  write(dir / "gen", "not a directory\n");
  try {
    write_files((dir / "gen").string(), files);
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "gen").string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not a directory"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read(dir / "gen"), "not a directory\n");
  EXPECT_EQ(entries_of(dir), std::vector<std::string>{"gen"});
}

// a file that cannot be created (its folder does not exist) makes the write fail midway
const std::vector<GeneratedFile> failing = {{"robot_dynamics.hpp", "// header\n"},
                                            {"missing_folder/robot_dynamics.cpp", "// source\n"}};

TEST_F(WriteFiles, AFailedWriteLeavesNoNewDirectory) {
  EXPECT_THROW(write_files((dir / "gen").string(), failing), std::exception);
  EXPECT_TRUE(entries_of(dir).empty()) << entries_of(dir).front();
}

TEST_F(WriteFiles, AFailedWriteInAnExistingDirectoryLeavesNoTemporaryFiles) {
  const fs::path gen = dir / "gen";
  write(gen / "build" / "CMakeCache.txt", "cache\n");
  EXPECT_THROW(write_files(gen.string(), failing), std::exception);
  for (const auto& [name, text] : snapshot(gen))
    EXPECT_EQ(name.find("dyngen-tmp"), std::string::npos) << name;
  EXPECT_EQ(read(gen / "build" / "CMakeCache.txt"), "cache\n");
}

// ---- the command's output directory

int run(const std::string& arguments) {
  const std::string command = std::string("'") + DYNGEN_EXECUTABLE + "' " + arguments +
                              " >/dev/null 2>&1";
  const int raw = std::system(command.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

const std::string planar5 = std::string(DYNGEN_TEST_MODELS) + "/planar5.yaml";

TEST_F(WriteFiles, CommandAcceptsAnOutputPathWithATrailingSlash) {
  // DESIGN.md's own example: dyngen robot.urdf -o gen/
  EXPECT_EQ(run("'" + planar5 + "' -q -o '" + (dir / "gen").string() + "/'"), 0);
  EXPECT_TRUE(fs::is_regular_file(dir / "gen" / "planar5_dynamics.cpp"));
  EXPECT_EQ(entries_of(dir), std::vector<std::string>{"gen"});
}

TEST_F(WriteFiles, CommandRegeneratesBesideTheUsersBuildFolder) {
  const fs::path gen = dir / "gen";
  ASSERT_EQ(run("'" + planar5 + "' -q -o '" + gen.string() + "'"), 0);
  const auto first = snapshot(gen);
  EXPECT_EQ(first.size(), 6u);
  write(gen / "build" / "CMakeCache.txt", "cache\n");
  ASSERT_EQ(run("'" + planar5 + "' -q -o '" + gen.string() + "' --algorithms rnea"), 0);
  const auto second = snapshot(gen);
  EXPECT_EQ(second.at("build/CMakeCache.txt"), "cache\n");
  EXPECT_NE(second.at("planar5_dynamics.cpp"), first.at("planar5_dynamics.cpp"));
  EXPECT_EQ(second.size(), first.size() + 2);
}

}  // namespace
