//! @file Uri.h
//! @brief `file:` URIs of LSP to paths and back (RFC 3986 percent-encoding).
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace iso::lsp {

/// The absolute path of a `file:` URI (`file:///a%20b/x.mpf` -> `/a b/x.mpf`); nullopt for
/// other schemes, a remote authority or a malformed escape.
std::optional<std::string> uriToPath(std::string_view uri);

/// The `file:` URI of an absolute path; bytes other than unreserved ones and `/` are escaped.
std::string pathToUri(std::string_view path);

} // namespace iso::lsp
