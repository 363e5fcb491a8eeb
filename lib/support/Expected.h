//! @file Expected.h
//! @brief One result type for operations that fail with a reason: a value, or an Error saying
//!        where (a path, a JSON path, a byte offset as text) and what. The library never
//!        prints: a caller renders the error in its own format.
#pragma once

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace iso::support {

/// Why something failed, and where.
struct Error {
  std::string where;   ///< e.g. a file path, "/axes/2/max_accel"; "" for the whole input
  std::string message; ///< e.g. "no such file or directory", "must be a number > 0"
};

template <class T> class Expected {
public:
  Expected(T value) : v_(std::move(value)) {}     // NOLINT(google-explicit-constructor)
  Expected(Error error) : v_(std::move(error)) {} // NOLINT(google-explicit-constructor)

  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }

  T& value() {
    assert(ok());
    return std::get<0>(v_);
  }
  const T& value() const {
    assert(ok());
    return std::get<0>(v_);
  }
  T& operator*() { return value(); }
  const T& operator*() const { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }

  const Error& error() const {
    assert(!ok());
    return std::get<1>(v_);
  }

private:
  std::variant<T, Error> v_;
};

/// The result of an operation that gives nothing back but may fail: success, or an Error.
class [[nodiscard]] Status {
public:
  Status() = default;                                              // success
  Status(Error error) : error_(std::move(error)), failed_(true) {} // NOLINT(google-explicit-constructor)
  static Status failure(std::string message) { return Status(Error{"", std::move(message)}); }

  bool ok() const { return !failed_; }
  explicit operator bool() const { return ok(); }
  const Error& error() const {
    assert(!ok());
    return error_;
  }
  /// The reason alone ("" on success), for messages that name the file themselves.
  const std::string& why() const { return error_.message; }

private:
  Error error_;
  bool failed_ = false;
};

} // namespace iso::support
