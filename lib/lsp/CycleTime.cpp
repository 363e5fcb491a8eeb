//! @file CycleTime.cpp
//! @brief The cycle time beside the code: after a document opens or is saved the server
//!        dry-runs its program when the input is idle (a message from the editor stops the run,
//!        which is done again later), then shows a code lens on the first line ("cycle 39.276 s ·
//!        148 blocks", or the runtime error), an inlay hint at the end of each line that ran
//!        with its own time, and the line's time, share and limiting factor in the hover. A
//!        subprogram shows the runs of the main programs of its folder that call it.
#include <poll.h>

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>

#include "lsp/Server.h"
#include "lsp/Uri.h"
#include "sim/TraceWriter.h"

namespace iso::lsp {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {
constexpr size_t kMaxMainsPerFolder = 8; ///< a subprogram shows the runs of at most so many main programs

std::string normalPath(const fs::path& p) {
  std::error_code ec;
  return fs::absolute(p, ec).lexically_normal().string();
}

/// The time a run spent on the lines of the file at `path`: per 1-based line.
std::map<uint32_t, const sim::LineProfile*> linesOf(const DryRun& r, const std::string& path) {
  std::map<uint32_t, const sim::LineProfile*> out;
  const std::string want = normalPath(path);
  std::string lastFile;
  bool lastMatch = false;
  for (const sim::LineProfile& lp : r.profile.lines) {
    if (lp.file != lastFile) {
      lastFile = lp.file;
      lastMatch = normalPath(fs::path(r.folder) / lp.file) == want;
    }
    if (lastMatch && lp.line > 0) out[lp.line] = &lp;
  }
  return out;
}

double totalOf(const std::map<uint32_t, const sim::LineProfile*>& lines) {
  double t = 0;
  for (const auto& [line, lp] : lines)
    t += lp->time.total();
  return t;
}

bool boolOption(const json& o, const char* key, bool fallback) {
  return o.contains(key) && o[key].is_boolean() ? o[key].get<bool>() : fallback;
}
} // namespace

void Server::readCycleTimeOptions(const json& params) {
  if (!params.is_object()) return;
  const json caps = params.value("capabilities", json::object());
  if (caps.is_object()) {
    lensRefresh_ = caps.value("/workspace/codeLens/refreshSupport"_json_pointer, json()) == true;
    hintRefresh_ = caps.value("/workspace/inlayHint/refreshSupport"_json_pointer, json()) == true;
  }
  const json o = params.value("/initializationOptions/cycleTime"_json_pointer, json());
  if (!o.is_object()) return;
  dryRunOpts_.enabled = boolOption(o, "enabled", dryRunOpts_.enabled);
  dryRunOpts_.inlayHints = boolOption(o, "inlayHints", dryRunOpts_.inlayHints);
  if (o.contains("budgetSeconds") && o["budgetSeconds"].is_number()) {
    const double b = o["budgetSeconds"].get<double>();
    if (b > 0 && b <= 3600) dryRunOpts_.budgetSeconds = b;
  }
  if (o.contains("inlayHintsMaxLines") && o["inlayHintsMaxLines"].is_number_unsigned())
    dryRunOpts_.inlayHintsMaxLines =
        static_cast<uint32_t>(std::min<uint64_t>(o["inlayHintsMaxLines"].get<uint64_t>(), UINT32_MAX));
}

void Server::queueDryRun(const std::string& uri) {
  if (!dryRunOpts_.enabled || !workspace_.document(uri) || !uriToPath(uri)) return;
  dryRunQueue_.insert(uri);
}

bool Server::inputWaiting() const {
  if (!reader_.idle()) return true;
  if (inputFd_ < 0) return false;
  pollfd p{inputFd_, POLLIN, 0};
  return ::poll(&p, 1, 0) > 0 && (p.revents & (POLLIN | POLLHUP)) != 0;
}

std::vector<std::string> Server::programsFor(const std::string& uri) {
  std::vector<std::string> out;
  const Analysis* a = workspace_.analysis(uri);
  const std::optional<uint32_t> file = a ? a->fileOf(uri) : std::nullopt;
  if (!file) return out;
  const frontend::File& f = a->set.files[*file];
  if (f.kind != lang::UnitKind::Sub) return {normalPath(f.path)};
  for (const frontend::File& g : a->set.files)
    if (g.kind == lang::UnitKind::Main && out.size() < kMaxMainsPerFolder) out.push_back(normalPath(g.path));
  return out;
}

std::vector<const DryRun*> Server::runsShownIn(const std::string& path) const {
  std::vector<const DryRun*> out;
  const std::string want = normalPath(path);
  if (auto own = dryRuns_.find(want); own != dryRuns_.end()) return {&own->second};
  const std::string folder = fs::path(want).parent_path().string();
  for (const auto& [program, run] : dryRuns_)
    if (fs::path(program).parent_path().string() == folder && !linesOf(run, want).empty()) out.push_back(&run);
  return out;
}

std::string Server::lensTitle(const std::string& path) const {
  const std::string want = normalPath(path);
  if (auto own = dryRuns_.find(want); own != dryRuns_.end()) return own->second.title;
  std::string title;
  for (const DryRun* r : runsShownIn(path)) {
    if (!title.empty()) title += "  |  ";
    const auto lines = linesOf(*r, path);
    const std::string main = fs::path(r->program).filename().string();
    if (r->state == DryRun::State::Ok)
      title += fmt::format("{} s here in {} (cycle {})", sim::formatNumber(std::round(totalOf(lines) * 1000) / 1000),
                           main, readableSeconds(r->summary.cycleTimeS));
    else
      title += fmt::format("{}: {}", main, r->title);
  }
  return title;
}

void Server::notifyDryRun(const std::string& uri, const char* state, const std::string& title) {
  send({{"jsonrpc", "2.0"},
        {"method", "isotools/dryRun"},
        {"params", {{"uri", uri}, {"state", state}, {"title", title}}}});
}

void Server::runDryRuns() {
  std::set<std::string> ran; // in this round: a program several queued documents show runs once
  while (!dryRunQueue_.empty() && !inputWaiting()) {
    const std::string uri = *dryRunQueue_.begin();
    const std::vector<std::string> programs = programsFor(uri);
    for (const std::string& p : programs) {
      if (ran.count(p)) continue;
      notifyDryRun(uri, "running", "dry run…");
      DryRun r = dryRun(p, policy_, dryRunOpts_, [this] { return inputWaiting(); });
      if (r.state == DryRun::State::Cancelled) {
        notifyDryRun(uri, "cancelled", r.title);
        return; // stays queued: it runs again when the input is idle
      }
      ran.insert(p);
      dryRuns_[p] = std::move(r);
    }
    dryRunQueue_.erase(uri);
    // every open document of the folder shows the new runs
    const std::string folder = fs::path(*uriToPath(uri)).parent_path().string();
    for (const std::string& doc : workspace_.documentsIn(folder)) {
      const std::optional<std::string> path = uriToPath(doc);
      if (!path) continue;
      const std::vector<const DryRun*> runs = runsShownIn(*path);
      if (runs.empty() && doc != uri) continue; // not run yet: its own turn comes
      const char* state = runs.empty() ? "none" : "ok";
      for (const DryRun* r : runs)
        if (r->state != DryRun::State::Ok) state = dryRunStateName(r->state);
      notifyDryRun(doc, state, lensTitle(*path));
    }
    if (lensRefresh_) send({{"jsonrpc", "2.0"}, {"id", nextRequestId_++}, {"method", "workspace/codeLens/refresh"}});
    if (hintRefresh_) send({{"jsonrpc", "2.0"}, {"id", nextRequestId_++}, {"method", "workspace/inlayHint/refresh"}});
  }
}

json Server::codeLenses(const std::string& uri) {
  json out = json::array();
  const std::optional<std::string> path = uriToPath(uri);
  if (!path || !workspace_.document(uri)) return out;
  const std::string title = lensTitle(*path);
  if (title.empty()) return out;
  auto lens = [](uint32_t line, const std::string& text) {
    return json{{"range", {{"start", {{"line", line}, {"character", 0}}}, {"end", {{"line", line}, {"character", 0}}}}},
                {"command", {{"title", text}, {"command", ""}}}};
  };
  out.push_back(lens(0, title));
  return out;
}

json Server::inlayHints(const std::string& uri, const json& params) {
  json out = json::array();
  const std::optional<std::string> path = uriToPath(uri);
  const TextDocument* doc = workspace_.document(uri);
  if (!path || !doc || !dryRunOpts_.inlayHints || doc->lineCount() > dryRunOpts_.inlayHintsMaxLines) return out;
  const std::vector<const DryRun*> runs = runsShownIn(*path);
  if (runs.empty()) return out;
  uint32_t first = 0, last = UINT32_MAX;
  const json start = params.value("/range/start/line"_json_pointer, json());
  const json end = params.value("/range/end/line"_json_pointer, json());
  if (start.is_number_unsigned()) first = static_cast<uint32_t>(std::min<uint64_t>(start.get<uint64_t>(), UINT32_MAX));
  if (end.is_number_unsigned()) last = static_cast<uint32_t>(std::min<uint64_t>(end.get<uint64_t>(), UINT32_MAX));
  for (const auto& [line, lp] : linesOf(*runs.front(), *path)) {
    const uint32_t l = line - 1;
    if (l < first || l > last || l >= doc->lineCount()) continue;
    const double t = lp->time.total();
    if (!(t > 0)) continue;
    const size_t lineStart = doc->offset({l, 0});
    const Position at = doc->position(lineStart + doc->line(l).size());
    out.push_back({{"position", {{"line", at.line}, {"character", at.character}}},
                   {"label", readableSeconds(t)},
                   {"paddingLeft", true}});
  }
  return out;
}

json Server::withLineTime(json hover, const std::string& uri, uint32_t line) {
  const std::optional<std::string> path = uriToPath(uri);
  if (!path) return hover;
  std::string text;
  for (const DryRun* r : runsShownIn(*path)) {
    const auto lines = linesOf(*r, *path);
    auto it = lines.find(line + 1);
    if (it == lines.end()) continue;
    const sim::LineProfile& lp = *it->second;
    const double t = lp.time.total();
    const double cycle = r->summary.cycleTimeS;
    text += fmt::format("**Dry run** ({}): {} on this line, {:.1f} % of the cycle {}; ran {} time{}",
                        fs::path(r->program).filename().string(), readableSeconds(t), cycle > 0 ? 100 * t / cycle : 0,
                        readableSeconds(cycle), lp.count, lp.count == 1 ? "" : "s");
    if (!lp.bounds.empty()) {
      text += "; limited by ";
      for (size_t i = 0; i < lp.bounds.size(); ++i)
        text += (i ? ", " : "") + lp.bounds[i];
    }
    text += "\n";
  }
  if (text.empty()) return hover;
  if (hover.is_null()) return {{"contents", {{"kind", markdownHover_ ? "markdown" : "plaintext"}, {"value", text}}}};
  json& value = hover["contents"]["value"];
  if (value.is_string()) value = value.get<std::string>() + "\n\n---\n\n" + text;
  return hover;
}

} // namespace iso::lsp
