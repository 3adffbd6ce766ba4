// Fuzz target: any bytes as dyngen eval's states (the first byte chooses a floating base,
// --derivatives and --frames), on a small robot whose names hold invalid UTF-8 and whose
// prismatic joint lets outputs overflow. Eval must succeed or throw InputError; what it writes
// must be JSON without null (a non-finite number), and on success hold a result per state.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "eval.hpp"
#include "fuzz_robot.hpp"
#include "robot.hpp"

namespace {

const char* robot_text =
    "<robot name=\"fuzz\"><link name=\"base\"><inertial><mass value=\"2\"/>"
    "<inertia ixx=\"0.1\" ixy=\"0\" ixz=\"0\" iyy=\"0.1\" iyz=\"0\" izz=\"0.1\"/></inertial></link>"
    "<link name=\"arm\xfe\"><inertial><origin xyz=\"0.1 0 0\"/><mass value=\"1\"/>"
    "<inertia ixx=\"0.1\" ixy=\"0\" ixz=\"0\" iyy=\"0.2\" iyz=\"0\" izz=\"0.2\"/></inertial></link>"
    "<link name=\"tip\xff\"><inertial><mass value=\"0.5\"/>"
    "<inertia ixx=\"0.1\" ixy=\"0\" ixz=\"0\" iyy=\"0.1\" iyz=\"0\" izz=\"0.1\"/></inertial></link>"
    "<joint name=\"j\xfe\" type=\"continuous\"><parent link=\"base\"/><child link=\"arm\xfe\"/>"
    "<axis xyz=\"0 0 1\"/></joint>"
    "<joint name=\"slide\" type=\"prismatic\"><parent link=\"arm\xfe\"/><child link=\"tip\xff\"/>"
    "<origin xyz=\"0.3 0 0\"/><axis xyz=\"1 0 0\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" "
    "velocity=\"1\"/></joint></robot>";

dyngen::Model<double> load(bool floating) {
  dyngen::gen::LoadOptions options;
  options.floating_base = floating;
  options.all_frames = true;
  return dyngen::gen::parse_robot("fuzz.urdf", robot_text, options).model;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const dyngen::Model<double> models[2] = {load(false), load(true)};
  const dyngen::Model<double>& model = models[data[0] & 1];
  const std::string states(reinterpret_cast<const char*>(data) + 1, size - 1);
  std::istringstream in(states);
  char* buffer = nullptr;
  std::size_t length = 0;
  std::FILE* out = open_memstream(&buffer, &length);
  bool accepted = true;
  try {
    dyngen::gen::evaluate(model, in, "fuzz.json", out, {(data[0] & 2) != 0, (data[0] & 4) != 0});
  } catch (const dyngen::gen::InputError&) {
    accepted = false;
  } catch (const std::exception& e) {
    dyngen::fuzz::finding(std::string("eval threw ") + e.what());
  }
  std::fclose(out);
  const std::string text(buffer, length);
  std::free(buffer);
  if (text.find("null") != std::string::npos) dyngen::fuzz::finding("eval wrote null");
  if (!accepted) return 0;
  nlohmann::json results, input;
  try {
    results = nlohmann::json::parse(text)["results"];
    input = nlohmann::json::parse(states);
  } catch (const nlohmann::json::exception& e) {
    dyngen::fuzz::finding(std::string("eval's output or accepted input is not JSON: ") + e.what());
  }
  if (!results.is_array() || results.size() != input.size())
    dyngen::fuzz::finding("eval wrote " + std::to_string(results.size()) + " results for " +
                          std::to_string(input.size()) + " states");
  for (const nlohmann::json& result : results)
    if (result["M"].size() != static_cast<std::size_t>(model.nv))
      dyngen::fuzz::finding("a result's M has " + std::to_string(result["M"].size()) + " rows");
  return 0;
}
