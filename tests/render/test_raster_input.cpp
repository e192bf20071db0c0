// SPDX-License-Identifier: GPL-3.0-or-later
// Image input as users expect it (spec/RASTER_INPUT.md): EXIF orientation, ICC profiles,
// GIF, OpenEXR and Radiance HDR input, the channels and sRGB tag of written PNGs.
// Every input is built here with a library other than the one sdvi reads with (OpenCV,
// giflib, zlib, Little CMS, OpenEXR) or byte by byte.
#include <catch2/catch.hpp>

#include <gif_lib.h>
#include <lcms2.h>
#include <zlib.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "sdvi/exr_io.h"
#include "sdvi/file_util.h"
#include "sdvi/raster_io.h"

using namespace sdvi;

// REQUIRE(x.ok()) that shows the status when it fails.
#define REQUIRE_OK(x)                                          \
  do {                                                         \
    INFO(((x).ok() ? std::string() : (x).status().ToString())); \
    REQUIRE((x).ok());                                         \
  } while (0)

namespace {

std::string InputTempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("sdvi_input_test_" + name)).string();
}

void PutBig32(std::vector<uint8_t>& out, uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(uint8_t(v >> s));
}

// A PNG chunk (length, type, data, CRC over type + data).
std::vector<uint8_t> PngChunk(const char* type, const std::vector<uint8_t>& data) {
  std::vector<uint8_t> chunk;
  chunk.reserve(12 + data.size());
  PutBig32(chunk, uint32_t(data.size()));
  chunk.insert(chunk.end(), type, type + 4);
  chunk.insert(chunk.end(), data.begin(), data.end());
  const uint32_t crc = uint32_t(crc32(crc32(0, reinterpret_cast<const Bytef*>(type), 4), data.data(), uInt(data.size())));
  PutBig32(chunk, crc);
  return chunk;
}

// sRGB encoding of linear light, 0..255.
double Encode(double linear) {
  linear = std::clamp(linear, 0.0, 1.0);
  return 255 * (linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1 / 2.4) - 0.055);
}

using Mat3 = std::array<std::array<double, 3>, 3>;
Mat3 Inverse(const Mat3& m) {
  const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                     m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int a = (j + 1) % 3, b = (j + 2) % 3, c = (i + 1) % 3, d = (i + 2) % 3;
      r[i][j] = (m[a][c] * m[b][d] - m[a][d] * m[b][c]) / det;
    }
  return r;
}
// RGB -> XYZ of primaries (x, y) and white (x, y), the textbook construction.
Mat3 RgbToXyz(const std::array<std::array<double, 2>, 3>& p, std::array<double, 2> white) {
  Mat3 m;
  for (int c = 0; c < 3; ++c) {
    m[0][c] = p[c][0] / p[c][1];
    m[1][c] = 1;
    m[2][c] = (1 - p[c][0] - p[c][1]) / p[c][1];
  }
  const std::array<double, 3> w = {white[0] / white[1], 1, (1 - white[0] - white[1]) / white[1]};
  const Mat3 inv = Inverse(m);
  for (int c = 0; c < 3; ++c) {
    const double s = inv[c][0] * w[0] + inv[c][1] * w[1] + inv[c][2] * w[2];
    for (int r = 0; r < 3; ++r) m[r][c] *= s;
  }
  return m;
}

constexpr std::array<double, 2> kD65 = {0.3127, 0.3290};
constexpr std::array<std::array<double, 2>, 3> kP3 = {{{0.680, 0.320}, {0.265, 0.690}, {0.150, 0.060}}};
constexpr std::array<std::array<double, 2>, 3> kSrgb = {{{0.640, 0.330}, {0.300, 0.600}, {0.150, 0.060}}};

