// dyngen eval: the runtime's RNEA, CRBA and ABA at states given as JSON, so that a user can
// check a model against other software without writing code. The results are written as they
// are computed, so that a million states or a large robot's mass matrix need no JSON tree.
#pragma once

#include <cstdio>
#include <istream>
#include <string>
#include <vector>

#include "dyngen/model.hpp"

namespace dyngen::gen {

/// One state: q, v, and a and/or tau (an absent field is empty).
struct EvalState {
  std::vector<double> q, v, a, tau;
};

/// The states of a JSON array of {"q": [nq], "v": [nv], "a": [nv]} and/or "tau": [nv], read from
/// `in` (`name` in messages) one at a time, so that only their numbers are held. Throws
/// InputError naming the position of a syntax error, or the state and the field that is
/// missing, of the wrong length, not a number, or (for a free joint's quaternion) not of unit
/// length within 1e-6; and when a state gives tau but ABA is undefined for the model.
std::vector<EvalState> read_states(const Model<double>& model, std::istream& in,
                                   const std::string& name);

/// The same from a file ("-": standard input).
std::vector<EvalState> read_states(const Model<double>& model, const std::string& path);

/// Writes {"joints": names of the v entries, "nq", "nv", "results": [{"M" (CRBA, rows), "qdd"
/// (ABA, when tau is given), "tau" (RNEA, when a is given)}]} to `out`, as nlohmann::json's
/// dump(2) would, one result at a time as it is computed. With derivatives, each result also
/// has "Minv" and, when tau is given, "dqdd_dq" and "dqdd_dv" (aba_derivatives), when a is
/// given, "dtau_dq" and "dtau_dv" (rnea_derivatives), each a list of rows. With frames, each
/// result has "frames": {NAME: {"J": 6 rows of nv (base axes at the frame's origin, linear rows
/// first), "R": 3 rows, "p": [x, y, z]}} for each of the model's frames. Throws InputError
/// naming the state and the output that is not finite (before writing that state's results), or
/// for derivatives of a robot without ABA's pivots or above Workspace::max_matrix_nv, and
/// FileError when `out` (standard output) cannot be written.
void write_results(const Model<double>& model, const std::vector<EvalState>& states,
                   std::FILE* out, bool derivatives = false, bool frames = false);

}  // namespace dyngen::gen
