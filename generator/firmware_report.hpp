// dyngen firmware-report ROBOT -o DIR --target cortex-m4f|cortex-m7|cortex-m33: what a package costs and
// computes on the microcontroller, measured under qemu rather than estimated: per function its
// code bytes and stack bound (the banner's, from --measure), the stack it used (painted), the
// instructions per call, and whether its outputs equal the host's bit for bit; and that the
// image links no C library, no libm and, in float, no software double.
#pragma once

#include <string>
#include <vector>

#include "generate.hpp"
#include "robot.hpp"

namespace dyngen::gen {

struct FirmwareReportOptions {
  GenerateOptions generate;  // the package: its target is the processor; measured always
  int states = 8;            // states each function runs on (the last with large angles)
  std::string command;       // the command line, for the report
  bool quiet = false;
  bool force = false;        // write into a directory that holds other files too
};

/// What dyngen firmware-report writes into DIR, besides package/ (the generated code) and
/// build/ (the harness, its objects and images).
inline constexpr const char* firmware_report_files[] = {"firmware-report.md",
                                                        "firmware-report.json"};

/// The targets firmware-report runs, on qemu's mps2-an386, mps2-an500 and mps2-an505.
inline constexpr const char* firmware_report_targets[] = {"cortex-m4f", "cortex-m7",
                                                          "cortex-m33"};

/// Generates the package into dir/package, builds the harness for the target and the host in
/// dir/build, runs both, and writes the report. Returns the checks that failed (none: empty).
/// Throws InputError when a tool is missing or a build fails.
std::vector<std::string> make_firmware_report(const Robot& robot,
                                              const FirmwareReportOptions& options,
                                              const std::string& dir);

}  // namespace dyngen::gen
