// Running the tools dyngen drives: CMake, qemu and gnuplot through the shell, compilers without
// one.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace dyngen::gen {

/// s as one shell word: 'it'\''s'.
std::string shell_quoted(const std::string& s);

/// s as one shell word, quoted only if it must be: ur5.urdf, 'my robot.urdf'.
std::string shell_word(const std::string& s);

/// The words of a command held in a variable such as $CXX ("ccache g++" is two), split at
/// blanks as make and CMake split them, without a shell: no quotes, no expansion.
std::vector<std::string> command_words(const std::string& text);

/// How a process ended, from its wait status: "exit status 1", "killed by signal 9 (Killed)";
/// from a shell (`shell`), 127 is "not found", the shell's status for a missing command.
std::string ending(int status, bool shell);

/// Runs a shell command with its output in log (and echoed, indented, if echo); throws
/// std::runtime_error with the log's last lines when it fails.
void run_logged(const std::string& what, const std::string& command,
                const std::filesystem::path& log, bool echo);

/// The output (standard output and error) of a shell command; InputError saying `what` failed,
/// with the output's end, when the command fails or is missing.
std::string output_of(const std::string& command, const std::string& what);

/// The same for a command run without a shell, argv[0] looked up in PATH; "ARGV0: not found"
/// when it is not there.
std::string output_of(const std::vector<std::string>& argv, const std::string& what);

}  // namespace dyngen::gen