// An ICC profile (Little CMS): Display P3 primaries, D65, pure gamma 2.2, with a description.
std::vector<uint8_t> P3Gamma22Profile() {
  const cmsCIExyY white = {kD65[0], kD65[1], 1.0};
  cmsCIExyYTRIPLE primaries;
  primaries.Red = {kP3[0][0], kP3[0][1], 1.0};
  primaries.Green = {kP3[1][0], kP3[1][1], 1.0};
  primaries.Blue = {kP3[2][0], kP3[2][1], 1.0};
  cmsToneCurve* gamma = cmsBuildGamma(nullptr, 2.2);
  cmsToneCurve* curves[3] = {gamma, gamma, gamma};
  cmsHPROFILE profile = cmsCreateRGBProfile(&white, &primaries, curves);
  cmsMLU* text = cmsMLUalloc(nullptr, 1);
  cmsMLUsetASCII(text, "en", "US", "sdvi test P3 gamma 2.2");
  cmsWriteTag(profile, cmsSigProfileDescriptionTag, text);
  cmsUInt32Number size = 0;
  cmsSaveProfileToMem(profile, nullptr, &size);
  std::vector<uint8_t> bytes(size);
  cmsSaveProfileToMem(profile, bytes.data(), &size);
  cmsMLUfree(text);
  cmsFreeToneCurve(gamma);
  cmsCloseProfile(profile);
  return bytes;
}

// Encodes an RGB raster (0..255) with OpenCV (BGR order), as ".png" or ".jpg".
std::vector<uint8_t> EncodeWithOpenCv(const Raster& r, const std::string& ext) {
  cv::Mat m(r.height, r.width, CV_8UC3);
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < r.width; ++x)
      for (int c = 0; c < 3; ++c) m.ptr<uint8_t>(y)[x * 3 + c] = uint8_t(r.at(x, y, 2 - c));
  std::vector<uint8_t> bytes;
  const std::vector<int> params = ext == ".jpg" ? std::vector<int>{cv::IMWRITE_JPEG_QUALITY, 100} : std::vector<int>{};
  REQUIRE(cv::imencode(ext, m, bytes, params));
  return bytes;
}

int PngColourType(const std::vector<uint8_t>& png) { return png.size() > 25 ? png[25] : -1; }

}  // namespace

TEST_CASE("EXIF orientation 6 (rotate 90 clockwise) is applied to a JPEG", "[raster_input]") {
  // Stored sideways: 16 wide, 24 tall, four 8x8-aligned flat blocks (JPEG keeps them exact-ish).
  Raster stored(16, 24, 3);
  const float colours[6][3] = {{250, 10, 10}, {10, 250, 10}, {10, 10, 250}, {250, 250, 10}, {10, 250, 250}, {250, 10, 250}};
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c = 0; c < 3; ++c) stored.at(x, y, c) = colours[(y / 8) * 2 + x / 8][c];
  std::vector<uint8_t> jpeg = EncodeWithOpenCv(stored, ".jpg");
  // APP1 "Exif", big-endian TIFF header, one IFD entry: Orientation (0x0112) SHORT = 6.
  const std::vector<uint8_t> app1 = {0xFF, 0xE1, 0, 34, 'E', 'x', 'i', 'f', 0, 0, 'M', 'M', 0, 0x2A, 0, 0, 0, 8,
                                     0,    1,    0x01, 0x12, 0, 3, 0, 0, 0, 1, 0, 6, 0, 0, 0, 0, 0, 0};
  REQUIRE(app1.size() == 36);
  jpeg.insert(jpeg.begin() + 2, app1.begin(), app1.end());
  RasterSource source;
  auto upright = DecodeRaster(jpeg, "rotated.jpg", &source);
  REQUIRE_OK(upright);
  CHECK(source.format == "jpeg");
  CHECK(source.orientation == 6);
  REQUIRE(upright->width == 24);
  REQUIRE(upright->height == 16);
  REQUIRE(upright->channels == 3);
  // Rotating 90 degrees clockwise: displayed (x, y) = stored (y, H - 1 - x).
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 24; ++x)
      for (int c = 0; c < 3; ++c) {
        const int sx = y, sy = 23 - x;
        if (sx % 8 == 0 || sx % 8 == 7 || sy % 8 == 0 || sy % 8 == 7) continue;  // block edges ring
        INFO("pixel " << x << "," << y << " channel " << c);
        CHECK(std::abs(upright->at(x, y, c) - stored.at(sx, sy, c)) <= 12);
      }
  // Without the tag the same pixels come out as stored.
  auto plain = DecodeRaster(EncodeWithOpenCv(stored, ".jpg"), "plain.jpg");
  REQUIRE_OK(plain);
  CHECK(plain->width == 16);
  CHECK(plain->height == 24);
}

