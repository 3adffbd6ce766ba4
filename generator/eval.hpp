// dyngen eval: the runtime's RNEA, CRBA and ABA at states given as JSON, so that a user can
// check a model against other software without writing code.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "dyngen/model.hpp"

namespace dyngen::gen {

/// Reads and parses a JSON file ("-": standard input); InputError names the file and the
/// position of a syntax error.
nlohmann::json read_states(const std::string& path);

/// states: an array of {"q": [nq], "v": [nv], "a": [nv]} and/or "tau": [nv]. Returns
/// {"joints": names of the v entries, "nq", "nv", "results": [{"tau" (RNEA, when a is given),
/// "M" (CRBA, rows), "qdd" (ABA, when tau is given)}]}. Throws InputError naming the state and
/// the field that is missing, of the wrong length, not a number, or (for a free joint's
/// quaternion) not of unit length within 1e-6.
nlohmann::json evaluate(const Model<double>& model, const nlohmann::json& states);

}  // namespace dyngen::gen
