//! @file Support.cpp
#include "Support.h"

#include <cstdio>
#include <cstring>
#include <deque>
#include <exception>
#include <string>
#include <vector>

#include "frontend/Lexer.h"
#include "image/ImageReader.h"
#include "image/ImageVerifier.h"
#include "image/ImageWriter.h"

namespace iso::fuzz {

void fail(const char* target, const char* what, const std::string& detail) {
  std::fprintf(stderr, "%s: %s%s\n", target, what, detail.c_str());
  __builtin_trap();
}

bool hasErrors(const frontend::ProgramSet& set) {
  for (const auto& d : set.diags.items())
    if (d.severity == diag::Severity::Error) return true;
  return false;
}

namespace {
bool sameLoc(const diag::Loc& a, const diag::Loc& b) { return a.file == b.file && a.line == b.line && a.col == b.col; }

bool sameDiagnostic(const diag::Diagnostic& a, const diag::Diagnostic& b) {
  if (a.code != b.code || a.severity != b.severity || !sameLoc(a.loc, b.loc) || a.endLine != b.endLine ||
      a.endCol != b.endCol || a.message != b.message || a.notes.size() != b.notes.size() ||
      a.fixes.size() != b.fixes.size())
    return false;
  for (size_t i = 0; i < a.notes.size(); ++i)
    if (!sameLoc(a.notes[i].loc, b.notes[i].loc) || a.notes[i].message != b.notes[i].message) return false;
  for (size_t i = 0; i < a.fixes.size(); ++i)
    if (a.fixes[i].description != b.fixes[i].description || a.fixes[i].edits.size() != b.fixes[i].edits.size())
      return false;
  return true;
}
} // namespace

namespace {
/// `other` (a compact load, split or not) says what `full` says.
void checkSameAs(const frontend::ProgramSet& full, const frontend::ProgramSet& other, const char* target,
                 const char* what) {
  const auto& a = full.diags.items();
  const auto& b = other.diags.items();
  if (a.size() != b.size())
    fail(target, what, ": diagnostic count " + std::to_string(a.size()) + " vs " + std::to_string(b.size()));
  for (size_t i = 0; i < a.size(); ++i)
    if (!sameDiagnostic(a[i], b[i])) fail(target, what, ": diagnostic differs: " + a[i].message);
  for (size_t i = 0; i < full.flows.size(); ++i)
    if (full.flows[i].match != other.flows[i].match || full.flows[i].reachable != other.flows[i].reachable ||
        full.flows[i].endReachable != other.flows[i].endReachable || full.files[i].kind != other.files[i].kind)
      fail(target, what, ": flow facts differ");
}
} // namespace

void checkCompactLoad(const frontend::ProgramSet& full, const std::string& path, const std::string& text,
                      frontend::LoadOptions opts, const char* target) {
  opts.compactTrees = true;
  frontend::ProgramSet compact;
  frontend::loadSingleSource(path, text, opts, compact);
  checkSameAs(full, compact, target, "compact load");
  // isolint's split of a large file into parts for two threads, here in 3 parts (at the first
  // line starts after a third and two thirds), each after the first starting from the state
  // after the first statement (a wrong guess that the join must catch)
  opts.jobs = 2;
  opts.splitting = {.minBytes = 0, .parts = 3, .guessAfter = 1};
  frontend::ProgramSet split;
  frontend::loadSingleSource(path, text, opts, split);
  checkSameAs(full, split, target, "split load");
}

namespace {
struct Lexed {
  std::vector<frontend::LogicalLine> lines;
  diag::DiagnosticList diags;
  std::vector<frontend::Suppression> suppressions;
  std::deque<std::string> owned;
};

void lexAll(const std::string& text, machine::Dialect dialect, bool fast, Lexed& out) {
  frontend::LexOptions lo;
  lo.dialect = dialect;
  lo.fastPaths = fast;
  frontend::Lexer lexer(text, 0, lo, out.diags, out.suppressions, out.owned);
  frontend::LogicalLine line;
  while (lexer.next(line))
    out.lines.push_back(line);
}

bool sameToken(const frontend::Token& a, const frontend::Token& b) {
  return a.kind == b.kind && std::memcmp(a.addr, b.addr, sizeof a.addr) == 0 && a.hasSep == b.hasSep &&
         a.tooManyDigits == b.tooManyDigits && a.hasSign == b.hasSign && a.joined == b.joined && a.sysvar == b.sysvar &&
         a.line == b.line && a.col == b.col && a.len == b.len && std::memcmp(&a.value, &b.value, sizeof a.value) == 0 &&
         a.text == b.text;
}
} // namespace

void checkLexerPaths(const std::string& text, machine::Dialect dialect, const char* target) {
  Lexed fast, general;
  lexAll(text, dialect, true, fast);
  lexAll(text, dialect, false, general);
  if (fast.lines.size() != general.lines.size()) fail(target, "lexer paths: line count differs");
  for (size_t i = 0; i < fast.lines.size(); ++i) {
    const auto& a = fast.lines[i];
    const auto& b = general.lines[i];
    if (a.firstLine != b.firstLine || a.lastLine != b.lastLine || a.length != b.length || a.hadError != b.hadError ||
        a.truncated != b.truncated || a.tokens.size() != b.tokens.size())
      fail(target, "lexer paths: logical line differs at ", std::to_string(a.firstLine));
    for (size_t k = 0; k < a.tokens.size(); ++k)
      if (!sameToken(a.tokens[k], b.tokens[k]))
        fail(target, "lexer paths: token differs at line ", std::to_string(a.tokens[k].line));
  }
  const auto& da = fast.diags.items();
  const auto& db = general.diags.items();
  if (da.size() != db.size()) fail(target, "lexer paths: diagnostic count differs");
  for (size_t i = 0; i < da.size(); ++i)
    if (!sameDiagnostic(da[i], db[i])) fail(target, "lexer paths: diagnostic differs: ", da[i].message);
}

bool compileAndLoad(const frontend::ProgramSet& set, const compiler::CompileOptions& opts,
                    std::optional<image::VerifiedImage>& out, const char* target) {
  image::Image compiled;
  compiler::CompileError cerr;
  if (!compiler::compileProgramSet(set, opts, compiled, cerr)) return false;
  const std::vector<uint8_t> bytes = image::writeImage(compiled);
  image::ImageError ierr;
  image::Layout layout;
  image::Image read;
  if (image::readImage(bytes, read, ierr, &layout)) out = image::verifyImage(std::move(read), ierr, &layout);
  if (!out) fail(target, "the compiler wrote an image its own loader refuses: ", ierr.message);
  return true;
}

sim::SimResult runBounded(const image::VerifiedImage& img, const machine::Machine& m, const std::string& entry,
                          bool blockSkip, const Budget& budget, const char* target) {
  sim::SimOptions opts;
  opts.maxSteps = budget.maxSteps;
  opts.maxTime = budget.maxTime;
  opts.dt = budget.dt;
  opts.entry = entry;
  opts.blockSkip = blockSkip;
  sim::SimResult r;
  try {
    r = sim::simulate(img, m, opts, nullptr);
  } catch (const std::exception& e) {
    fail(target, "simulate threw: ", e.what());
  } catch (...) {
    fail(target, "simulate threw a non-standard exception");
  }
  switch (r.setupError) {
  case sim::SetupError::None: break;
  case sim::SetupError::AxisMissing: return r; // an axis the machine lacks: exit 2, fine
  case sim::SetupError::InvalidImage: fail(target, "a verified image does not decode: ", r.setupMessage);
  case sim::SetupError::UnknownEntry: fail(target, "an entry the image names is unknown: ", r.setupMessage);
  }
  const sim::Summary& s = r.summary;
  if (s.status != sim::Status::Ok && s.status != sim::Status::Error && s.status != sim::Status::Emergency)
    fail(target, "status not ok/error/emergency");
  if (s.blocks >= budget.maxSteps) fail(target, "--max-steps statements or more ran (SPEC §6.3: the last one stops)");
  if (!(s.cycleTimeS >= 0) || s.cycleTimeS > budget.maxTime * (1 + 1e-9) + 1e-9)
    fail(target, "cycle time negative or over --max-time");
  if ((s.status == sim::Status::Ok) != s.message.empty()) fail(target, "status ok iff no message");
  if (s.finalPosition.size() != m.axes.size()) fail(target, "final position of the wrong size");
  return r;
}

void forEachFrame(const char* target, std::string_view out,
                  const std::function<void(const nlohmann::json&, const std::string&)>& check) {
  constexpr std::string_view kHead = "Content-Length: ";
  while (!out.empty()) {
    if (out.substr(0, kHead.size()) != kHead) fail(target, "output is not a frame: ", std::string(out.substr(0, 80)));
    out.remove_prefix(kHead.size());
    size_t n = 0, i = 0;
    while (i < out.size() && out[i] >= '0' && out[i] <= '9' && i < 12)
      n = n * 10 + static_cast<size_t>(out[i++] - '0');
    if (i == 0 || out.substr(i, 4) != "\r\n\r\n" || out.size() - i - 4 < n)
      fail(target, "a malformed or truncated frame: ", std::string(out.substr(0, 80)));
    const std::string body(out.substr(i + 4, n));
    out.remove_prefix(i + 4 + n);
    nlohmann::json m = nlohmann::json::parse(body, nullptr, false);
    if (m.is_discarded()) fail(target, "a body that is not JSON: ", body.substr(0, 200));
    check(m, body.substr(0, 200));
  }
}

} // namespace iso::fuzz