TEST_CASE("An embedded ICC profile (P3, gamma 2.2) is converted to sRGB", "[raster_input]") {
  const float values[4][3] = {{200, 100, 50}, {128, 128, 128}, {30, 180, 90}, {255, 255, 255}};
  Raster in(4, 1, 3);
  for (int x = 0; x < 4; ++x)
    for (int c = 0; c < 3; ++c) in.at(x, 0, c) = values[x][c];
  std::vector<uint8_t> png = EncodeWithOpenCv(in, ".png");
  // iCCP: name, 0, compression method 0, zlib stream of the profile; right after IHDR.
  const std::vector<uint8_t> profile = P3Gamma22Profile();
  std::vector<uint8_t> compressed(compressBound(uLong(profile.size())));
  uLongf size = uLongf(compressed.size());
  REQUIRE(compress2(compressed.data(), &size, profile.data(), uLong(profile.size()), 9) == Z_OK);
  std::vector<uint8_t> iccp = {'P', '3', 0, 0};
  iccp.reserve(4 + size);
  iccp.insert(iccp.end(), compressed.begin(), compressed.begin() + size);
  const std::vector<uint8_t> chunk = PngChunk("iCCP", iccp);
  png.insert(png.begin() + 33, chunk.begin(), chunk.end());

  RasterSource source;
  auto out = DecodeRaster(png, "p3.png", &source);
  REQUIRE_OK(out);
  CHECK(source.icc_converted);
  CHECK(source.icc_profile == "sdvi test P3 gamma 2.2");
  CHECK(source.warnings.empty());
  REQUIRE(out->channels == 3);
  // Independent: linear P3 -> XYZ -> linear sRGB (same white, so no adaptation), clipped, encoded.
  const Mat3 p3 = RgbToXyz(kP3, kD65), srgb_inv = Inverse(RgbToXyz(kSrgb, kD65));
  bool any_changed = false;
  for (int x = 0; x < 4; ++x) {
    std::array<double, 3> lin{}, xyz{}, s{};
    for (int c = 0; c < 3; ++c) lin[c] = std::pow(values[x][c] / 255.0, 2.2);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) xyz[r] += p3[r][c] * lin[c];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) s[r] += srgb_inv[r][c] * xyz[c];
    for (int c = 0; c < 3; ++c) {
      INFO("pixel " << x << " channel " << c);
      CHECK(out->at(x, 0, c) == Approx(Encode(s[c])).margin(0.6));
      any_changed |= std::abs(Encode(s[c]) - values[x][c]) > 5;
    }
  }
  CHECK(any_changed);  // the profile matters: taking the samples as sRGB would fail above
}

TEST_CASE("An unusable ICC profile is a warning, the samples taken as sRGB", "[raster_input]") {
  Raster in(16, 8, 3);
  for (size_t i = 0; i < in.data.size(); ++i) in.data[i] = float(i * 20 % 256);
  const std::vector<uint8_t> plain = EncodeWithOpenCv(in, ".jpg");
  // APP2 "ICC_PROFILE\0", chunk 1 of 1, then bytes that are no ICC profile (libjpeg does not
  // check them; libpng would have dropped such a profile from a PNG itself).
  const std::string junk = "not an ICC profile at all, just some text";
  const std::string tag = std::string("ICC_PROFILE") + '\0';
  std::vector<uint8_t> app2 = {0xFF, 0xE2, 0, 0};
  app2.reserve(4 + tag.size() + 2 + junk.size());
  app2.insert(app2.end(), tag.begin(), tag.end());
  app2.push_back(1), app2.push_back(1);
  app2.insert(app2.end(), junk.begin(), junk.end());
  app2[2] = uint8_t((app2.size() - 2) >> 8), app2[3] = uint8_t(app2.size() - 2);
  std::vector<uint8_t> tagged = plain;
  tagged.insert(tagged.begin() + 2, app2.begin(), app2.end());
  RasterSource source;
  auto out = DecodeRaster(tagged, "junk_icc.jpg", &source);
  REQUIRE_OK(out);
  CHECK_FALSE(source.icc_converted);
  REQUIRE(source.warnings.size() == 1);
  CHECK(source.warnings[0].find("junk_icc.jpg") != std::string::npos);
  CHECK(source.warnings[0].find("ICC") != std::string::npos);
  auto reference = DecodeRaster(plain, "plain.jpg");
  REQUIRE_OK(reference);
  CHECK(out->data == reference->data);  // the same samples as without the profile
}

