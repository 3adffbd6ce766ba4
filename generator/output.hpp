// Writing what dyngen produces without losing the user's files or leaving half of it: a package
// goes into a new or empty directory, or replaces a package dyngen wrote, whole; a failure
// leaves the directory as it was and no temporary behind.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace dyngen::gen {

struct GeneratedFile {
  std::string name;
  std::string text;
};

/// Writes `text` to `path`, replacing it; FileError naming the path and the system's reason
/// (No space left on device, Permission denied) when that fails.
void write_file(const std::filesystem::path& path, const std::string& text);

/// Whether dir holds a package that dyngen wrote and may replace: every file in it starts with
/// dyngen's banner (or is the dyngen_sincos.h (dyngen_sincos.hpp before 0.2) or
/// dyngen_kernels.hpp it copies), at least one does, and every folder in it is a CMake build tree
/// (has a CMakeCache.txt), such as the build/ of the README.
bool is_dyngen_package(const std::filesystem::path& dir);

/// Writes files as the package in dir. A new directory (with missing parents, removed again if
/// writing fails) appears whole; an empty one, or one that is_dyngen_package(), is replaced
/// whole and atomically by a directory assembled beside it, into which the CMake build trees of
/// the old package move, so that they are kept. Any other existing directory, and the current
/// directory (which the shell would lose), is refused (FileError, naming what is in the way)
/// unless `force`, which stages every file in a folder inside dir, then moves each into place
/// by a rename, and leaves the rest alone. Staging directories are named `.NAME.dyngen-tmp-PID`
/// beside dir (a NAME too long for that cut, and completed by a digest of it) or
/// `.dyngen-tmp-PID` inside it; those of processes that died (killed while writing) are removed
/// on the next write.
void write_package(const std::string& dir, const std::vector<GeneratedFile>& files,
                   bool force = false);

/// What dir holds besides what a command that writes `files` (each whole: a leftover NAME.tmp
/// counts as NAME) and works in `folders` writes, sorted (folders with a trailing /): the entries
/// that keep it from writing into dir without --force. None when dir does not exist. FileError
/// when dir is not a directory.
std::vector<std::string> foreign_entries(const std::filesystem::path& dir,
                                         const std::vector<std::string>& files,
                                         const std::vector<std::string>& folders);

/// The first names and how many more: "a, b, c and 4 more".
std::string listed(const std::vector<std::string>& names);

/// Throws what write_package would about dir (an empty path, a file, a directory it may not
/// write into), so that a command can refuse before it works.
void check_output_dir(const std::string& dir, bool force = false);

}  // namespace dyngen::gen
