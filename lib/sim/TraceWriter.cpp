//! @file TraceWriter.cpp
//! @brief CSV/JSON trace writers and the summary renderers, with the one number format.
#include "sim/TraceWriter.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <ostream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "machine/Machine.h"

namespace iso::sim {

namespace {
constexpr size_t kFlushBytes = 1 << 16;
} // namespace

const char* statusName(Status s) {
  switch (s) {
  case Status::Ok: return "ok";
  case Status::Error: return "error";
  case Status::Emergency: return "emergency";
  }
  return "?";
}

const char* eventKindName(EventKind k) {
  switch (k) {
  case EventKind::Line: return "line";
  case EventKind::MoveStart: return "move_start";
  case EventKind::MoveEnd: return "move_end";
  case EventKind::MStart: return "m_start";
  case EventKind::MEnd: return "m_end";
  case EventKind::Output: return "output";
  case EventKind::Marker: return "marker";
  case EventKind::Input: return "input";
  case EventKind::When: return "when";
  case EventKind::Dwell: return "dwell";
  case EventKind::Stop: return "stop";
  case EventKind::Error: return "error";
  case EventKind::End: return "end";
  case EventKind::Spindle: return "spindle";
  case EventKind::Coolant: return "coolant";
  case EventKind::Tool: return "tool";
  case EventKind::Aux: return "aux";
  case EventKind::Zone: return "zone";
  case EventKind::AxisControl: return "axis_control";
  case EventKind::Pal: return "pal";
  }
  return "?";
}

void appendNumber(std::string& out, double v) {
  if (!std::isfinite(v)) {
    out += std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
    return;
  }
  const double scaled = v * 1e6;
  if (!(std::fabs(scaled) < 9.0e15)) {
    // Beyond 2^53 µ-units: let fmt round, then trim the same way.
    std::string s = fmt::format("{:.6f}", v);
    while (!s.empty() && s.back() == '0')
      s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
    out += s;
    return;
  }
  int64_t m = std::llround(scaled);
  if (m == 0) {
    out += '0';
    return;
  }
  if (m < 0) {
    out += '-';
    m = -m;
  }
  const auto um = static_cast<uint64_t>(m);
  uint64_t ip = um / 1000000u;
  uint64_t fp = um % 1000000u;
  char tmp[24];
  auto r = std::to_chars(tmp, tmp + sizeof tmp, ip);
  out.append(tmp, r.ptr);
  if (fp != 0) {
    char f[6];
    for (int i = 5; i >= 0; --i) {
      f[i] = static_cast<char>('0' + fp % 10);
      fp /= 10;
    }
    size_t len = 6;
    while (len > 0 && f[len - 1] == '0')
      --len;
    out += '.';
    out.append(f, len);
  }
}

std::string formatNumber(double v) {
  std::string s;
  appendNumber(s, v);
  return s;
}

double readNumber(std::string_view text) {
  double v = 0;
  auto r = std::from_chars(text.data(), text.data() + text.size(), v); // its own '-', "inf" and "nan"
  if (r.ec == std::errc::invalid_argument) return std::numeric_limits<double>::quiet_NaN();
  return v;
}

std::string clockTime(double seconds) {
  if (!(seconds >= 0) || !std::isfinite(seconds) || seconds > 1e15) return formatNumber(seconds);
  const auto tenths = static_cast<uint64_t>(std::llround(seconds * 10));
  const uint64_t h = tenths / 36000, m = tenths / 600 % 60, sec = tenths / 10 % 60, t = tenths % 10;
  if (h > 0) return fmt::format("{}:{:02}:{:02}.{}", h, m, sec, t);
  return fmt::format("{}:{:02}.{}", m, sec, t);
}

std::string readableDuration(double seconds) {
  std::string out = formatNumber(seconds);
  out += " s";
  if (seconds >= 0 && std::isfinite(seconds)) out += fmt::format(" ({})", clockTime(seconds));
  return out;
}

void appendJsonString(std::string& out, std::string_view s) {
  out += '"';
  for (char c : s) {
    auto u = static_cast<unsigned char>(c);
    switch (c) {
    case '"': out += "\\\""; break;
    case '\\': out += "\\\\"; break;
    case '\n': out += "\\n"; break;
    case '\r': out += "\\r"; break;
    case '\t': out += "\\t"; break;
    default:
      if (u < 0x20)
        out += fmt::format("\\u{:04x}", u);
      else
        out += c;
    }
  }
  out += '"';
}

std::string summaryText(const Summary& s) {
  std::string out;
  out += fmt::format("status: {}\n", statusName(s.status));
  out += fmt::format("cycle_time_s: {}\n", readableDuration(s.cycleTimeS));
  out += fmt::format("blocks: {} (lines charged with block_time_s; G64 read-ahead not counted)\n", s.blocks);
  out += fmt::format("lines_executed: {}\nfinal_position:", s.linesExecuted);
  for (const auto& [axis, pos] : s.finalPosition) {
    out += ' ';
    out += axis;
    out += '=';
    appendNumber(out, pos);
  }
  out += '\n';
  if (s.z32) {
    out += "spindle_on_s: ";
    appendNumber(out, s.spindleOnS);
    out += fmt::format("\ntool_changes: {}\ntool: {}\norigin: {}\n", s.toolChanges,
                       s.tool ? fmt::format("{}", *s.tool) : std::string("none"), s.origin);
  }
  if (s.search) out += fmt::format("search: {} ({}:{})\n", s.search->text, s.search->file, s.search->line);
  for (const auto& o : s.overrides)
    out += fmt::format("override: {}\n", o);
  if (!s.message.empty()) out += fmt::format("message: {}\n", s.message);
  for (const auto& w : s.warnings)
    out += fmt::format("warning: {}\n", w);
  return out;
}

nlohmann::ordered_json jsonNumber(double v) {
  if (!std::isfinite(v)) return v;
  const std::string s = formatNumber(v);
  const char* const last = s.data() + s.size();
  if (s.find('.') == std::string::npos) {
    // as the reader does: unsigned when not negative, and a double when out of range
    if (s.front() == '-') {
      int64_t i = 0;
      if (auto r = std::from_chars(s.data(), last, i); r.ec == std::errc() && r.ptr == last) return i;
    } else {
      uint64_t u = 0;
      if (auto r = std::from_chars(s.data(), last, u); r.ec == std::errc() && r.ptr == last) return u;
    }
  }
  return readNumber(s);
}

nlohmann::ordered_json summaryValue(const Summary& s) {
  nlohmann::ordered_json j;
  j["format_version"] = kSummaryFormatVersion;
  j["status"] = statusName(s.status);
  j["cycle_time_s"] = jsonNumber(s.cycleTimeS);
  auto& pos = j["final_position"] = nlohmann::ordered_json::object();
  for (const auto& [axis, p] : s.finalPosition)
    pos[std::string(1, axis)] = jsonNumber(p);
  j["blocks"] = s.blocks;
  j["lines_executed"] = s.linesExecuted;
  j["message"] = s.message.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(s.message);
  j["warnings"] = s.warnings;
  if (s.z32) {
    j["spindle_on_s"] = jsonNumber(s.spindleOnS);
    j["tool_changes"] = s.toolChanges;
    j["tool"] = s.tool ? nlohmann::ordered_json(*s.tool) : nlohmann::ordered_json();
    j["origin"] = s.origin;
  }
  if (s.search) j["search"] = {{"text", s.search->text}, {"file", s.search->file}, {"line", s.search->line}};
  if (!s.overrides.empty()) j["overrides"] = s.overrides;
  return j;
}

namespace {
/// appendNumber of a number that jsonNumber read back from formatNumber's text: that text.
/// From about 4e9 a double holds less than µ resolution and rounding again can move the last
/// digit; then the neighbour that reads back as `x` is the text it came from.
void appendReadNumber(std::string& out, double x) {
  std::string s = formatNumber(x);
  if (std::isfinite(x) && readNumber(s) != x)
    for (double step : {-1e-6, 1e-6}) {
      std::string t = formatNumber(x + step);
      if (readNumber(t) == x) {
        s = std::move(t);
        break;
      }
    }
  out += s;
}

/// A value on one line: ", " between items, ": " after keys, strings by appendJsonString and
/// numbers by appendReadNumber (the trace's own escapes and number format).
void appendInline(std::string& out, const nlohmann::ordered_json& v) {
  using Type = nlohmann::ordered_json::value_t;
  bool first = true;
  switch (v.type()) {
  case Type::object:
    out += '{';
    for (const auto& [key, item] : v.items()) {
      out += first ? "" : ", ";
      first = false;
      appendJsonString(out, key);
      out += ": ";
      appendInline(out, item);
    }
    out += '}';
    break;
  case Type::array:
    out += '[';
    for (const auto& item : v) {
      out += first ? "" : ", ";
      first = false;
      appendInline(out, item);
    }
    out += ']';
    break;
  case Type::string: appendJsonString(out, v.get_ref<const std::string&>()); break;
  case Type::number_float: appendReadNumber(out, v.get<double>()); break;
  default: out += v.dump(); // null, booleans, integers
  }
}
} // namespace

std::string summaryJson(const Summary& s, int indent) {
  const std::string pad(static_cast<size_t>(indent), ' ');
  const std::string close(static_cast<size_t>(indent >= 2 ? indent - 2 : 0), ' ');
  const nlohmann::ordered_json j = summaryValue(s);
  std::string out = "{";
  bool first = true;
  for (const auto& [key, value] : j.items()) {
    out += first ? "\n" : ",\n";
    first = false;
    out += pad;
    appendJsonString(out, key);
    out += ": ";
    appendInline(out, value);
  }
  out += "\n" + close + "}";
  return out;
}

void appendEventJson(std::string& out, const Event& e) {
  out += "{\"t\":";
  appendNumber(out, e.t);
  out += ",\"kind\":\"";
  out += eventKindName(e.kind);
  out += '"';
  switch (e.kind) {
  case EventKind::Line:
    out += ",\"file\":";
    appendJsonString(out, e.file);
    out += fmt::format(",\"line\":{}", e.line);
    if (e.hasN) {
      out += ",\"n\":";
      appendNumber(out, e.n);
    }
    break;
  case EventKind::MoveStart:
  case EventKind::MoveEnd:
    out += ",\"axis\":";
    appendJsonString(out, std::string_view(&e.axis, 1));
    out += ",\"target\":";
    appendNumber(out, e.target);
    break;
  case EventKind::MStart: out += fmt::format(",\"m\":{},\"blocking\":{}", e.m, e.blocking ? "true" : "false"); break;
  case EventKind::MEnd: out += fmt::format(",\"m\":{}", e.m); break;
  case EventKind::Output:
  case EventKind::Marker:
  case EventKind::Input: out += fmt::format(",\"index\":{},\"value\":{}", e.index, e.value); break;
  case EventKind::When:
    out += ",\"action\":";
    appendJsonString(out, e.action);
    out += ",\"file\":";
    appendJsonString(out, e.file);
    out += fmt::format(",\"line\":{}", e.line);
    break;
  case EventKind::Dwell:
  case EventKind::Stop:
    out += ",\"duration\":";
    appendNumber(out, e.duration);
    break;
  case EventKind::Error:
    out += ",\"status\":";
    appendJsonString(out, statusName(e.status));
    out += ",\"message\":";
    appendJsonString(out, e.message);
    break;
  case EventKind::End: break;
  case EventKind::Spindle:
    out += fmt::format(",\"state\":\"{}\",\"rpm\":", e.state);
    appendNumber(out, e.rpm);
    break;
  case EventKind::Coolant: out += fmt::format(",\"c1\":{},\"c2\":{}", e.c1, e.c2); break;
  case EventKind::Tool: out += fmt::format(",\"tool\":{},\"word\":\"{}\"", e.tool, e.state); break;
  case EventKind::AxisControl:
    out += ",\"axis\":";
    appendJsonString(out, std::string_view(&e.axis, 1));
    out += fmt::format(",\"on\":{}", e.on);
    break;
  case EventKind::Pal:
    out += fmt::format(",\"index\":{},\"value\":", e.index);
    appendNumber(out, e.number);
    break;
  case EventKind::Aux:
    out += fmt::format(",\"word\":\"{}\",\"programmed\":", e.state);
    appendNumber(out, e.programmed);
    out += fmt::format(",\"sent\":{}", e.sent);
    break;
  case EventKind::Zone:
    out += ",\"name\":";
    appendJsonString(out, e.zone ? std::string_view(e.zone->name) : std::string_view());
    out += fmt::format(",\"zone_kind\":\"{}\",\"file\":", e.zone && e.zone->forbidden ? "forbidden" : "warn");
    appendJsonString(out, e.file);
    out += fmt::format(",\"line\":{},\"position\":{{", e.line);
    for (size_t i = 0; e.zone && e.zonePosition && i < e.zone->axes.size(); ++i) {
      out += i ? "," : "";
      appendJsonString(out, std::string_view(&e.zone->axes[i].letter, 1));
      out += ':';
      appendNumber(out, e.zonePosition[i]);
    }
    out += '}';
    break;
  }
  out += '}';
}

// ---- CSV ----------------------------------------------------------------------------------

CsvTraceWriter::CsvTraceWriter(std::ostream& os) : os_(os) { buf_.reserve(kFlushBytes + 4096); }

CsvTraceWriter::~CsvTraceWriter() { flush(); }

void CsvTraceWriter::flush() {
  if (!buf_.empty()) os_.write(buf_.data(), static_cast<std::streamsize>(buf_.size()));
  buf_.clear();
}

void CsvTraceWriter::begin(const machine::Machine& m) {
  axes_ = m.axes.size();
  buf_ += 't';
  for (const auto& a : m.axes) {
    buf_ += ',';
    buf_ += a.letter;
  }
  buf_ += '\n';
}

void CsvTraceWriter::sample(double t, const double* positions) {
  appendNumber(buf_, t);
  for (size_t i = 0; i < axes_; ++i) {
    buf_ += ',';
    appendNumber(buf_, positions[i]);
  }
  buf_ += '\n';
  if (buf_.size() >= kFlushBytes) flush();
}

void CsvTraceWriter::end(const Summary&) {
  flush();
  os_.flush();
}

// ---- JSON ---------------------------------------------------------------------------------

JsonTraceWriter::JsonTraceWriter(std::ostream& os) : os_(os) {
  buf_.reserve(kFlushBytes + 4096);
  spool_ = std::tmpfile();
}

JsonTraceWriter::~JsonTraceWriter() {
  if (spool_) std::fclose(spool_);
}

void JsonTraceWriter::flushSamples() {
  if (!buf_.empty()) os_.write(buf_.data(), static_cast<std::streamsize>(buf_.size()));
  buf_.clear();
}

void JsonTraceWriter::flushEvents() {
  if (ev_.empty()) return;
  if (spool_ && spoolMemory_.empty() && std::fwrite(ev_.data(), 1, ev_.size(), spool_) == ev_.size()) {
    ev_.clear();
    return;
  }
  // No temporary file (or it is full): keep the rest in memory, after what the file holds.
  spoolMemory_ += ev_;
  ev_.clear();
}

void JsonTraceWriter::begin(const machine::Machine& m) {
  axes_ = m.axes.size();
  buf_ += "{\n\"format_version\": 1,\n\"machine\": ";
  appendJsonString(buf_, m.name);
  buf_ += ",\n\"columns\": [\"t\"";
  for (const auto& a : m.axes) {
    buf_ += ", ";
    appendJsonString(buf_, std::string_view(&a.letter, 1));
  }
  buf_ += "],\n\"samples\": [";
}

void JsonTraceWriter::sample(double t, const double* positions) {
  buf_ += firstSample_ ? "\n[" : ",\n[";
  firstSample_ = false;
  appendNumber(buf_, t);
  for (size_t i = 0; i < axes_; ++i) {
    buf_ += ',';
    appendNumber(buf_, positions[i]);
  }
  buf_ += ']';
  if (buf_.size() >= kFlushBytes) flushSamples();
}

void JsonTraceWriter::event(const Event& e) {
  ev_ += firstEvent_ ? "\n" : ",\n";
  firstEvent_ = false;
  appendEventJson(ev_, e);
  if (ev_.size() >= kFlushBytes) flushEvents();
}

void JsonTraceWriter::end(const Summary& s) {
  buf_ += firstSample_ ? "],\n\"events\": [" : "\n],\n\"events\": [";
  flushSamples();
  flushEvents();
  if (spool_) {
    std::rewind(spool_);
    char chunk[1 << 15];
    size_t n = 0;
    while ((n = std::fread(chunk, 1, sizeof chunk, spool_)) > 0)
      os_.write(chunk, static_cast<std::streamsize>(n));
  }
  if (!spoolMemory_.empty()) os_.write(spoolMemory_.data(), static_cast<std::streamsize>(spoolMemory_.size()));
  buf_ += firstEvent_ ? "],\n\"summary\": " : "\n],\n\"summary\": ";
  buf_ += summaryJson(s, 2);
  buf_ += "\n}\n";
  flushSamples();
  os_.flush();
}

// ============================================================================================
// TeeSink

void TeeSink::begin(const machine::Machine& m) {
  for (TraceSink* s : sinks_)
    s->begin(m);
}

void TeeSink::sample(double t, const double* positions) {
  for (TraceSink* s : sinks_)
    if (s->wantsSamples()) s->sample(t, positions);
}

void TeeSink::sampleWithVelocity(double t, const double* positions, const double* velocities) {
  for (TraceSink* s : sinks_) {
    if (!s->wantsSamples()) continue;
    if (s->wantsVelocities())
      s->sampleWithVelocity(t, positions, velocities);
    else
      s->sample(t, positions);
  }
}

void TeeSink::event(const Event& e) {
  for (TraceSink* s : sinks_)
    if (s->wantsEvents()) s->event(e);
}

void TeeSink::end(const Summary& summary) {
  for (TraceSink* s : sinks_)
    s->end(summary);
}

bool TeeSink::wantsSamples() const {
  return std::any_of(sinks_.begin(), sinks_.end(), [](const TraceSink* s) { return s->wantsSamples(); });
}

bool TeeSink::wantsEvents() const {
  return std::any_of(sinks_.begin(), sinks_.end(), [](const TraceSink* s) { return s->wantsEvents(); });
}

bool TeeSink::wantsVelocities() const {
  return std::any_of(sinks_.begin(), sinks_.end(),
                     [](const TraceSink* s) { return s->wantsSamples() && s->wantsVelocities(); });
}

} // namespace iso::sim
