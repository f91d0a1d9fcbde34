// The project's error type for failures the caller must handle (files, user input,
// cameras, DDS). Programmer errors are assertions instead.
#pragma once

#include <cassert>
#include <ostream>
#include <string>
#include <utility>
#include <variant>

namespace monocle {

enum class ErrorCode {
  kInvalidArgument,   // the user's input is malformed
  kNotFound,          // a file, camera or board that is not there
  kIo,                // reading or writing failed
  kDegenerate,        // the geometry has no (unique) answer
  kOutOfRange,        // a value outside what the model can handle
  kPermissionDenied,  // DDS Security permissions forbid it
  kCancelled,         // stopped on request (a signal) before it finished
};

struct Error {
  ErrorCode code;
  std::string message;  // complete sentence a user can act on
};

inline std::ostream& operator<<(std::ostream& os, const Error& e) { return os << e.message; }

// A value or an Error. Small stand-in for C++23 std::expected.
template <typename T>
class Result {
 public:
  Result(T value) : data_(std::move(value)) {}      // NOLINT(google-explicit-constructor)
  Result(Error error) : data_(std::move(error)) {}  // NOLINT(google-explicit-constructor)

  bool ok() const { return std::holds_alternative<T>(data_); }
  explicit operator bool() const { return ok(); }

  const T& value() const& {
    assert(ok());
    return std::get<T>(data_);
  }
  T& value() & {
    assert(ok());
    return std::get<T>(data_);
  }
  T&& value() && {
    assert(ok());
    return std::get<T>(std::move(data_));
  }
  // Non-const and rvalue forms too: `std::move(*result)` must move, not copy (a copy of a
  // 100 000-point answer cost milliseconds per request).
  const T& operator*() const& { return value(); }
  T& operator*() & { return value(); }
  T&& operator*() && { return std::move(*this).value(); }
  const T* operator->() const { return &value(); }
  T* operator->() { return &value(); }

  const Error& error() const {
    assert(!ok());
    return std::get<Error>(data_);
  }

 private:
  std::variant<T, Error> data_;
};

// Result<void>
struct Ok {};
using Status = Result<Ok>;

inline Error MakeError(ErrorCode code, std::string message) {
  return Error{code, std::move(message)};
}

}  // namespace monocle
