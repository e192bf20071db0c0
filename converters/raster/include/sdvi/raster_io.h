// Raster image files via OpenCV: PNG, JPEG, TIFF, BMP in; PNG (8/16-bit) out.
// The raster module owns the implementation and may add declarations.
#pragma once

#include <string>

#include "sdvi/raster.h"
#include "sdvi/status.h"

namespace sdvi {

// Loads an image keeping its channels (grey 1, grey+alpha 2, RGB 3, RGBA 4; palette
// images expand to RGB(A)); 16-bit samples are scaled to the 0..255 float scale; alpha
// to 0..1. Errors name the file: kNotFound, kDecodeFailed, kEmptyInput, kLimitExceeded.
StatusOr<Raster> LoadRaster(const std::string& path);

// Writes a PNG (bits 8 or 16), atomically; colours clamped to 0..255 and rounded.
// Grey+alpha rasters are written as RGBA with R = G = B (OpenCV has no grey+alpha PNG writer).
Status SaveRasterPng(const std::string& path, const Raster& raster, int bits = 8);

}  // namespace sdvi
