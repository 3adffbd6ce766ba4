// From a loaded robot to the text of every emitted file, and writing them out.
#pragma once

#include <string>
#include <vector>

#include "emit.hpp"
#include "robot.hpp"
#include "trace.hpp"

namespace dyngen::gen {

inline constexpr const char* version = "0.1.0";

struct GenerateOptions {
  std::string name;                     // file prefix and C++ namespace
  std::vector<Algorithm> algorithms{Algorithm::Rnea, Algorithm::Crba, Algorithm::Aba};
  bool single_precision = false;        // float instead of double
  std::string options_text;             // the options as given, for the banner
};

struct FunctionCounts {
  Algorithm algorithm;
  OpCounts generated;  // in the emitted function
  OpCounts runtime;    // what runtime<T> performs for the same call
};

struct GeneratedFile {
  std::string name;
  std::string text;
};

struct Generated {
  std::vector<GeneratedFile> files;
  std::vector<FunctionCounts> counts;
};

/// A valid C++ identifier from a robot name ("my-robot" -> "my_robot").
std::string identifier(const std::string& name);

/// Traces, simplifies and prints every requested algorithm. Throws InputError when ABA is
/// requested for a robot with a joint that moves no mass.
Generated generate(const Robot& robot, const GenerateOptions& options);

/// Writes the files into dir, creating it if needed. Each file is written to a temporary name
/// and renamed into place, so a failure leaves no half-written file; a new directory is
/// assembled under a temporary name and renamed as a whole.
void write_files(const std::string& dir, const std::vector<GeneratedFile>& files);

}  // namespace dyngen::gen
