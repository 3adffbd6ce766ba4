#include "readers.hpp"

#include <fmt/format.h>
#include <tinyxml2.h>

#include <algorithm>
#include <filesystem>

#include "process.hpp"

namespace dyngen::gen {

namespace {

std::string extension_of(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

/// "a", "a or b", "a, b or c".
std::string or_list(const std::vector<std::string>& items) {
  std::string text;
  for (std::size_t k = 0; k < items.size(); ++k)
    text += (k == 0 ? "" : k + 1 == items.size() ? " or " : ", ") + items[k];
  return text;
}

/// ur5.urdf.xacro: a URDF written with macros, which ROS's xacro expands.
RobotDescription refuse_xacro(const std::string& path, const std::string&) {
  std::string urdf = std::filesystem::path(path).stem().string();
  if (extension_of(urdf) != ".urdf") urdf += ".urdf";
  throw InputError(fmt::format(
      "{}: a xacro file (a URDF with macros): expand it to a URDF first, with ROS's xacro "
      "(xacro {} > {}), and give dyngen the .urdf",
      path, shell_word(path), shell_word(urdf)));
}

}  // namespace

const std::vector<Reader>& readers() {
  static const std::vector<Reader> table = {
      {"URDF", {".urdf", ".xml"}, "robot", parse_urdf},
      {"chain spec", {".yaml", ".yml"}, "", parse_chain},
      {"MJCF", {".xml"}, "mujoco", parse_mjcf},
      // refused by its extension: its root element is URDF's
      {"xacro", {".xacro"}, "", refuse_xacro, true},
  };
  return table;
}

std::string robot_file_formats() {
  std::vector<std::string> formats;
  for (const Reader& reader : readers()) {
    if (reader.refused) continue;
    std::string extensions;
    for (const std::string_view ext : reader.extensions)
      extensions += fmt::format("{}{}", extensions.empty() ? "" : ", ", ext);
    formats.push_back(fmt::format("{} ({})", reader.format, extensions));
  }
  return or_list(formats);
}

void parse_xml(const std::string& path, const std::string& xml, tinyxml2::XMLDocument& doc) {
  if (doc.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS)
    throw InputError(
        fmt::format("{}:{}: malformed XML: {}", path, doc.ErrorLineNum(), doc.ErrorStr()));
}

const Reader& reader_for(const std::string& path, const std::string& text) {
  const std::string ext = extension_of(path);
  std::vector<const Reader*> fits;
  for (const Reader& reader : readers())
    if (std::count(reader.extensions.begin(), reader.extensions.end(), ext))
      fits.push_back(&reader);
  if (fits.empty())
    throw InputError(
        fmt::format("{}: unknown kind of robot file; dyngen reads {}", path, robot_file_formats()));
  if (fits.size() == 1) return *fits[0];
  // formats that share the extension are XML with different root elements
  tinyxml2::XMLDocument doc;
  parse_xml(path, text, doc);
  const tinyxml2::XMLElement* root = doc.RootElement();  // none in a file of comments only
  std::vector<std::string> roots;
  for (const Reader* reader : fits) {
    if (root && reader->root == root->Name()) return *reader;
    roots.push_back(fmt::format("<{}> for {}", reader->root, reader->format));
  }
  throw InputError(fmt::format("{}: {}: dyngen expects {} in a {} file", path,
                               root ? fmt::format("root element <{}>", root->Name()) : "no element",
                               or_list(roots), ext));
}

}  // namespace dyngen::gen
