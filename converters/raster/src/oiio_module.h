// SPDX-License-Identifier: GPL-3.0-or-later
// The OpenImageIO side of sdvi_raster_io, built as its own loadable module
// (libsdvi_raster_oiio.so) and opened on the first decode of a raster that is not a PNG
// (png_reader.h), so that commands which read and write only PNGs do not load OpenImageIO
// and the ~260 shared libraries it needs (spec/RASTER_INPUT.md, "Loading"). Internal: the module and the loader are built
// from the same tree, and kOiioModuleAbi changes whenever this table does.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sdvi/raster.h"
#include "sdvi/status.h"

namespace sdvi::raster_internal {

inline constexpr uint32_t kOiioModuleAbi = 2;

// A decoded image before ICC conversion and orientation (the loader applies both), from the
// module or from the libpng reader (png_reader.h).
struct DecodedImage {
  Raster raster;
  std::string format;                // the decoder's name: "png", "jpeg", "openexr", ...
  int file_channels = 0;
  int bits = 0;
  bool linear = false;               // float samples, already encoded to sRGB 0..255
  std::vector<uint8_t> icc_profile;  // the embedded profile's bytes (empty: none)
  int orientation = 1;               // EXIF/TIFF orientation tag, 1..8
};

struct OiioModule {
  uint32_t abi;
  uint32_t sizeof_decoded;  // sizeof(DecodedImage) where the module was built
  // The first subimage of an encoded file in memory; max_pixels bounds width x height
  // before any pixel is decoded.
  StatusOr<DecodedImage> (*decode)(const std::vector<uint8_t>& bytes, const std::string& name, uint64_t max_pixels);
  // raster turned upright for an EXIF/TIFF orientation of 2..8.
  StatusOr<Raster> (*reorient)(const Raster& raster, int orientation, const std::string& name);
};

}  // namespace sdvi::raster_internal

// The module's one exported symbol.
extern "C" __attribute__((visibility("default"))) const sdvi::raster_internal::OiioModule* sdvi_raster_oiio_module();
