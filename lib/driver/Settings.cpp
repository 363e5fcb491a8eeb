//! @file Settings.cpp
#include "driver/Settings.h"

#include <algorithm>
#include <filesystem>
#include <iterator>
#include <utility>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "support/File.h"
#include "support/Text.h"
#include "support/TomlDepth.h"

namespace iso::driver {

namespace fs = std::filesystem;

bool globMatch(std::string_view pat, std::string_view s) {
  // iterative matcher with one backtrack point per kind of star
  size_t p = 0, i = 0;
  size_t starP = std::string_view::npos, starI = 0;   // last `*` (stays in a component)
  size_t dstarP = std::string_view::npos, dstarI = 0; // last `**` (crosses components)
  while (i < s.size()) {
    if (p + 1 < pat.size() && pat[p] == '*' && pat[p + 1] == '*') {
      p += 2;
      if (p < pat.size() && pat[p] == '/') ++p; // `**/` also matches no folder at all
      dstarP = p;
      dstarI = i;
      starP = std::string_view::npos;
      continue;
    }
    if (p < pat.size() && pat[p] == '*') {
      starP = ++p;
      starI = i;
      continue;
    }
    if (p < pat.size() && (pat[p] == s[i] || (pat[p] == '?' && s[i] != '/'))) {
      ++p;
      ++i;
      continue;
    }
    if (starP != std::string_view::npos && s[starI] != '/') {
      p = starP;
      i = ++starI;
      continue;
    }
    if (dstarP != std::string_view::npos) {
      p = dstarP;
      i = ++dstarI;
      starP = std::string_view::npos;
      continue;
    }
    return false;
  }
  while (p < pat.size() && pat[p] == '*')
    ++p;
  return p == pat.size();
}

namespace {

/// `path` relative to the settings folder, with '/' separators ("" when outside it).
std::string relativeTo(const std::string& dir, const std::string& path) {
  std::error_code ec;
  fs::path abs = fs::weakly_canonical(fs::absolute(path, ec), ec);
  fs::path rel = abs.lexically_relative(dir);
  std::string r = rel.generic_string();
  if (r.empty() || r.rfind("..", 0) == 0) return "";
  return r;
}

bool anyMatch(const std::vector<std::string>& patterns, const std::string& rel) {
  if (rel.empty()) return false;
  for (const auto& p : patterns)
    if (globMatch(p, rel)) return true;
  return false;
}

struct Reader {
  std::string file;
  std::string error;
  bool fail(const toml::node& n, const std::string& what) {
    if (error.empty()) error = fmt::format("{}:{}: error: {}", file, n.source().begin.line, what);
    return false;
  }
  bool string(const toml::node& n, const std::string& key, std::string& out) {
    if (!n.is_string()) return fail(n, fmt::format("'{}' must be a string", key));
    out = *n.value<std::string>();
    return true;
  }
  bool strings(const toml::node& n, const std::string& key, std::vector<std::string>& out) {
    const toml::array* a = n.as_array();
    if (!a) return fail(n, fmt::format("'{}' must be an array of strings", key));
    for (const auto& e : *a) {
      if (!e.is_string()) return fail(e, fmt::format("'{}' must be an array of strings", key));
      out.push_back(*e.value<std::string>());
    }
    return true;
  }
  bool codes(const toml::node& n, const std::string& key, std::vector<diag::Code>& out) {
    std::vector<std::string> names;
    if (!strings(n, key, names)) return false;
    for (const auto& name : names) {
      auto c = diag::findCode(name);
      if (!c) {
        const std::string near = suggestCode(name);
        return fail(n, fmt::format("'{}': unknown diagnostic '{}'{} (a code like W402 or a name like feed-unset)", key,
                                   name, near.empty() ? "" : fmt::format("; did you mean '{}'?", near)));
      }
      out.push_back(*c);
    }
    return true;
  }
};

} // namespace

bool Settings::disabledFor(const std::string& file, diag::Code code) const {
  auto has = [&](const std::vector<diag::Code>& v) { return std::find(v.begin(), v.end(), code) != v.end(); };
  bool off = has(disable) && !has(enable);
  if (overrides.empty()) return off;
  const std::string rel = relativeTo(dir, file);
  for (const auto& o : overrides)
    if (anyMatch(o.paths, rel)) {
      if (has(o.disable)) off = true;
      if (has(o.enable)) off = false;
    }
  return off;
}

bool Settings::excludes(const std::string& file) const {
  return !exclude.empty() && anyMatch(exclude, relativeTo(dir, file));
}

namespace {

constexpr const char* kKnownKeys[] = {"machine", "dialect", "max-diagnostics", "disable",
                                      "enable",  "exclude", "overrides",       "format"};
constexpr const char* kKnownFormatKeys[] = {"case",    "spaces",      "operator-spaces", "indent",
                                            "numbers", "blank-lines", "renumber",        "renumber-all"};
constexpr const char* kKnownOverrideKeys[] = {"paths", "disable", "enable"};

/// "; did you mean 'KEY'?" when `key` is near one of `known`.
template <size_t N> std::string keyHint(const std::string& key, const char* const (&known)[N]) {
  const std::vector<std::string_view> candidates(std::begin(known), std::end(known));
  const std::string_view near = support::closestMatch(key, candidates);
  return near.empty() ? "" : fmt::format("; did you mean '{}'?", near);
}

bool readOverrides(Reader& r, const toml::node& v, Settings& out) {
  const toml::array* a = v.as_array();
  if (!a) return r.fail(v, "'overrides' must be an array of tables ([[overrides]])");
  for (size_t i = 0; i < a->size(); ++i) {
    const toml::table* t = (*a)[i].as_table();
    if (!t) return r.fail((*a)[i], "each [[overrides]] entry must be a table");
    Settings::Override o;
    for (const auto& [k, ov] : *t) {
      const std::string k2(k.str());
      const std::string name = fmt::format("overrides.{}", k2);
      bool ok = true;
      if (k2 == "paths")
        ok = r.strings(ov, name, o.paths);
      else if (k2 == "disable")
        ok = r.codes(ov, name, o.disable);
      else if (k2 == "enable")
        ok = r.codes(ov, name, o.enable);
      else
        ok = r.fail(ov, fmt::format("unknown key '{}'{} (known in [[overrides]]: paths, disable, enable)", name,
                                    keyHint(k2, kKnownOverrideKeys)));
      if (!ok) return false;
    }
    if (o.paths.empty()) return r.fail((*a)[i], "an [[overrides]] entry needs 'paths'");
    out.overrides.push_back(std::move(o));
  }
  return true;
}

bool readChoice(Reader& r, const toml::node& v, const std::string& key, std::initializer_list<const char*> choices,
                std::optional<std::string>& out) {
  std::string value;
  if (!r.string(v, key, value)) return false;
  std::string list;
  for (const char* c : choices) {
    if (value == c) {
      out = value;
      return true;
    }
    list += fmt::format("{}\"{}\"", list.empty() ? "" : " or ", c);
  }
  return r.fail(v, fmt::format("'{}' must be {}", key, list));
}

bool readBool(Reader& r, const toml::node& v, const std::string& key, std::optional<bool>& out) {
  if (!v.is_boolean()) return r.fail(v, fmt::format("'{}' must be true or false", key));
  out = *v.value<bool>();
  return true;
}

bool readCount(Reader& r, const toml::node& v, const std::string& key, long long most, std::optional<long long>& out) {
  if (!v.is_integer() || *v.value<int64_t>() < 0 || *v.value<int64_t>() > most)
    return r.fail(v, fmt::format("'{}' must be a whole number from 0 to {}", key, most));
  out = *v.value<int64_t>();
  return true;
}

bool readFormat(Reader& r, const toml::node& v, Settings::Format& out) {
  const toml::table* t = v.as_table();
  if (!t) return r.fail(v, "'format' must be a table ([format])");
  for (const auto& [k, fv] : *t) {
    const std::string key(k.str());
    const std::string name = "format." + key;
    bool ok = false;
    if (key == "case")
      ok = readChoice(r, fv, name, {"upper", "lower", "keep"}, out.wordCase);
    else if (key == "spaces")
      ok = readBool(r, fv, name, out.spaceBetweenWords);
    else if (key == "operator-spaces")
      ok = readBool(r, fv, name, out.spaceAroundOperators);
    else if (key == "indent")
      ok = readCount(r, fv, name, 8, out.indent);
    else if (key == "numbers")
      ok = readChoice(r, fv, name, {"as-written", "normalised"}, out.numbers);
    else if (key == "blank-lines")
      ok = readCount(r, fv, name, 9, out.blankLines);
    else if (key == "renumber")
      ok = r.string(fv, name, out.renumber.emplace());
    else if (key == "renumber-all")
      ok = readBool(r, fv, name, out.renumberAll);
    else
      ok = r.fail(fv, fmt::format("unknown key '{}'{} (known in [format]: case, spaces, operator-spaces, indent, "
                                  "numbers, blank-lines, renumber, renumber-all)",
                                  name, keyHint(key, kKnownFormatKeys)));
    if (!ok) return false;
  }
  return true;
}

bool readKey(Reader& r, const std::string& key, const toml::node& v, Settings& out) {
  if (key == "machine") {
    if (!r.string(v, key, out.machine)) return false;
    if (!out.machine.empty() && fs::path(out.machine).is_relative())
      out.machine = (fs::path(out.dir) / out.machine).lexically_normal().string();
    return true;
  }
  if (key == "dialect") {
    if (!r.string(v, key, out.dialect)) return false;
    if (out.dialect != "sidac" && out.dialect != "z32") return r.fail(v, "'dialect' must be \"sidac\" or \"z32\"");
    return true;
  }
  if (key == "max-diagnostics") {
    if (!v.is_integer() || *v.value<int64_t>() < 0) return r.fail(v, "'max-diagnostics' must be a whole number >= 0");
    out.maxDiagnostics = *v.value<int64_t>();
    return true;
  }
  if (key == "disable") return r.codes(v, key, out.disable);
  if (key == "enable") return r.codes(v, key, out.enable);
  if (key == "exclude") return r.strings(v, key, out.exclude);
  if (key == "overrides") return readOverrides(r, v, out);
  if (key == "format") return readFormat(r, v, out.format);
  return r.fail(v, fmt::format("unknown key '{}'{} (known: machine, dialect, max-diagnostics, disable, enable, "
                               "exclude, [[overrides]], [format])",
                               key, keyHint(key, kKnownKeys)));
}

/// Where `text` is not UTF-8 text: "" when it is, else what is wrong and its offset.
std::string notText(std::string_view text) {
  for (size_t i = 0; i < text.size();) {
    if (text[i] == '\0') return fmt::format("a NUL byte at offset {}", i);
    const size_t n = support::utf8SequenceLength(text, i);
    if (n == 0) return fmt::format("byte 0x{:02x} at offset {} is not UTF-8", static_cast<unsigned char>(text[i]), i);
    i += n;
  }
  return "";
}

/// 1-based line and column (in bytes) of `offset`.
std::pair<size_t, size_t> lineColumn(std::string_view text, size_t offset) {
  const std::string_view before = text.substr(0, offset);
  const size_t nl = before.rfind('\n');
  return {support::countByte(before, '\n') + 1, nl == std::string_view::npos ? offset + 1 : offset - nl};
}

} // namespace

std::string suggestCode(std::string_view name) {
  std::vector<std::string_view> candidates;
  for (size_t i = 0; i < diag::codeCount(); ++i) {
    candidates.emplace_back(diag::info(static_cast<diag::Code>(i)).code);
    candidates.emplace_back(diag::info(static_cast<diag::Code>(i)).name);
  }
  return std::string(support::closestMatch(name, candidates));
}

bool parseSettings(std::string_view text, const std::string& path, Settings& out, std::string& error) {
  if (const std::string why = notText(text); !why.empty()) {
    error = fmt::format("{}: error: not a text file: {}", path, why);
    return false;
  }
  if (const size_t at = support::tomlNestingBeyond(text); at != std::string_view::npos) {
    const auto [line, col] = lineColumn(text, at);
    error = fmt::format("{}:{}:{}: error: tables, arrays or dotted keys nested deeper than {} levels", path, line, col,
                        support::kMaxNesting);
    return false;
  }
  toml::table tbl;
  try {
    tbl = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    error = fmt::format("{}:{}:{}: error: {}", path, e.source().begin.line, e.source().begin.column, e.description());
    return false;
  }
  out = Settings{};
  out.path = path;
  std::error_code ec;
  out.dir = fs::weakly_canonical(fs::absolute(path, ec), ec).parent_path().string();
  Reader r{path, {}};
  for (const auto& [k, v] : tbl)
    if (!readKey(r, std::string(k.str()), v, out)) {
      error = r.error;
      return false;
    }
  return true;
}

bool loadSettings(const std::string& path, Settings& out, std::string& error) {
  bool whole = false;
  const auto text = support::readFilePrefix(path, kMaxSettingsBytes + 1, whole);
  if (!text) {
    error = fmt::format("{}: error: cannot open the settings file: {}", path, text.error().message);
    return false;
  }
  if (text->size() > kMaxSettingsBytes) {
    error = fmt::format("{}: error: the settings file is larger than {} MiB", path, kMaxSettingsBytes >> 20);
    return false;
  }
  return parseSettings(*text, path, out, error);
}

std::string findSettings(const std::string& input) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(input, ec), ec);
  if (!fs::is_directory(p, ec)) p = p.parent_path();
  for (; !p.empty(); p = p.parent_path()) {
    fs::path f = p / kSettingsFileName;
    if (fs::is_regular_file(f, ec)) return f.string();
    if (p == p.root_path()) break;
  }
  return "";
}

} // namespace iso::driver
