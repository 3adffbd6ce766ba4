// From a loaded robot to the text of every emitted file, and writing them out.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "dyngen/numerics/conditioning_estimate.hpp"
#include "emit.hpp"
#include "footprint.hpp"
#include "names.hpp"
#include "output.hpp"
#include "robot.hpp"
#include "trace.hpp"

namespace dyngen::gen {

inline constexpr const char* version = "0.1.0";

/// The processor the code is meant for: dyngen warns where the scalar has no hardware there.
enum class Target { Host, CortexM4F, CortexM7, CortexM33 };

/// --target's names, in Target's order.
inline constexpr const char* target_names[] = {"host", "cortex-m4f", "cortex-m7", "cortex-m33"};

/// Whether the target's FPU computes in single precision only (double runs in software).
inline bool target_single_precision(Target t) {
  return t == Target::CortexM4F || t == Target::CortexM33;
}

struct GenerateOptions {
  std::string name;                     // file prefix and C++ namespace or C name prefix
  std::string language = "c++";        // --lang: a language of the backend registry (backend.cpp)
  std::vector<Algorithm> algorithms = default_algorithm_names();
  bool single_precision = false;        // float instead of double
  Structure structure = Structure::Auto;
  Target target = Target::Host;
  bool measure = false;                 // compile for the target and record code and stack
  int batch = 0;                        // lanes of the _batch and _many functions (C++); 0: none
  bool python = false;                  // a Python module over the batch functions (needs batch)
  bool torch = false;                   // and PyTorch functions over it (needs python)
  std::string options_text;             // the options as given, for the banner
  int conditioning_samples = 16;        // sampled states of the conditioning estimate
  std::function<void(const std::string&)> progress;  // told of each step as it starts, if set
};

/// CRBA carries each column of M up to the base, so its work and code grow with the sum over
/// joints of nv times depth (nv^2 / 2 for a chain): generation refuses CRBA above this many
/// such steps, a chain of 500 links (its cost: docs/performance.md, "The generator's limits").
inline constexpr long long max_crba_column_steps = 125000;

/// frame_jacobians computes a Jacobian column per degree of freedom between each frame and the
/// base: generation refuses it above this many such columns (500 frames along a 500-link chain;
/// README, "Limits"), whose code grows as CRBA's does ...
inline constexpr long long max_frame_columns = 125000;

/// ... and above this many entries of its output (frames times 6 nv: 1000 frames of a 1000-joint
/// star), which the trace, the check and every caller hold (README, "Limits").
inline constexpr long long max_frame_entries = 6000000;

/// minv and aba_derivatives fill every entry of an nv x nv matrix with work that grows with the
/// depth: generation refuses them above this many degrees of freedom (a 64-link chain's
/// aba_derivatives is about 1.5 million operations).
inline constexpr int max_dense_nv = 64;

struct FunctionCounts {
  Algorithm algorithm;
  OpCounts generated;  // in the emitted function
  OpCounts runtime;    // what runtime<T> performs for the same call
  int sections = 0, shared_sections = 0, shared_functions = 0;  // EmittedCode's
  int lane_blocks = 0;
  long lane_operations = 0;
};

struct Generated {
  std::vector<GeneratedFile> files;
  std::vector<FunctionCounts> counts;
  numerics::Conditioning conditioning;
  std::string conditioning_text;      // as the banner records it
  std::vector<std::string> warnings;  // digits the generated scalar is expected to lose
  std::optional<Footprint> footprint;  // when measured
  int nframes = 0;                     // frames the functions compute (0: no frame function)
};

/// Correct decimal digits below which dyngen warns that the generated scalar is not enough
/// (the estimate of numerics::Conditioning::aba_digits_lost, or constants outside float's range).
inline constexpr double min_float_digits = 3, min_double_digits = 6;


/// What --snap changed, in words, as the banner and the console say it.
std::string snap_text(const SnapReport& s);

/// The tolerance dyngen suggests snapping with (docs/performance.md, "Snapping").
inline constexpr double suggested_snap = 1e-9;

/// Without --snap: a note of the constants that --snap suggested_snap would make exact, or ""
/// when there are none.
std::string snap_note(const Model<double>& model);

/// The conditioning estimate in words (the ABA lines only if with_aba), as the banner and
/// dyngen report record it; aba_overflows names the scalar ("float") whose code of an algorithm
/// that divides by ABA's pivots overflows at extreme states (range.hpp), which then keeps no
/// digit there, or is null.
std::string conditioning_text(const numerics::Conditioning& c, bool with_aba,
                              const char* aba_overflows = nullptr);

/// Whether an algorithm has an array per frame (frame_placements, frame_jacobians, ...): the
/// algorithms that --frames is for.
bool uses_frames(const Algorithm& a);

/// Whether any of the algorithms has an output with entries per body (the regressor's Y): the
/// package then names its bodies.
bool uses_bodies(const std::vector<Algorithm>& algorithms);

/// Traces, simplifies and prints every requested algorithm. Throws InputError when ABA is
/// requested for a robot with a joint that moves no mass, CRBA for one above
/// max_crba_column_steps, frame Jacobians above max_frame_columns or max_frame_entries, float
/// code for constants beyond float's range, when a number the trace computes from the model's
/// constants alone overflows, and when an algorithm's values overflow at typical states
/// (range.hpp); warns when they do at extreme states.
Generated generate(const Robot& robot, const GenerateOptions& options);

/// Why generate refuses algorithm a in float (single) or double for this robot because its
/// values overflow at typical states (range.hpp), in words, or "" when they do not: dyngen
/// report leaves such algorithms out of its float variants.
std::string typical_overflow(const Robot& robot, const Algorithm& a, bool single);

}  // namespace dyngen::gen
