// dyngen eval: the runtime's RNEA, CRBA and ABA at states given as JSON, so that a user can
// check a model against other software without writing code. The states are read one at a
// time and each one's results are written as they are computed, so that a million states or a
// large robot's mass matrix need neither a JSON tree nor the results' text in memory.
#pragma once

#include <cstdio>
#include <istream>
#include <string>

#include "dyngen/model.hpp"

namespace dyngen::gen {

struct EvalOptions {
  bool derivatives = false;  // "Minv", and the derivatives of ABA and RNEA
  bool frames = false;       // "frames": each of the model's frames' R, p and J
  bool regressor = false;    // "Y": the inertial-parameter regressor, where a is given
};

/// Reads a JSON array of states {"q": [nq], "v": [nv], "a": [nv]} and/or "tau": [nv] from `in`
/// (`name` in messages) and writes {"joints": names of the v entries, "nq", "nv", "results":
/// [{"M" (CRBA, rows), "qdd" (ABA, when tau is given), "tau" (RNEA, when a is given)}]} to
/// `out`, as nlohmann::json's dump(2) would, each state's results as soon as the state is read
/// and computed. Names are written as safe_text writes them, which keeps the output valid UTF-8
/// and tells different names apart. With derivatives, each result also has "Minv" and, when
/// tau is given, "dqdd_dq" and "dqdd_dv" (aba_derivatives), when a is given, "dtau_dq" and
/// "dtau_dv" (rnea_derivatives), each a list of rows. With frames, each result has "frames":
/// {NAME: {"J": 6 rows of nv (base axes at the frame's origin, linear rows first), "R": 3 rows,
/// "p": [x, y, z]}} for each of the model's frames, and with v "Jdot_v" (6 numbers: the frame's
/// acceleration at qdd = 0). With regressor, each result with a has "Y", nv rows of 10 nbodies
/// (dyngen/regressor.hpp). A model with constraints (--contacts) adds "constraints" (their names)
/// and "nc" to the head; "qdd" is then contact_dynamics', with "lambda" (nc), and a state with v
/// also has impulse_dynamics' "v_plus" and "impulse" (dyngen/constrained.hpp).
///
/// Throws InputError, with nothing written for the state at fault, naming `name`, the state
/// and the field: for a syntax error (with its line and column), a number beyond double's range,
/// a field that is missing, unknown, repeated, of the wrong length or not an array of numbers,
/// a free or ball joint's quaternion that is not of unit length within 1e-6, tau where ABA is
/// undefined, or an output that is not finite; and before reading, for derivatives of a robot
/// without ABA's pivots, above Workspace::max_matrix_nv or with constraints. The results of the
/// states before the error stay written, without the closing brackets. Throws FileError when `out`
/// (standard output) cannot be written.
void evaluate(const Model<double>& model, std::istream& in, const std::string& name,
              std::FILE* out, const EvalOptions& options = {});

/// The same from a file ("-": standard input, named <stdin>).
void evaluate(const Model<double>& model, const std::string& path, std::FILE* out,
              const EvalOptions& options = {});

}  // namespace dyngen::gen
