// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target over DecodeSdvi (the .sdvi reader).
// Besides "never crash", it checks the reader/writer contract on every input that
// decodes: encoding the decoded image succeeds and decodes to its canonical form.
#include <cstdint>
#include <cstdlib>
#include <span>

#include "sdvi/format.h"

namespace {

[[noreturn]] void Fail() { std::abort(); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  sdvi::ReadOptions options;  // keep allocations small enough for the fuzzer's RSS limit
  options.max_file_bytes = 1 << 24;
  options.max_vertices = 1 << 20;
  options.max_triangles = 1 << 21;
  sdvi::ReadOptions verified = options;  // what the writer made has a correct checksum
  options.verify_checksums = false;       // mutated inputs reach the checks behind it
  auto file = sdvi::DecodeSdvi(std::span<const uint8_t>(data, size), "fuzz-input", options);
  if (!file.ok()) {
    if (file.status().code() == sdvi::StatusCode::kOk || file.status().message().empty()) Fail();
    return 0;
  }
  if (file->payload == sdvi::PayloadKind::kRaw) {
    auto bytes = sdvi::EncodeSdvi(file->image);
    if (!bytes.ok()) Fail();
    auto again = sdvi::DecodeSdvi(*bytes, "fuzz-reencoded", verified);
    if (!again.ok() || !(again->image == sdvi::CanonicalizeImage(file->image))) Fail();
    auto bytes2 = sdvi::EncodeSdvi(again->image);
    if (!bytes2.ok() || *bytes2 != *bytes) Fail();
  } else {
    auto bytes = sdvi::EncodeSdviCompressed(file->image, file->compressed_payload,
                                            file->payload_summary);
    if (!bytes.ok()) Fail();
    auto again = sdvi::DecodeSdvi(*bytes, "fuzz-reencoded", verified);
    if (!again.ok() || !(again->image == file->image) ||
        again->compressed_payload != file->compressed_payload ||
        !(again->payload_summary == file->payload_summary))
      Fail();
  }
  return 0;
}