namespace {
// A GIF (giflib): palette colours, optionally one transparent index.
std::vector<uint8_t> MakeGif(int w, int h, const std::vector<uint8_t>& indices, int transparent) {
  std::vector<uint8_t> bytes;
  int error = 0;
  GifFileType* gif = EGifOpen(&bytes,
                              [](GifFileType* g, const GifByteType* data, int n) {
                                auto* out = static_cast<std::vector<uint8_t>*>(g->UserData);
                                out->insert(out->end(), data, data + n);
                                return n;
                              },
                              &error);
  REQUIRE(gif);
  const GifColorType palette[4] = {{255, 0, 0}, {0, 200, 0}, {10, 20, 250}, {240, 240, 240}};
  ColorMapObject* map = GifMakeMapObject(4, palette);
  EGifSetGifVersion(gif, true);
  REQUIRE(EGifPutScreenDesc(gif, w, h, 2, 0, map) == GIF_OK);
  if (transparent >= 0) {
    GraphicsControlBlock gcb{};
    gcb.DisposalMode = DISPOSAL_UNSPECIFIED;
    gcb.TransparentColor = transparent;
    GifByteType ext[4];
    const size_t n = EGifGCBToExtension(&gcb, ext);
    REQUIRE(EGifPutExtension(gif, GRAPHICS_EXT_FUNC_CODE, int(n), ext) == GIF_OK);
  }
  REQUIRE(EGifPutImageDesc(gif, 0, 0, w, h, false, nullptr) == GIF_OK);
  std::vector<GifPixelType> line(w);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) line[x] = indices[size_t(y) * w + x];
    REQUIRE(EGifPutLine(gif, line.data(), w) == GIF_OK);
  }
  REQUIRE(EGifCloseFile(gif, &error) == GIF_OK);
  GifFreeMapObject(map);
  return bytes;
}
}  // namespace

TEST_CASE("GIF input: palette colours exact, alpha only when a pixel is transparent", "[raster_input]") {
  const int w = 7, h = 5;
  const int palette[4][3] = {{255, 0, 0}, {0, 200, 0}, {10, 20, 250}, {240, 240, 240}};
  std::vector<uint8_t> indices(size_t(w) * h);
  for (size_t i = 0; i < indices.size(); ++i) indices[i] = uint8_t((i * 7 + i / 3) % 4);
  for (int transparent : {-1, 3}) {
    INFO("transparent index " << transparent);
    RasterSource source;
    auto out = DecodeRaster(MakeGif(w, h, indices, transparent), "palette.gif", &source);
    REQUIRE_OK(out);
    CHECK(source.format == "gif");
    REQUIRE(out->width == w);
    REQUIRE(out->height == h);
    REQUIRE(out->channels == (transparent < 0 ? 3 : 4));
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const int i = indices[size_t(y) * w + x];
        if (i == transparent) {
          CHECK(out->at(x, y, 3) == 0.0f);
          continue;
        }
        for (int c = 0; c < 3; ++c) CHECK(out->at(x, y, c) == float(palette[i][c]));
        if (transparent >= 0) CHECK(out->at(x, y, 3) == 1.0f);
      }
  }
}

TEST_CASE("OpenEXR input: linear premultiplied -> straight sRGB 0..255, clipped", "[raster_input]") {
  // SaveExr (OpenEXR) stores sRGB 0..255 as linear light premultiplied by alpha.
  Raster in(6, 4, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x) {
      for (int c = 0; c < 3; ++c) in.at(x, y, c) = float((x * 40 + y * 23 + c * 70) % 256);
      in.at(x, y, 3) = (x + y) % 3 == 0 ? 0.5f : 1.0f;
    }
  const std::string path = InputTempPath("linear.exr");
  REQUIRE(SaveExr(path, in).ok());
  RasterSource source;
  auto out = LoadRaster(path, &source);
  REQUIRE_OK(out);
  CHECK(source.format == "openexr");
  CHECK(source.linear);
  REQUIRE(out->channels == 4);
  for (size_t i = 0; i < in.data.size(); ++i) CHECK(out->data[i] == Approx(in.data[i]).margin(0.01));
  // Without alpha the EXR has R, G, B only and reads back RGB.
  Raster rgb(3, 2, 3);
  for (size_t i = 0; i < rgb.data.size(); ++i) rgb.data[i] = float(i * 41 % 256);
  REQUIRE(SaveExr(path, rgb).ok());
  auto back = LoadRaster(path);
  REQUIRE_OK(back);
  REQUIRE(back->channels == 3);
  for (size_t i = 0; i < rgb.data.size(); ++i) CHECK(back->data[i] == Approx(rgb.data[i]).margin(0.01));
  std::filesystem::remove(path);
}

