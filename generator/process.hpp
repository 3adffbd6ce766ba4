// Running the tools dyngen drives (CMake, compilers, qemu, gnuplot) through the shell.
#pragma once

#include <filesystem>
#include <string>

namespace dyngen::gen {

/// s as one shell word: 'it'\''s'.
std::string shell_quoted(const std::string& s);

/// Runs a shell command with its output in log (and echoed, indented, if echo); throws
/// std::runtime_error with the log's last lines when it fails.
void run_logged(const std::string& what, const std::string& command,
                const std::filesystem::path& log, bool echo);

/// The output (standard output and error) of a shell command; InputError saying `what` failed,
/// with the output's end, when the command fails or is missing.
std::string output_of(const std::string& command, const std::string& what);

}  // namespace dyngen::gen
