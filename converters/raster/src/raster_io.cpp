// Raster image files through OpenCV's imgcodecs (raster_io.h). OpenCV exceptions stop here.
#include "sdvi/raster_io.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "sdvi/file_util.h"

namespace sdvi {
namespace {

constexpr uint64_t kMaxPixels = uint64_t(1) << 28;  // 16384 x 16384

bool IsPng(const std::vector<uint8_t>& b) {
  static const uint8_t kSig[8] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
  return b.size() >= 33 && std::equal(kSig, kSig + 8, b.begin()) && b[12] == 'I' && b[13] == 'H' &&
         b[14] == 'D' && b[15] == 'R';
}
uint32_t BigEndian32(const uint8_t* p) {
  return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | p[3];
}

}  // namespace

StatusOr<Raster> LoadRaster(const std::string& path) {
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, ReadFileBytes(path));
  if (bytes.empty()) return Status(StatusCode::kEmptyInput, path + ": the file is empty");
  bool grey_alpha = false;
  if (IsPng(bytes)) {
    // Size limit before decoding; PNG colour type 4 = grey + alpha (OpenCV expands it to BGRA).
    const uint64_t w = BigEndian32(&bytes[16]), h = BigEndian32(&bytes[20]);
    if (w == 0 || h == 0) return Status(StatusCode::kEmptyInput, path + ": PNG header says " + std::to_string(w) + "x" + std::to_string(h));
    if (w * h > kMaxPixels)
      return Status(StatusCode::kLimitExceeded, path + ": " + std::to_string(w) + "x" + std::to_string(h) +
                                                    " pixels is over the limit of 2^28");
    grey_alpha = bytes[25] == 4;
  }
  cv::Mat mat;
  try {
    mat = cv::imdecode(cv::Mat(1, int(bytes.size()), CV_8U, bytes.data()), cv::IMREAD_UNCHANGED);
  } catch (const std::exception& e) {
    return Status(StatusCode::kDecodeFailed, path + ": cannot decode the image: " + e.what());
  }
  if (mat.empty())
    return Status(StatusCode::kDecodeFailed, path + ": not an image OpenCV can decode (PNG, JPEG, TIFF, BMP expected)");
  if (uint64_t(mat.cols) * uint64_t(mat.rows) > kMaxPixels)
    return Status(StatusCode::kLimitExceeded, path + ": " + std::to_string(mat.cols) + "x" + std::to_string(mat.rows) +
                                                  " pixels is over the limit of 2^28");
  double colour_scale = 1, alpha_scale = 1.0 / 255;
  switch (mat.depth()) {
    case CV_8U: break;
    case CV_16U: colour_scale = 255.0 / 65535.0, alpha_scale = 1.0 / 65535; break;
    default:
      return Status(StatusCode::kUnsupportedFormat, path + ": sample type " + std::to_string(mat.depth()) +
                                                        " (OpenCV depth) is not 8- or 16-bit unsigned");
  }
  const int in_ch = mat.channels();
  if (in_ch < 1 || in_ch > 4)
    return Status(StatusCode::kUnsupportedFormat, path + ": " + std::to_string(in_ch) + " channels");
  const int out_ch = grey_alpha && in_ch == 4 ? 2 : in_ch;
  Raster out(mat.cols, mat.rows, out_ch);
  auto convert = [&](auto sample_type) {
    using T = decltype(sample_type);
    for (int y = 0; y < mat.rows; ++y) {
      const T* row = mat.ptr<T>(y);
      for (int x = 0; x < mat.cols; ++x) {
        const T* s = row + size_t(x) * in_ch;
        float* d = &out.data[(size_t(y) * out.width + x) * out_ch];
        switch (in_ch) {
          case 1: d[0] = float(s[0] * colour_scale); break;
          case 2: d[0] = float(s[0] * colour_scale), d[1] = float(s[1] * alpha_scale); break;
          case 3:
            d[0] = float(s[2] * colour_scale), d[1] = float(s[1] * colour_scale), d[2] = float(s[0] * colour_scale);
            break;
          default:
            if (out_ch == 2) {
              d[0] = float(s[1] * colour_scale), d[1] = float(s[3] * alpha_scale);
            } else {
              d[0] = float(s[2] * colour_scale), d[1] = float(s[1] * colour_scale), d[2] = float(s[0] * colour_scale);
              d[3] = float(s[3] * alpha_scale);
            }
        }
      }
    }
  };
  if (mat.depth() == CV_8U)
    convert(uint8_t{});
  else
    convert(uint16_t{});
  return out;
}

Status SaveRasterPng(const std::string& path, const Raster& raster, int bits) {
  if (bits != 8 && bits != 16)
    return Status(StatusCode::kInvalidArgument, path + ": PNG bit depth " + std::to_string(bits) + " (8 or 16 expected)");
  if (raster.empty()) return Status(StatusCode::kEmptyInput, path + ": the raster to write is empty");
  if (raster.channels < 1 || raster.channels > 4 ||
      raster.data.size() != size_t(raster.width) * raster.height * raster.channels)
    return Status(StatusCode::kInvalidArgument, path + ": raster has " + std::to_string(raster.channels) +
                                                    " channels and " + std::to_string(raster.data.size()) + " samples");
  const int in_ch = raster.channels;
  const int out_ch = in_ch == 2 ? 4 : in_ch;  // PNG grey+alpha is written as RGBA
  const double max = bits == 8 ? 255.0 : 65535.0;
  auto quantise = [max](double v, double unit) {
    if (!(v == v)) return 0.0;  // NaN
    return std::round(std::clamp(v * unit, 0.0, max));
  };
  cv::Mat mat(raster.height, raster.width, CV_MAKETYPE(bits == 8 ? CV_8U : CV_16U, out_ch));
  const double cu = max / 255.0, au = max;
  for (int y = 0; y < raster.height; ++y) {
    for (int x = 0; x < raster.width; ++x) {
      const float* s = &raster.data[(size_t(y) * raster.width + x) * in_ch];
      double px[4];
      switch (in_ch) {
        case 1: px[0] = quantise(s[0], cu); break;
        case 2: px[0] = px[1] = px[2] = quantise(s[0], cu), px[3] = quantise(s[1], au); break;
        case 3: px[0] = quantise(s[2], cu), px[1] = quantise(s[1], cu), px[2] = quantise(s[0], cu); break;
        default:
          px[0] = quantise(s[2], cu), px[1] = quantise(s[1], cu), px[2] = quantise(s[0], cu), px[3] = quantise(s[3], au);
      }
      for (int c = 0; c < out_ch; ++c) {
        if (bits == 8)
          mat.ptr<uint8_t>(y)[size_t(x) * out_ch + c] = uint8_t(px[c]);
        else
          mat.ptr<uint16_t>(y)[size_t(x) * out_ch + c] = uint16_t(px[c]);
      }
    }
  }
  std::vector<uint8_t> encoded;
  try {
    if (!cv::imencode(".png", mat, encoded))
      return Status(StatusCode::kEncodeFailed, path + ": OpenCV could not encode the PNG");
  } catch (const std::exception& e) {
    return Status(StatusCode::kEncodeFailed, path + ": PNG encoding failed: " + e.what());
  }
  return WriteFileAtomic(path, encoded);
}

}  // namespace sdvi