TEST_CASE("Radiance HDR input: RGBE decoded, linear -> sRGB, above 1 clipped", "[raster_input]") {
  // Written byte by byte: flat (not run-length) scanlines of 3 pixels.
  std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 3\n";
  std::vector<uint8_t> bytes(header.begin(), header.end());
  // (0.5, 0.25, 0.125): mantissas 128, 64, 32, exponent 0 -> 128. (2, 2, 2): 128, e = 2 -> 130.
  // (0.0625, 0.0625, 0): 128 with e = -3 -> 125.
  const uint8_t pixels[3][4] = {{128, 64, 32, 128}, {128, 128, 128, 130}, {128, 128, 0, 125}};
  bytes.reserve(header.size() + sizeof(pixels));
  for (const auto& p : pixels) bytes.insert(bytes.end(), p, p + 4);
  RasterSource source;
  auto out = DecodeRaster(bytes, "light.hdr", &source);
  REQUIRE_OK(out);
  CHECK(source.format == "hdr");
  REQUIRE(out->channels == 3);
  const double expected[3][3] = {{0.5, 0.25, 0.125}, {2, 2, 2}, {0.0625, 0.0625, 0}};
  for (int x = 0; x < 3; ++x)
    for (int c = 0; c < 3; ++c) {
      INFO("pixel " << x << " channel " << c);
      CHECK(out->at(x, 0, c) == Approx(Encode(expected[x][c])).margin(0.75));
    }
  CHECK(out->at(1, 0, 0) == 255.0f);
}

// A PNG of the given IHDR fields whose scanlines (filter byte 0 each, already packed) are
// raw, with extra chunks (PLTE, tRNS, eXIf) between IHDR and IDAT.
std::vector<uint8_t> MakePng(uint32_t w, uint32_t h, int depth, int colour_type, int interlace,
                             const std::vector<uint8_t>& raw, const std::vector<std::vector<uint8_t>>& extra = {}) {
  std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
  std::vector<uint8_t> ihdr;
  PutBig32(ihdr, w), PutBig32(ihdr, h);
  ihdr.insert(ihdr.end(), {uint8_t(depth), uint8_t(colour_type), 0, 0, uint8_t(interlace)});
  auto append = [&](const std::vector<uint8_t>& c) { png.insert(png.end(), c.begin(), c.end()); };
  append(PngChunk("IHDR", ihdr));
  for (const auto& c : extra) append(c);
  uLongf size = compressBound(uLong(raw.size()));
  std::vector<uint8_t> z(size);
  REQUIRE(compress(z.data(), &size, raw.data(), uLong(raw.size())) == Z_OK);
  z.resize(size);
  append(PngChunk("IDAT", z));
  append(PngChunk("IEND", {}));
  return png;
}

