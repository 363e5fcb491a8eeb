//! @file Support.h
//! @brief What several fuzz targets check the same way: a compiled program set must load back
//!        through the image reader and verifier; a verified image must run within small budgets
//!        to ok/error/emergency without throwing. Linked into every target (not a target itself:
//!        only Fuzz*.cpp are).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "compiler/Compiler.h"
#include "frontend/ProgramSet.h"
#include "image/Image.h"
#include "image/ImageVerifier.h"
#include "machine/Machine.h"
#include "sim/Run.h"

namespace iso::fuzz {

/// Prints "<target>: <what><detail>" to stderr and traps (the fuzzer reports a crash).
[[noreturn]] void fail(const char* target, const char* what, const std::string& detail = {});

/// True when `set` has an error-severity diagnostic (then the compiler must not run).
bool hasErrors(const frontend::ProgramSet& set);

/// isolint's compact load (LoadOptions::compactTrees) must give the diagnostics and flow facts
/// of the full load `full`, and so must its split into parts for two threads (SplitOptions, 3
/// parts, from a wrong guess): loads `text` again both ways and compares (a difference is a
/// crash).
void checkCompactLoad(const frontend::ProgramSet& full, const std::string& path, const std::string& text,
                      frontend::LoadOptions opts, const char* target);

/// The lexer's fast path (LexOptions::fastPaths) must give the tokens and diagnostics of its
/// general path on `text` (a difference is a crash).
void checkLexerPaths(const std::string& text, machine::Dialect dialect, const char* target);

/// Compiles `set` (no error diagnostics) and loads the image back from its bytes as isosim does:
/// false when the compiler refuses the set (e.g. no main program), else `out` is the image read
/// back and verified; an image its own reader or verifier refuses is a crash.
bool compileAndLoad(const frontend::ProgramSet& set, const compiler::CompileOptions& opts,
                    std::optional<image::VerifiedImage>& out, const char* target);

/// The small budgets of a run under the fuzzer.
struct Budget {
  uint64_t maxSteps = 2000;
  double maxTime = 100;
  double dt = 0.5;
};

/// Runs a verified image, summary only, and checks the outcome: no exception, a decodable image,
/// status ok/error/emergency, at most `maxSteps` statements, a cycle time within `maxTime`, a
/// message iff not ok. Returns the result (setup errors other than a missing axis are a crash).
sim::SimResult runBounded(const image::VerifiedImage& img, const machine::Machine& m, const std::string& entry,
                          bool blockSkip, const Budget& budget, const char* target);

/// Every byte of `out` belongs to a "Content-Length: N\r\n\r\n" frame whose body is JSON
/// (else `target` fails); `check` gets each parsed body and its first 200 bytes.
void forEachFrame(const char* target, std::string_view out,
                  const std::function<void(const nlohmann::json&, const std::string&)>& check);

} // namespace iso::fuzz
