// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target over raster input through the importer (DecodeRaster: OpenImageIO reads
// the header, the size limit applies, then it decodes; orientation and ICC conversion
// follow). Never crash; a decoded raster is within the pixel limit, has the size its data
// holds and finite samples.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "sdvi/raster_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  sdvi::RasterLimits limits;
  limits.max_pixels = 1 << 22;  // keeps the fuzzer within its RSS limit
  auto raster = sdvi::DecodeRaster(std::vector<uint8_t>(data, data + size), "fuzz-image", limits);
  if (!raster.ok()) {
    if (raster.status().message().empty()) std::abort();
    return 0;
  }
  if (raster->width <= 0 || raster->height <= 0 || uint64_t(raster->width) * raster->height > limits.max_pixels)
    std::abort();
  if (raster->data.size() != size_t(raster->width) * raster->height * raster->channels) std::abort();
  for (float v : raster->data)
    if (!std::isfinite(v)) std::abort();
  return 0;
}