TEST_CASE("PNG input (libpng): palettes, low-bit grey and tRNS expand, Adam7 and eXIf read", "[raster_input]") {
  // A 2-bit palette image, 3 x 2, indices 0 1 2 / 3 0 1; tRNS gives entries 0 and 1 alpha.
  const std::vector<uint8_t> plte = {255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30};
  const std::vector<uint8_t> raw_palette = {0, 0b00011000, 0, 0b11000100};
  RasterSource source;
  auto pal = DecodeRaster(MakePng(3, 2, 2, 3, 0, raw_palette, {PngChunk("PLTE", plte), PngChunk("tRNS", {0, 128})}),
                          "palette.png", &source);
  REQUIRE_OK(pal);
  CHECK(source.format == "png");
  REQUIRE(pal->channels == 4);
  const int index[2][3] = {{0, 1, 2}, {3, 0, 1}};
  const float alpha[4] = {0.0f, float(128 * (1.0 / 255)), 1.0f, 1.0f};
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) {
      const int i = index[y][x];
      for (int c = 0; c < 3; ++c) CHECK(pal->at(x, y, c) == float(plte[size_t(3 * i + c)]));
      CHECK(pal->at(x, y, 3) == alpha[i]);
    }
  // 1-bit grey: 0 and 1 become 0 and 255.
  auto grey = DecodeRaster(MakePng(3, 1, 1, 0, 0, {0, 0b10100000}), "bits.png");
  REQUIRE_OK(grey);
  REQUIRE(grey->channels == 1);
  CHECK(grey->data == std::vector<float>{255, 0, 255});
  // Adam7: a 5 x 5 RGB image interlaced reads as the same image stored plainly.
  std::vector<uint8_t> pixel(5 * 5 * 3);
  for (size_t i = 0; i < pixel.size(); ++i) pixel[i] = uint8_t(i * 37 % 251);
  std::vector<uint8_t> plain, adam7;
  for (int y = 0; y < 5; ++y) {
    plain.push_back(0);
    plain.insert(plain.end(), pixel.begin() + y * 15, pixel.begin() + (y + 1) * 15);
  }
  const int passes[7][4] = {{0, 0, 8, 8}, {4, 0, 8, 8}, {0, 4, 4, 8}, {2, 0, 4, 4}, {0, 2, 2, 4}, {1, 0, 2, 2}, {0, 1, 1, 2}};
  for (const auto& p : passes) {
    if (p[0] >= 5) continue;  // an empty pass has no scanlines
    for (int y = p[1]; y < 5; y += p[3]) {
      adam7.push_back(0);
      for (int x = p[0]; x < 5; x += p[2]) adam7.insert(adam7.end(), pixel.begin() + (y * 5 + x) * 3, pixel.begin() + (y * 5 + x + 1) * 3);
    }
  }
  auto a = DecodeRaster(MakePng(5, 5, 8, 2, 0, plain), "plain.png");
  auto b = DecodeRaster(MakePng(5, 5, 8, 2, 1, adam7), "adam7.png");
  REQUIRE_OK(a);
  REQUIRE_OK(b);
  CHECK(a->data == b->data);
  CHECK(a->at(4, 4, 2) == float(pixel[74]));
  // eXIf orientation 6 (rotate 90 clockwise): 3 x 2 -> 2 x 3, the bottom-left pixel first.
  std::vector<uint8_t> exif = {'M', 'M', 0, 42, 0, 0, 0, 8, 0, 1, 0x01, 0x12, 0, 3, 0, 0, 0, 1, 0, 6, 0, 0, 0, 0, 0, 0};
  const std::vector<uint8_t> raw_rgb = {0, 1, 1, 1, 2, 2, 2, 3, 3, 3, 0, 4, 4, 4, 5, 5, 5, 6, 6, 6};
  auto turned = DecodeRaster(MakePng(3, 2, 8, 2, 0, raw_rgb, {PngChunk("eXIf", exif)}), "turned.png", &source);
  REQUIRE_OK(turned);
  CHECK(source.orientation == 6);
  REQUIRE(turned->width == 2);
  REQUIRE(turned->height == 3);
  CHECK(turned->at(0, 0, 0) == 4.0f);
  CHECK(turned->at(1, 0, 0) == 1.0f);
  // Cut short in the pixel data: truncated, never a partial image.
  std::vector<uint8_t> cut = MakePng(5, 5, 8, 2, 0, plain);
  cut.resize(cut.size() - 30);
  CHECK(DecodeRaster(cut, "cut.png").status().code() == StatusCode::kTruncated);
}

TEST_CASE("Written PNGs keep the raster's channels and carry an sRGB chunk", "[raster_input]") {
  // PNG colour types: 0 grey, 4 grey+alpha, 2 RGB, 6 RGBA.
  const int types[5] = {-1, 0, 4, 2, 6};
  for (int channels : {1, 2, 3, 4}) {
    Raster r(5, 3, channels);
    for (size_t i = 0; i < r.data.size(); ++i) r.data[i] = r.has_alpha() && int(i % channels) == channels - 1 ? 0.5f : float(i * 13 % 256);
    auto png = EncodePng(r);
    REQUIRE_OK(png);
    CHECK(PngColourType(*png) == types[channels]);
    // The sRGB chunk (rendering intent byte) comes before IDAT.
    const std::string text(png->begin(), png->end());
    const size_t srgb = text.find("sRGB"), idat = text.find("IDAT");
    REQUIRE(srgb != std::string::npos);
    CHECK(srgb < idat);
    auto back = DecodeRaster(*png, "back.png");
    REQUIRE_OK(back);
    REQUIRE(back->channels == channels);
    for (size_t i = 0; i < r.data.size(); ++i) CHECK(back->data[i] == Approx(r.data[i]).margin(0.51 / 255));
    // Deterministic bytes.
    CHECK(*EncodePng(r) == *png);
  }
}

