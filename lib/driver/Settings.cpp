//! @file Settings.cpp
#include "driver/Settings.h"

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>
#include <toml++/toml.h>

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
      if (!c)
        return fail(
            n, fmt::format("'{}': unknown diagnostic '{}' (a code like W402 or a name like feed-unset)", key, name));
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

bool loadSettings(const std::string& path, Settings& out, std::string& error) {
  Reader r{path, {}};
  toml::table tbl;
  try {
    tbl = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    error = fmt::format("{}:{}:{}: error: {}", path, e.source().begin.line, e.source().begin.column, e.description());
    return false;
  }
  out = Settings{};
  out.path = path;
  std::error_code ec;
  out.dir = fs::weakly_canonical(fs::absolute(path, ec), ec).parent_path().string();
  for (const auto& [k, v] : tbl) {
    const std::string key(k.str());
    bool ok = true;
    if (key == "machine") {
      ok = r.string(v, key, out.machine);
      if (ok && !out.machine.empty() && fs::path(out.machine).is_relative())
        out.machine = (fs::path(out.dir) / out.machine).lexically_normal().string();
    } else if (key == "dialect") {
      ok = r.string(v, key, out.dialect);
      if (ok && out.dialect != "sidac" && out.dialect != "z32")
        ok = r.fail(v, "'dialect' must be \"sidac\" or \"z32\"");
    } else if (key == "max-diagnostics") {
      if (!v.is_integer() || *v.value<int64_t>() < 0)
        ok = r.fail(v, "'max-diagnostics' must be a whole number >= 0");
      else
        out.maxDiagnostics = *v.value<int64_t>();
    } else if (key == "disable") {
      ok = r.codes(v, key, out.disable);
    } else if (key == "enable") {
      ok = r.codes(v, key, out.enable);
    } else if (key == "exclude") {
      ok = r.strings(v, key, out.exclude);
    } else if (key == "overrides") {
      const toml::array* a = v.as_array();
      if (!a) ok = r.fail(v, "'overrides' must be an array of tables ([[overrides]])");
      for (size_t i = 0; ok && a && i < a->size(); ++i) {
        const toml::table* t = (*a)[i].as_table();
        if (!t) {
          ok = r.fail((*a)[i], "each [[overrides]] entry must be a table");
          break;
        }
        Settings::Override o;
        for (const auto& [ok2, ov] : *t) {
          const std::string k2(ok2.str());
          const std::string name = fmt::format("overrides.{}", k2);
          if (k2 == "paths")
            ok = r.strings(ov, name, o.paths);
          else if (k2 == "disable")
            ok = r.codes(ov, name, o.disable);
          else if (k2 == "enable")
            ok = r.codes(ov, name, o.enable);
          else
            ok = r.fail(ov, fmt::format("unknown key '{}' (known in [[overrides]]: paths, disable, enable)", name));
          if (!ok) break;
        }
        if (ok && o.paths.empty()) ok = r.fail((*a)[i], "an [[overrides]] entry needs 'paths'");
        out.overrides.push_back(std::move(o));
      }
    } else {
      ok =
          r.fail(v, fmt::format("unknown key '{}' (known: machine, dialect, max-diagnostics, disable, enable, exclude, "
                                "[[overrides]])",
                                key));
    }
    if (!ok) {
      error = r.error;
      return false;
    }
  }
  return true;
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
