// The robot files dyngen knows, in one table: parse_robot picks the reader through it, and the
// CLI's help and the errors that list the formats are built from it. A new format is one entry.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "robot.hpp"

namespace tinyxml2 {
class XMLDocument;
}

namespace dyngen::gen {

/// The robot in `text`, read from `path` (which messages name): the readers of the table.
RobotDescription parse_urdf(const std::string& path, const std::string& text);
RobotDescription parse_chain(const std::string& path, const std::string& text);
RobotDescription parse_mjcf(const std::string& path, const std::string& text);

struct Reader {
  std::string_view format;                   // as --help and messages name it: "URDF"
  std::vector<std::string_view> extensions;  // lower case, with the dot
  /// An XML format's root element: it tells apart the formats that share an extension (.xml is
  /// URDF's and MJCF's). Empty for the others.
  std::string_view root;
  /// Reads the file; for a format dyngen recognises but does not read, throws the InputError
  /// that says why and what to give it instead.
  RobotDescription (*parse)(const std::string& path, const std::string& text);
  bool refused = false;  // recognised only to be refused (parse throws); left out of --help
};

/// Every format, read or refused: URDF, chain spec, MJCF, xacro.
const std::vector<Reader>& readers();

/// The formats dyngen reads with their extensions, for --help and messages:
/// "URDF (.urdf, .xml) or chain spec (.yaml, .yml)".
std::string robot_file_formats();

/// The reader of the file at `path` with `text`: by its extension, and among the formats that
/// share it by its root element. InputError naming the file when no format fits.
const Reader& reader_for(const std::string& path, const std::string& text);

/// Parses `xml` into `doc`; InputError "PATH:LINE: malformed XML: ..." when it is not XML.
void parse_xml(const std::string& path, const std::string& xml, tinyxml2::XMLDocument& doc);

}  // namespace dyngen::gen
