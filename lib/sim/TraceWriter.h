//! @file TraceWriter.h
//! @brief The trace formats of SPEC §8 (CSV, JSON) and the summary (text, JSON). Writers
//!        stream: memory does not grow with the number of samples or events.
#pragma once

#include <cstdio>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "sim/Trace.h"

namespace iso::sim {

/// The one number format of every isosim output: fixed point rounded to 6 decimals (µs, µm),
/// trailing zeros and a trailing '.' removed, "-0" printed as "0". Non-finite values print
/// as "nan" / "inf" / "-inf" (never produced by a correct run).
void appendNumber(std::string& out, double v);
std::string formatNumber(double v);
/// The double a decimal text denotes ("nan" and "inf" too), read without the C locale
/// (std::from_chars): formatNumber's text read back. NaN when it is not a number.
double readNumber(std::string_view text);

/// A duration as clock time, rounded to the tenth of a second: "0:39.3" under an hour,
/// "1:02:03.4" from an hour. Negative or non-finite durations print as formatNumber does.
std::string clockTime(double seconds);
/// A duration in seconds and as clock time: "39.276 s (0:39.3)" (seconds by formatNumber).
std::string readableDuration(double seconds);

/// A JSON string literal (quotes included) with the escapes of RFC 8259.
void appendJsonString(std::string& out, std::string_view s);

/// The summary as text, one "key: value" line each (status, cycle_time_s as readableDuration,
/// blocks with what it counts, lines_executed, final_position, then message and warnings when
/// there are any).
std::string summaryText(const Summary& s);
/// The version of the summary and profile JSON (schemas/isosim-summary.schema.json,
/// schemas/isosim-profile.schema.json): raised when a key changes meaning or goes away.
inline constexpr int kSummaryFormatVersion = 1;
/// A number of the summary as a JSON value: formatNumber's text as a JSON reader reads it (a
/// whole number is an integer, printed "2" and not "2.0"; else the double nearest the text),
/// so that printing the value gives that text. Non-finite values stay as they are.
nlohmann::ordered_json jsonNumber(double v);
/// The summary as a JSON value (fixed key order; every number by jsonNumber).
nlohmann::ordered_json summaryValue(const Summary& s);
/// summaryValue as text: `indent` spaces before each key line, the value of each key (the
/// final_position object, the warnings array) on its line; numbers as formatNumber prints them.
std::string summaryJson(const Summary& s, int indent = 2);

/// CSV trace: header `t,<axes>`, one row per sample. Events and the summary are not part of it.
class CsvTraceWriter : public TraceSink {
public:
  explicit CsvTraceWriter(std::ostream& os);
  ~CsvTraceWriter() override;
  void begin(const machine::Machine& m) override;
  void sample(double t, const double* positions) override;
  void event(const Event&) override {}
  void end(const Summary& s) override;
  bool wantsEvents() const override { return false; }

private:
  void flush();
  std::ostream& os_;
  std::string buf_;
  size_t axes_ = 0;
};

/// JSON trace {"format_version": 1, "machine", "columns", "samples", "events", "summary"}.
/// Samples go straight to the stream; events are spooled to a temporary file (or, if none can
/// be created, kept in memory) and copied after the samples at end().
class JsonTraceWriter : public TraceSink {
public:
  explicit JsonTraceWriter(std::ostream& os);
  ~JsonTraceWriter() override;
  void begin(const machine::Machine& m) override;
  void sample(double t, const double* positions) override;
  void event(const Event& e) override;
  void end(const Summary& s) override;

private:
  void flushSamples();
  void flushEvents();
  std::ostream& os_;
  std::string buf_;
  std::string ev_;
  std::FILE* spool_ = nullptr;
  std::string spoolMemory_; ///< fallback when tmpfile() fails
  size_t axes_ = 0;
  bool firstSample_ = true;
  bool firstEvent_ = true;
};

/// Hands one run to several sinks (a trace writer and a plot, say), each in the order given.
/// The simulator produces samples, velocities and events when any of them wants them; each
/// sink still gets only what it wants. The sinks are not owned and must outlive the run.
class TeeSink : public TraceSink {
public:
  explicit TeeSink(std::vector<TraceSink*> sinks) : sinks_(std::move(sinks)) {}
  void begin(const machine::Machine& m) override;
  void sample(double t, const double* positions) override;
  void sampleWithVelocity(double t, const double* positions, const double* velocities) override;
  void event(const Event& e) override;
  void end(const Summary& s) override;
  bool wantsSamples() const override;
  bool wantsEvents() const override;
  bool wantsVelocities() const override;

private:
  std::vector<TraceSink*> sinks_;
};

/// Appends one event as a JSON object (no trailing separator), keys in a fixed order:
/// t, kind, then the fields of the kind.
void appendEventJson(std::string& out, const Event& e);

} // namespace iso::sim
