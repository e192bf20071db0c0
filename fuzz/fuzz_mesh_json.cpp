// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target over ParseMeshJson (the mesh JSON reader).
// Besides "never crash", every document that parses must survive
// FormatMeshJson -> ParseMeshJson unchanged and encode as a valid .sdvi file.
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "sdvi/format.h"
#include "sdvi/mesh_json.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto image = sdvi::ParseMeshJson(text, "fuzz.json");
  if (!image.ok()) {
    if (image.status().message().empty()) std::abort();
    return 0;
  }
  auto again = sdvi::ParseMeshJson(sdvi::FormatMeshJson(*image), "fuzz-formatted.json");
  if (!again.ok() || !(*again == *image)) std::abort();
  auto bytes = sdvi::EncodeSdvi(*image);
  if (!bytes.ok()) std::abort();
  auto file = sdvi::DecodeSdvi(*bytes, "fuzz.sdvi");
  if (!file.ok() || !(file->image == sdvi::CanonicalizeImage(*image))) std::abort();
  return 0;
}