TEST_CASE("WithNeededChannels drops a full-coverage alpha and collapses exact grey", "[raster_input]") {
  Raster rgba(2, 1, 4);
  const float px[8] = {10, 20, 30, 1, 40, 50, 60, 1};
  std::copy(px, px + 8, rgba.data.begin());
  Raster rgb = WithNeededChannels(rgba);
  REQUIRE(rgb.channels == 3);
  CHECK(rgb.data == std::vector<float>{10, 20, 30, 40, 50, 60});
  rgba.at(1, 0, 3) = 0.25f;  // partly outside the domain: alpha stays
  CHECK(WithNeededChannels(rgba).channels == 4);
  Raster grey(2, 1, 4);
  const float g[8] = {7, 7, 7, 1, 9, 9, 9, 0};
  std::copy(g, g + 8, grey.data.begin());
  Raster ga = WithNeededChannels(grey);
  REQUIRE(ga.channels == 2);
  CHECK(ga.data == std::vector<float>{7, 1, 9, 0});
}

TEST_CASE("A BMP whose pixel data offset lies before the file is an error, read within the bytes",
          "[raster_input]") {
  // 5x6 pixels, 24 bits, BITMAPINFOHEADER; bfOffBits = 0xffffffc0 (-64 as a signed offset).
  // OpenImageIO's memory reader once copied from before the buffer here (ASan, fuzz.raster).
  std::vector<uint8_t> bmp(130, 0x5A);
  const uint8_t header[] = {'B', 'M', 0x82, 0, 0, 0, 0, 0, 0, 0, 0xc0, 0xff, 0xff, 0xff, 40, 0, 0, 0,
                            5, 0, 0, 0, 6, 0, 0, 0, 1, 0, 24, 0, 0, 0, 0, 0};
  std::copy(std::begin(header), std::end(header), bmp.begin());
  std::fill(bmp.begin() + sizeof(header), bmp.begin() + 54, uint8_t{0});
  auto out = DecodeRaster(bmp, "offset.bmp");
  REQUIRE_FALSE(out.ok());
  CHECK(out.status().message().find("offset.bmp") != std::string::npos);
}

TEST_CASE("A BMP with 24 bits a pixel that says RLE8 is a clear error, not a crash", "[raster_input]") {
  // 5x6 pixels, BITMAPINFOHEADER, biBitCount 24, biCompression 1 (RLE8), then six rows of the
  // run (5 pixels of index 7) and the end-of-bitmap mark. RLE8 has a colour table only at 8
  // bits a pixel; OpenImageIO 2.4 looked the runs up in the absent table and crashed
  // (SEGV under ASan, fuzz.raster). Likewise RLE4 at 16 bits.
  for (const auto& [bits, compression] : {std::pair{24, 1}, std::pair{32, 1}, std::pair{16, 2}}) {
    std::array<uint8_t, 78> bmp{};
    const uint8_t header[] = {'B', 'M', uint8_t(bmp.size()), 0, 0, 0, 0, 0, 0, 0, 54, 0, 0, 0, 40, 0, 0, 0,
                              5, 0, 0, 0, 6, 0, 0, 0, 1, 0, uint8_t(bits), 0, uint8_t(compression), 0, 0, 0,
                              24, 0, 0, 0};
    std::copy(std::begin(header), std::end(header), bmp.begin());
    for (int row = 0; row < 6; ++row) {
      bmp[size_t(54 + 4 * row)] = 5;
      bmp[size_t(55 + 4 * row)] = 7;
      bmp[size_t(57 + 4 * row)] = row == 5 ? 1 : 0;
    }
    INFO("bits " << bits << ", compression " << compression);
    auto out = DecodeRaster(std::vector<uint8_t>(bmp.begin(), bmp.end()), "rle.bmp");
    REQUIRE_FALSE(out.ok());
    CHECK(out.status().code() == StatusCode::kDecodeFailed);
    CHECK(out.status().message().find("rle.bmp: damaged BMP header: RLE") != std::string::npos);
  }
}

