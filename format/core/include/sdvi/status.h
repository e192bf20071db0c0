// SPDX-License-Identifier: GPL-3.0-or-later
// Status and StatusOr: how every sdvi library function reports failure.
// A Status carries a specific code (act on it) and a message that names the input,
// the place and what was expected (show it). Exceptions from dependencies are caught
// at module boundaries and turned into a Status.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>

namespace sdvi {

// Codes are stable: append only, never renumber (tests and scripts assert them).
enum class StatusCode : int {
  kOk = 0,
  kInvalidArgument = 1,     // a caller passed a bad option or value
  kIoError = 2,             // the OS refused a read, write or rename
  kNotFound = 3,            // an input file does not exist
  kTruncated = 4,           // a file ends before its structure does
  kCorrupt = 5,             // structure check failed (FlatBuffers verifier, bad offsets)
  kWrongIdentifier = 6,     // not an sdvi file (file_identifier mismatch)
  kUnsupportedVersion = 7,  // major version newer than this build reads
  kIndexOutOfRange = 8,     // a vertex index >= vertex count
  kCountMismatch = 9,       // header counts disagree with the lists they describe
  kNonFinite = 10,          // NaN or infinity in coordinates or colours
  kLimitExceeded = 11,      // sizes beyond ReadOptions limits / too large to process
  kInvalidMesh = 12,        // topology the engine cannot subdivide (general)
  kNonManifoldEdge = 13,    // an edge shared by more than two triangles
  kDegenerateTriangle = 14, // a triangle with a repeated vertex
  kDuplicateTriangle = 15,  // the same vertex triple twice
  kCreaseNotAnEdge = 16,    // a crease edge that no triangle has
  kUnsupportedFormat = 17,  // an input format or pixel type we do not read
  kDecodeFailed = 18,       // a dependency failed to decode (image, Draco, SVG)
  kEncodeFailed = 19,       // a dependency failed to encode
  kEmptyInput = 20,         // an empty image, mesh or file
  kInternal = 21,           // a broken invariant inside sdvi (a bug)
  kEditRefused = 22,        // an edit would fold, degenerate or cross the mesh (nothing written)
  kValueOutOfRange = 23,    // a finite value no real image has (spec/FORMAT.md 9)
  kFoldedTriangle = 24,     // two triangles of an edge lie on the same side of it
};

// Stable lower_snake name of a code, e.g. "wrong_identifier" (used in --json output).
std::string_view StatusCodeName(StatusCode code);

class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}
  static Status Ok() { return {}; }

  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }
  // "code_name: message".
  std::string ToString() const;

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

template <typename T>
class [[nodiscard]] StatusOr {
 public:
  StatusOr(Status status) : value_(std::move(status)) {}  // NOLINT: implicit by design
  StatusOr(T value) : value_(std::move(value)) {}         // NOLINT: implicit by design

  bool ok() const { return std::holds_alternative<T>(value_); }
  Status status() const { return ok() ? Status::Ok() : std::get<Status>(value_); }
  const T& value() const& { return std::get<T>(value_); }
  T& value() & { return std::get<T>(value_); }
  T&& value() && { return std::get<T>(std::move(value_)); }
  const T& operator*() const& { return value(); }
  T& operator*() & { return value(); }
  const T* operator->() const { return &value(); }
  T* operator->() { return &value(); }

 private:
  std::variant<Status, T> value_;
};

}  // namespace sdvi

#define SDVI_CONCAT_INNER(a, b) a##b
#define SDVI_CONCAT(a, b) SDVI_CONCAT_INNER(a, b)

// Returns the Status from the enclosing function if `expr` is not ok.
#define SDVI_RETURN_IF_ERROR(expr)              \
  do {                                          \
    ::sdvi::Status sdvi_status_ = (expr);       \
    if (!sdvi_status_.ok()) return sdvi_status_; \
  } while (0)

// `lhs = value of expr`, or returns its Status from the enclosing function.
#define SDVI_ASSIGN_OR_RETURN(lhs, expr) \
  SDVI_ASSIGN_OR_RETURN_IMPL(SDVI_CONCAT(sdvi_statusor_, __LINE__), lhs, expr)
#define SDVI_ASSIGN_OR_RETURN_IMPL(tmp, lhs, expr) \
  auto tmp = (expr);                               \
  if (!tmp.ok()) return tmp.status();              \
  lhs = std::move(tmp).value()
