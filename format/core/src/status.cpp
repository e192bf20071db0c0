// SPDX-License-Identifier: GPL-3.0-or-later
#include "sdvi/status.h"

namespace sdvi {

std::string_view StatusCodeName(StatusCode code) {
  switch (code) {
    case StatusCode::kOk: return "ok";
    case StatusCode::kInvalidArgument: return "invalid_argument";
    case StatusCode::kIoError: return "io_error";
    case StatusCode::kNotFound: return "not_found";
    case StatusCode::kTruncated: return "truncated";
    case StatusCode::kCorrupt: return "corrupt";
    case StatusCode::kWrongIdentifier: return "wrong_identifier";
    case StatusCode::kUnsupportedVersion: return "unsupported_version";
    case StatusCode::kIndexOutOfRange: return "index_out_of_range";
    case StatusCode::kCountMismatch: return "count_mismatch";
    case StatusCode::kNonFinite: return "non_finite";
    case StatusCode::kLimitExceeded: return "limit_exceeded";
    case StatusCode::kInvalidMesh: return "invalid_mesh";
    case StatusCode::kNonManifoldEdge: return "non_manifold_edge";
    case StatusCode::kDegenerateTriangle: return "degenerate_triangle";
    case StatusCode::kDuplicateTriangle: return "duplicate_triangle";
    case StatusCode::kCreaseNotAnEdge: return "crease_not_an_edge";
    case StatusCode::kUnsupportedFormat: return "unsupported_format";
    case StatusCode::kDecodeFailed: return "decode_failed";
    case StatusCode::kEncodeFailed: return "encode_failed";
    case StatusCode::kEmptyInput: return "empty_input";
    case StatusCode::kInternal: return "internal";
    case StatusCode::kEditRefused: return "edit_refused";
    case StatusCode::kValueOutOfRange: return "value_out_of_range";
    case StatusCode::kFoldedTriangle: return "folded_triangle";
  }
  return "unknown";
}

std::string Status::ToString() const {
  if (ok()) return "ok";
  return std::string(StatusCodeName(code_)) + ": " + message_;
}

}  // namespace sdvi
