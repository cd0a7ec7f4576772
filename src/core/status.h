// Status and Result<T>: how semvox reports errors at I/O and user-input boundaries.
//
// A Status carries a code and one human-readable line. Messages at input boundaries name the
// file, what was expected and a hint, e.g.
//   "scan.ply: truncated binary PLY: expected 1200 vertices, file ends after 731 (hint: re-export the mesh)".
// The CLI maps StatusCode::kInvalidInput to exit code 2 and kInternal to exit code 1.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <variant>

namespace semvox {

enum class StatusCode {
  kOk = 0,
  kInternal = 1,      // A bug or an environment failure (disk full, out of memory).
  kInvalidInput = 2,  // Bad file, bad option, bad usage: the user can fix it.
};

class Status {
 public:
  Status() = default;
  static Status Ok() { return Status(); }
  static Status InvalidInput(std::string message) {
    return Status(StatusCode::kInvalidInput, std::move(message));
  }
  static Status Internal(std::string message) {
    return Status(StatusCode::kInternal, std::move(message));
  }

  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }
  // Exit code for the CLI: 0 ok, 1 internal, 2 invalid input / usage.
  int exit_code() const { return static_cast<int>(code_); }

 private:
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

// Either a value or a non-ok Status.
template <typename T>
class Result {
 public:
  Result(T value) : value_(std::move(value)) {}        // NOLINT: implicit by design.
  Result(Status status) : status_(std::move(status)) {}  // NOLINT: implicit by design.

  bool ok() const { return value_.has_value(); }
  const Status& status() const { return status_; }
  T& value() & { return *value_; }
  const T& value() const& { return *value_; }
  T&& value() && { return std::move(*value_); }
  T* operator->() { return &*value_; }
  const T* operator->() const { return &*value_; }
  T& operator*() { return *value_; }

 private:
  std::optional<T> value_;
  Status status_;
};

// Formats "PATH: WHAT (hint: HINT)".
std::string FileError(const std::string& path, const std::string& what, const std::string& hint = "");

}  // namespace semvox

#define SEMVOX_RETURN_IF_ERROR(expr)          \
  do {                                        \
    ::semvox::Status _st = (expr);            \
    if (!_st.ok()) return _st;                \
  } while (0)
