// SPDX-License-Identifier: GPL-3.0-or-later
// Raster input (raster_io.h): header size checked before decoding, truncated or damaged
// data refused, decoder messages captured into the Status.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "sdvi/file_util.h"
#include "sdvi/raster_io.h"

namespace fs = std::filesystem;
using sdvi::StatusCode;

namespace {

fs::path Scratch() {
  const fs::path dir = fs::temp_directory_path() / ("sdvi_raster_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

// A noisy colour image (noise keeps the encoded data long enough to cut).
std::vector<uint8_t> Encoded(const std::string& ext, int w = 96, int h = 64) {
  cv::Mat mat(h, w, CV_8UC3);
  cv::RNG rng(7);
  rng.fill(mat, cv::RNG::UNIFORM, 0, 256);
  std::vector<uint8_t> bytes;
  REQUIRE(cv::imencode(ext, mat, bytes));
  return bytes;
}

std::string Put(const std::string& name, const std::vector<uint8_t>& bytes) {
  const std::string path = (Scratch() / name).string();
  REQUIRE(sdvi::WriteFileAtomic(path, bytes).ok());
  return path;
}

// Offset of the JPEG baseline frame header (SOF0, FF C0) or -1.
long FindSof(const std::vector<uint8_t>& b) {
  for (size_t i = 2; i + 9 < b.size(); ++i)
    if (b[i] == 0xff && b[i + 1] == 0xc0) return long(i);
  return -1;
}

void SetJpegSize(std::vector<uint8_t>& b, int w, int h) {
  const long sof = FindSof(b);
  REQUIRE(sof > 0);
  b[sof + 5] = uint8_t(h >> 8), b[sof + 6] = uint8_t(h);
  b[sof + 7] = uint8_t(w >> 8), b[sof + 8] = uint8_t(w);
}

}  // namespace

TEST_CASE("every format reads: PNG, JPEG, TIFF, BMP, WebP, PNM") {
  for (const char* ext : {".png", ".jpg", ".tif", ".bmp", ".webp", ".ppm"}) {
    INFO(ext);
    auto raster = sdvi::LoadRaster(Put(std::string("ok") + ext, Encoded(ext)));
    REQUIRE(raster.ok());
    CHECK(raster->width == 96);
    CHECK(raster->height == 64);
  }
}

TEST_CASE("issue 16.3: a JPEG declaring 30000^2 pixels is refused from its header") {
  std::vector<uint8_t> jpeg = Encoded(".jpg");
  SetJpegSize(jpeg, 30000, 30000);
  auto big = sdvi::LoadRaster(Put("big.jpg", jpeg));
  CHECK(big.status().code() == StatusCode::kLimitExceeded);
  CHECK(big.status().message().find("30000x30000") != std::string::npos);
}

TEST_CASE("huge sizes in PNG, TIFF, BMP and PNM headers are refused before decoding") {
  std::vector<uint8_t> png = Encoded(".png");
  png[16] = 0, png[17] = 1, png[18] = 0, png[19] = 0;  // width 65536 (the CRC is not checked first)
  auto p = sdvi::LoadRaster(Put("big.png", png));
  CHECK(p.status().code() != StatusCode::kOk);
  std::vector<uint8_t> bmp = Encoded(".bmp");
  bmp[18] = 0, bmp[19] = 0, bmp[20] = 0, bmp[21] = 0x10;  // width 2^28
  CHECK(!sdvi::LoadRaster(Put("big.bmp", bmp)).ok());
  const std::string pnm = "P6\n100000 100000\n255\n";
  CHECK(sdvi::LoadRaster(Put("big.ppm", std::vector<uint8_t>(pnm.begin(), pnm.end()))).status().code() ==
        StatusCode::kLimitExceeded);
}

TEST_CASE("issue 16.3: a JPEG truncated in half is kTruncated, with libjpeg's words, printed nowhere") {
  std::vector<uint8_t> jpeg = Encoded(".jpg", 256, 256);
  jpeg.resize(jpeg.size() / 2);
  const std::string path = Put("half.jpg", jpeg);
  // Nothing reaches standard error: capture it around the call.
  std::fflush(stderr);
  FILE* sink = std::tmpfile();
  const int saved = ::dup(2);
  ::dup2(::fileno(sink), 2);
  auto raster = sdvi::LoadRaster(path);
  std::fflush(stderr);
  ::dup2(saved, 2);
  ::close(saved);
  CHECK(std::ftell(sink) == 0);
  std::fclose(sink);
  CHECK(raster.status().code() == StatusCode::kTruncated);
  CHECK(raster.status().message().find(path) == 0);
  CHECK(raster.status().message().find("Premature end") != std::string::npos);
}

TEST_CASE("truncated PNG, TIFF, BMP and WebP files are errors, never partial images, printed nowhere") {
  std::fflush(stderr);
  FILE* sink = std::tmpfile();
  const int saved = ::dup(2);
  ::dup2(::fileno(sink), 2);
  for (const char* ext : {".png", ".tif", ".bmp", ".webp", ".jpg"}) {
    const std::vector<uint8_t> whole = Encoded(ext, 128, 128);
    for (size_t keep : {whole.size() / 4, whole.size() / 2, whole.size() * 3 / 4, whole.size() - 20}) {
      INFO(ext << " cut to " << keep << " of " << whole.size());
      std::vector<uint8_t> cut(whole.begin(), whole.begin() + long(keep));
      auto raster = sdvi::LoadRaster(Put(std::string("cut") + ext, cut));
      CHECK(!raster.ok());
    }
  }
  std::fflush(stderr);
  ::dup2(saved, 2);
  ::close(saved);
  CHECK(std::ftell(sink) == 0);
  std::fclose(sink);
}

TEST_CASE("an unknown or empty file is a clear error naming it") {
  const std::string text = "hello, not an image";
  auto r = sdvi::LoadRaster(Put("x.png", std::vector<uint8_t>(text.begin(), text.end())));
  CHECK(r.status().code() == StatusCode::kDecodeFailed);
  CHECK(r.status().message().find("x.png") != std::string::npos);
  CHECK(sdvi::LoadRaster(Put("empty.png", {})).status().code() == StatusCode::kEmptyInput);
  fs::remove_all(Scratch());
}
