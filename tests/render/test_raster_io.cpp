// SPDX-License-Identifier: GPL-3.0-or-later
// PNG reading and writing through sdvi_raster_io.
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <string>

#include "sdvi/file_util.h"
#include "render_meshes.h"
#include "sdvi/raster_io.h"

using namespace sdvi;

namespace {

using test::TempPath;

Raster Gradient(int w, int h, int channels) {
  Raster r(w, h, channels);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < channels; ++c) {
        const bool alpha = (channels == 2 && c == 1) || (channels == 4 && c == 3);
        r.at(x, y, c) = alpha ? float(x) / (w - 1) : float((x * 37 + y * 11 + c * 60) % 256);
      }
  return r;
}
}  // namespace

TEST_CASE("PNG round trip keeps channels and 8-bit values", "[raster_io]") {
  for (int channels : {1, 2, 3, 4}) {
    const Raster in = Gradient(23, 17, channels);
    const std::string path = TempPath("rt" + std::to_string(channels) + ".png");
    REQUIRE(SaveRasterPng(path, in).ok());
    auto out = LoadRaster(path);
    REQUIRE(out.ok());
    INFO("channels " << channels);
    // Every layout, grey+alpha included, is written and read back as it is.
    const int back_channels = channels;
    REQUIRE(out->channels == back_channels);
    for (int y = 0; y < in.height; ++y)
      for (int x = 0; x < in.width; ++x)
        for (int c = 0; c < back_channels; ++c) {
          const bool alpha = c == back_channels - 1 && in.has_alpha();
          const int src = channels == 2 ? (alpha ? 1 : 0) : c;
          CHECK(out->at(x, y, c) == Approx(in.at(x, y, src)).margin(alpha ? 0.51 / 255 : 1e-4));
        }
    std::filesystem::remove(path);
  }
}

TEST_CASE("16-bit PNG keeps fractions of the 8-bit scale", "[raster_io]") {
  Raster in(5, 3, 3);
  for (size_t i = 0; i < in.data.size(); ++i) in.data[i] = float(i) * 17.25f;
  const std::string path = TempPath("sixteen.png");
  REQUIRE(SaveRasterPng(path, in, 16).ok());
  auto out = LoadRaster(path);
  REQUIRE(out.ok());
  for (size_t i = 0; i < in.data.size(); ++i) CHECK(out->data[i] == Approx(std::min(in.data[i], 255.0f)).margin(0.005));
  std::filesystem::remove(path);
}

TEST_CASE("Raster I/O reports bad files with specific codes", "[raster_io][errors]") {
  CHECK(LoadRaster(TempPath("does_not_exist.png")).status().code() == StatusCode::kNotFound);
  const std::string empty = TempPath("empty.png");
  REQUIRE(WriteFileAtomic(empty, nullptr, 0).ok());
  CHECK(LoadRaster(empty).status().code() == StatusCode::kEmptyInput);
  const std::string junk = TempPath("junk.png");
  const std::string text = "this is not an image at all";
  REQUIRE(WriteFileAtomic(junk, text.data(), text.size()).ok());
  CHECK(LoadRaster(junk).status().code() == StatusCode::kDecodeFailed);
  // A PNG header claiming 100000 x 100000 pixels is refused before decoding.
  std::vector<uint8_t> huge = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a, 0, 0, 0, 13, 'I', 'H', 'D', 'R',
                               0, 1, 0x86, 0xa0, 0, 1, 0x86, 0xa0, 8, 2, 0, 0, 0, 0, 0, 0, 0};
  const std::string big = TempPath("huge.png");
  REQUIRE(WriteFileAtomic(big, huge).ok());
  CHECK(LoadRaster(big).status().code() == StatusCode::kLimitExceeded);
  CHECK(SaveRasterPng(TempPath("bad.png"), Raster(4, 4, 3), 12).code() == StatusCode::kInvalidArgument);
  CHECK(SaveRasterPng(TempPath("bad.png"), Raster(), 8).code() == StatusCode::kEmptyInput);
  CHECK(SaveRasterPng("/nonexistent-dir/x.png", Raster(4, 4, 3), 8).code() == StatusCode::kIoError);
  for (const auto& p : {empty, junk, big}) std::filesystem::remove(p);
}