TEST_CASE("A BMP's size is checked on its header before OpenImageIO opens it, whatever its name", "[raster_input]") {
  // OpenImageIO 2.4 decodes an RLE BMP whole while opening it: a 108-byte file declaring
  // 5 x 419430406 pixels (fuzz.raster) made it fill 2 GB before sdvi saw the size. Named
  // .tga (so the BMP reader is not the first tried) and declaring RLE8 at 8 bits.
  for (const int32_t height : {419430406, -419430406}) {
    std::array<uint8_t, 108> bmp{};
    const uint32_t h = uint32_t(height);
    const uint8_t header[] = {'B', 'M', uint8_t(bmp.size()), 0, 0, 0, 0, 0, 0, 0, 54, 0, 0, 0, 40, 0, 0, 0,
                              5, 0, 0, 0, uint8_t(h), uint8_t(h >> 8), uint8_t(h >> 16), uint8_t(h >> 24),
                              1, 0, 8, 0, 1, 0, 0, 0};
    std::copy(std::begin(header), std::end(header), bmp.begin());
    std::fill(bmp.begin() + 54, bmp.end(), uint8_t(0xff));
    INFO("height " << height);
    auto out = DecodeRaster(std::vector<uint8_t>(bmp.begin(), bmp.end()), "tall.tga");
    REQUIRE_FALSE(out.ok());
    CHECK(out.status().code() == StatusCode::kLimitExceeded);
    CHECK(out.status().message() == "tall.tga: 5x419430406 pixels is over the limit of 268435456");
  }
  // A 24-bit RLE8 header is refused before opening too: the words name the damage, not
  // "none of PNG, JPEG, ..." after every reader failed.
  std::array<uint8_t, 108> bmp{};
  const uint8_t header[] = {'B', 'M', 108, 0, 0, 0, 0, 0, 0, 0, 54, 0, 0, 0, 40, 0, 0, 0,
                            5, 0, 0, 0, 6, 0, 0, 0x19, 1, 0, 24, 0, 1, 0, 0, 0};
  std::copy(std::begin(header), std::end(header), bmp.begin());
  auto out = DecodeRaster(std::vector<uint8_t>(bmp.begin(), bmp.end()), "fuzzed.bmp");
  REQUIRE_FALSE(out.ok());
  CHECK(out.status().message() == "fuzzed.bmp: damaged BMP header: RLE8 compression with 24 bits a pixel (RLE8 needs 8)");
}

TEST_CASE("Only the listed formats are read: an SGI file is refused by extension or content", "[raster_input]") {
  // A 4x3 grey SGI image (verbatim storage, 1 byte a sample), byte by byte: OpenImageIO 2.4
  // reads it, and before sdvi chose its readers it was decoded under any name.
  std::vector<uint8_t> sgi(512, 0);
  const uint8_t header[] = {0x01, 0xDA, 0, 1, 0, 2, 0, 4, 0, 3, 0, 1, 0, 0, 0, 0, 0, 0, 0, 255};
  std::copy(std::begin(header), std::end(header), sgi.begin());
  for (int i = 0; i < 12; ++i) sgi.push_back(uint8_t(20 * i));
  auto named = DecodeRaster(sgi, "grey.sgi");
  REQUIRE_FALSE(named.ok());
  CHECK(named.status().code() == StatusCode::kUnsupportedFormat);
  CHECK(named.status().message() ==
        "grey.sgi: the extension says sgi, which sdvi does not read, and the bytes are none of PNG, JPEG, TIFF, BMP, "
        "GIF, WebP, OpenEXR, Radiance HDR, PNM, TGA");
  for (const char* name : {"grey", "grey.png"}) {
    auto other = DecodeRaster(sgi, name);
    REQUIRE_FALSE(other.ok());
    CHECK(other.status().code() == StatusCode::kDecodeFailed);
    CHECK(other.status().message().rfind(std::string(name) + ": not an image sdvi can decode (", 0) == 0);
  }
  // A listed format is read whatever the name says: a PNG named .jpg, or with no extension.
  std::vector<uint8_t> png;
  REQUIRE(cv::imencode(".png", cv::Mat(3, 4, CV_8UC1, cv::Scalar(77)), png));
  for (const char* name : {"grey.jpg", "grey", "grey.sgi"}) {
    auto read = DecodeRaster(png, name);
    INFO(name);
    REQUIRE_OK(read);
    CHECK(read->width == 4);
    CHECK(read->data[0] == 77.0f);
  }
}
