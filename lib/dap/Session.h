//! @file Session.h
//! @brief One debug session of isosim --dap (private to lib/dap): the protocol's requests,
//!        the breakpoints and steps, and the hook the run calls (sim::DebugHook).
#pragma once

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dap/DebugAdapter.h"
#include "dap/Evaluate.h"
#include "driver/Simulate.h"
#include "lsp/JsonRpc.h"
#include "sim/Debug.h"

namespace iso::dap {

/// The largest message accepted (16 MiB): a breakpoint list of a whole CAM program fits.
inline constexpr size_t kMaxDapMessageBytes = size_t{16} << 20;
/// Breakpoints in one request, and in the session.
inline constexpr size_t kMaxBreakpoints = 100'000;

/// A breakpoint's hit condition: `N` or `==N` (the Nth hit), `>N`, `>=N`, `<N`, `<=N`, `%N`
/// (every Nth hit).
struct HitCondition {
  enum class Op : uint8_t { Always, Eq, Gt, Ge, Lt, Le, Mod } op = Op::Always;
  uint64_t n = 0;
  bool holds(uint64_t hits) const;
  /// nullopt: not a hit condition.
  static std::optional<HitCondition> parse(const std::string& text);
};

/// A line or function breakpoint, resolved to the statements it stops at.
struct Breakpoint {
  int id = 0;
  bool verified = false;
  std::string message;           ///< why it is not verified, or what it became
  std::string path;              ///< line breakpoints: the client's path
  int line = 0;                  ///< the line asked for
  int actualLine = 0;            ///< the line it stops at (0: none)
  std::string function;          ///< function breakpoints: the name
  double time = -1;              ///< time breakpoints: the simulated time (s), else < 0
  bool fired = false;            ///< time breakpoints: the run passed it
  std::vector<uint32_t> entries; ///< the line-table rows it stops at
  std::string conditionText;     ///< as written
  std::optional<Expression> condition;
  HitCondition hit;
  uint64_t hits = 0;
};

class Session final : public sim::DebugHook {
public:
  Session(std::istream& in, std::ostream& out, const AdapterOptions& opts);
  int run();

  // sim::DebugHook
  bool statement(const sim::RunView& view, uint32_t thread, uint32_t lineEntry, size_t depth) override;
  double nextTimeStop() const override;
  bool timeReached(const sim::RunView& view) override;
  void fault(const sim::RunView& view, sim::Status status, const std::string& message, uint32_t thread) override;

private:
  using json = nlohmann::json;
  enum class Step : uint8_t { None, Over, In, Out };

  // ---- protocol (Session.cpp)
  void handle(const std::string& body);
  void request(const json& req);
  void respond(const json& req, json body = json::object());
  void fail(const json& req, const std::string& message);
  void event(const std::string& name, json body = json::object());
  void output(const std::string& category, const std::string& text);
  void send(json message);
  /// Reads and handles messages until the run resumes (or the client goes away).
  void waitWhileStopped();
  /// Handles the messages that arrived while the program runs.
  void pollWhileRunning();

  // ---- requests
  json initialize();
  void launch(const json& req, const json& args);
  void execute();
  json setBreakpoints(const json& args);
  json setFunctionBreakpoints(const json& args);
  void setExceptionBreakpoints(const json& args);
  void resume(const json& req, Step step, const json& args);
  void runToTime(const json& req, const json& args);
  json threads() const;
  json stackTrace(const json& args) const;
  json scopes(const json& args);
  json variables(const json& args);
  json evaluate(const json& args) const;
  json exceptionInfo() const;

  // ---- breakpoints (Breakpoints.cpp)
  /// Reads a breakpoint's condition and hit condition from `b` into `bp` (false: refused,
  /// bp.message says why).
  bool readConditions(const json& b, Breakpoint& bp) const;
  /// Parses bp's condition once the program is loaded (false: bp refused, message set).
  bool compileCondition(Breakpoint& bp) const;
  /// The program is loaded and bp's condition parsed (false: bp refused, message set).
  bool loaded(Breakpoint& bp) const;
  void resolveLine(Breakpoint& bp);
  void resolveFunction(Breakpoint& bp);
  void rebuildIndex();
  json breakpointJson(const Breakpoint& bp) const;
  /// The breakpoints at `lineEntry` that stop now (conditions and hit counts applied).
  std::vector<int> breakpointsHit(const sim::RunView& view, uint32_t lineEntry);
  /// Breakpoint `bp` is reached: whether it stops there (its condition holds, or cannot be
  /// evaluated; its hit condition holds for this hit).
  bool stops(Breakpoint& bp, const sim::RunView& view);
  bool stepDone(const sim::RunView& view, uint32_t thread, size_t depth) const;
  void stop(const sim::RunView& view, const std::string& reason, uint32_t thread, const std::vector<int>& hit,
            const std::string& text);
  std::string clientPath(uint32_t fileString) const;   ///< an image file's path for the client
  std::string clientPath(std::string_view file) const; ///< a path the image records, for the client
  std::optional<uint32_t> imageFile(const std::string& clientPath) const;

  // ---- variables (Variables.cpp)
  json scopeVariables(uint32_t thread, int kind, int index) const;
  int reference(uint32_t thread, int kind, int index);

  lsp::MessageReader reader_;
  std::ostream& out_;
  AdapterOptions opts_;
  int64_t seq_ = 1;
  bool initialized_ = false;
  bool launched_ = false;
  bool started_ = false;
  bool startRun_ = false;
  bool ended_ = false;
  bool disconnected_ = false;

  driver::PreparedRun prepared_;
  std::filesystem::path base_; ///< the folder the image's file names are relative to
  bool stopOnEntry_ = false;
  bool noDebug_ = false;
  std::string programName_;

  std::map<std::string, std::vector<Breakpoint>> lineBps_; ///< by the client's path
  std::vector<Breakpoint> functionBps_;
  int nextBpId_ = 1;
  bool breakOnError_ = true;
  bool breakOnEmergency_ = true;
  std::vector<uint8_t> marked_;                        ///< by line-table row: a breakpoint is there
  std::map<uint32_t, std::vector<Breakpoint*>> bpsAt_; ///< by line-table row

  // ---- the stop
  const sim::RunView* view_ = nullptr;
  uint32_t stoppedThread_ = 0;
  bool resume_ = false;
  bool abort_ = false;
  Step step_ = Step::None;
  uint32_t stepThread_ = 0;
  size_t stepDepth_ = 0;
  bool pauseRequested_ = false;
  bool entryPending_ = false;
  double runTo_ = std::numeric_limits<double>::infinity();
  uint64_t calls_ = 0;
  struct ExceptionStop {
    std::string id;
    std::string description;
  };
  std::optional<ExceptionStop> exception_;
  struct Ref {
    uint32_t thread = 0;
    int kind = 0;
    int index = -1;
  };
  std::vector<Ref> refs_; ///< variablesReference - 1 -> what it shows (valid during one stop)
};

} // namespace iso::dap
