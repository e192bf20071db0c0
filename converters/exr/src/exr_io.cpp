// SPDX-License-Identifier: GPL-3.0-or-later
// EXR files through OpenEXR (exr_io.h). OpenEXR exceptions stop here.
#include "sdvi/exr_io.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <half.h>

#include "sdvi/file_util.h"

namespace sdvi {
namespace {

constexpr uint64_t kMaxPixels = uint64_t(1) << 28;

bool ValidRaster(const Raster& r) {
  return r.channels >= 1 && r.channels <= 4 && r.data.size() == size_t(r.width) * r.height * r.channels;
}
inline double Colour(const Raster& r, size_t p, int c) { return r.data[p * r.channels + (r.channels >= 3 ? c : 0)]; }
inline double Alpha(const Raster& r, size_t p) { return r.has_alpha() ? r.data[p * r.channels + r.channels - 1] : 1.0; }

}  // namespace

double SrgbToLinear(double v255) {
  const double v = v255 / 255.0;
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

double LinearToSrgb(double linear) {
  const double v = linear <= 0.0031308 ? linear * 12.92 : 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
  return v * 255.0;
}

StatusOr<std::vector<float>> ErrorChannel(const Raster& render, const Raster& reference) {
  if (!ValidRaster(render) || !ValidRaster(reference) || render.empty())
    return Status(StatusCode::kInvalidArgument, "error channel: a raster is empty or malformed");
  if (render.width != reference.width || render.height != reference.height)
    return Status(StatusCode::kInvalidArgument,
                  "error channel: render " + std::to_string(render.width) + "x" + std::to_string(render.height) +
                      " and reference " + std::to_string(reference.width) + "x" + std::to_string(reference.height) +
                      " differ in size");
  const size_t n = size_t(render.width) * render.height;
  std::vector<float> out(n, 0.0f);
  for (size_t p = 0; p < n; ++p) {
    if (!(Alpha(render, p) > 0.5) || !(Alpha(reference, p) > 0.5)) continue;
    double s = 0;
    for (int c = 0; c < 3; ++c) s += std::abs(Colour(render, p, c) - Colour(reference, p, c));
    out[p] = float(s / 3);
  }
  return out;
}

Status SaveExr(const std::string& path, const Raster& raster, const ExrWriteOptions& options) {
  if (raster.empty()) return Status(StatusCode::kEmptyInput, path + ": the raster to write is empty");
  if (!ValidRaster(raster))
    return Status(StatusCode::kInvalidArgument, path + ": raster has " + std::to_string(raster.channels) +
                                                    " channels and " + std::to_string(raster.data.size()) + " samples");
  const size_t n = size_t(raster.width) * raster.height;
  if (options.display_width < 0 || options.display_height < 0 || std::abs(int64_t(options.data_x)) > (1 << 30) ||
      std::abs(int64_t(options.data_y)) > (1 << 30))
    return Status(StatusCode::kInvalidArgument, path + ": data window origin or display window out of range");
  if (options.error && options.error->size() != n)
    return Status(StatusCode::kInvalidArgument, path + ": error channel has " + std::to_string(options.error->size()) +
                                                    " values for " + std::to_string(n) + " pixels");
  // Linear, premultiplied RGBA, interleaved floats.
  std::vector<float> rgba(n * 4);
  for (size_t p = 0; p < n; ++p) {
    const double a = std::clamp(Alpha(raster, p), 0.0, 1.0);
    for (int c = 0; c < 3; ++c) {
      const double v = std::clamp(Colour(raster, p, c), 0.0, 255.0);
      rgba[p * 4 + c] = float(SrgbToLinear(v) * a);
    }
    rgba[p * 4 + 3] = float(a);
  }
  const Imf::PixelType type = options.half ? Imf::HALF : Imf::FLOAT;
  return WriteViaTempFile(path, [&](const std::string& temp) -> Status {
    try {
      const Imath::Box2i data_window(Imath::V2i(options.data_x, options.data_y),
                                     Imath::V2i(options.data_x + raster.width - 1, options.data_y + raster.height - 1));
      const Imath::Box2i display_window(
          Imath::V2i(0, 0), Imath::V2i((options.display_width > 0 ? options.display_width : raster.width) - 1,
                                       (options.display_height > 0 ? options.display_height : raster.height) - 1));
      Imf::Header header(display_window, data_window);
      header.compression() = Imf::ZIP_COMPRESSION;
      const char* names[4] = {"R", "G", "B", "A"};
      const int channels = raster.has_alpha() ? 4 : 3;
      for (int c = 0; c < channels; ++c) header.channels().insert(names[c], Imf::Channel(type));
      if (options.error) header.channels().insert("error", Imf::Channel(type));
      // OpenEXR does not convert on output: give it samples of the file's type.
      std::vector<half> rgba_half, error_half;
      if (options.half) {
        rgba_half.assign(rgba.begin(), rgba.end());
        if (options.error) error_half.assign(options.error->begin(), options.error->end());
      }
      const size_t bytes = options.half ? sizeof(half) : sizeof(float);
      char* rgba_base = options.half ? reinterpret_cast<char*>(rgba_half.data()) : reinterpret_cast<char*>(rgba.data());
      char* error_base = !options.error ? nullptr
                         : options.half ? reinterpret_cast<char*>(error_half.data())
                                        : reinterpret_cast<char*>(const_cast<float*>(options.error->data()));
      // Slices are addressed from the data window's origin.
      const int64_t origin = int64_t(options.data_x) + int64_t(options.data_y) * raster.width;
      rgba_base -= origin * int64_t(bytes * 4);
      if (error_base) error_base -= origin * int64_t(bytes);
      Imf::FrameBuffer fb;
      for (int c = 0; c < channels; ++c)
        fb.insert(names[c], Imf::Slice(type, rgba_base + bytes * c, bytes * 4, bytes * 4 * raster.width));
      if (options.error) fb.insert("error", Imf::Slice(type, error_base, bytes, bytes * raster.width));
      Imf::OutputFile file(temp.c_str(), header);  // destroyed (flushed) before the rename
      file.setFrameBuffer(fb);
      file.writePixels(raster.height);
    } catch (const std::exception& e) {
      return Status(StatusCode::kEncodeFailed, path + ": OpenEXR could not write the file: " + e.what());
    }
    return Status::Ok();
  });
}

StatusOr<ExrImage> LoadExr(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return Status(StatusCode::kNotFound, path + ": no such file");
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const int64_t w = int64_t(dw.max.x) - dw.min.x + 1, h = int64_t(dw.max.y) - dw.min.y + 1;
    if (w <= 0 || h <= 0) return Status(StatusCode::kEmptyInput, path + ": empty data window");
    if (uint64_t(w) * uint64_t(h) > kMaxPixels)
      return Status(StatusCode::kLimitExceeded, path + ": " + std::to_string(w) + "x" + std::to_string(h) +
                                                    " pixels is over the limit of 2^28");
    ExrImage out;
    out.rgba = Raster(int(w), int(h), 4);
    const Imath::Box2i display = file.header().displayWindow();
    out.data_x = dw.min.x - display.min.x, out.data_y = dw.min.y - display.min.y;
    out.display_width = display.max.x - display.min.x + 1, out.display_height = display.max.y - display.min.y + 1;
    out.has_alpha = file.header().channels().findChannel("A") != nullptr;
    const bool has_error = file.header().channels().findChannel("error") != nullptr;
    if (has_error) out.error.assign(size_t(w) * h, 0.0f);
    // Slices are addressed from the data window's origin.
    char* base = reinterpret_cast<char*>(out.rgba.data.data()) -
                 (int64_t(dw.min.x) + int64_t(dw.min.y) * w) * int64_t(sizeof(float) * 4);
    Imf::FrameBuffer fb;
    const char* names[4] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; ++c)
      fb.insert(names[c], Imf::Slice(Imf::FLOAT, base + sizeof(float) * c, sizeof(float) * 4,
                                     sizeof(float) * 4 * size_t(w), 1, 1, c == 3 ? 1.0 : 0.0));
    if (has_error) {
      char* ebase = reinterpret_cast<char*>(out.error.data()) -
                    (int64_t(dw.min.x) + int64_t(dw.min.y) * w) * int64_t(sizeof(float));
      fb.insert("error", Imf::Slice(Imf::FLOAT, ebase, sizeof(float), sizeof(float) * size_t(w)));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    return out;
  } catch (const std::exception& e) {
    return Status(StatusCode::kDecodeFailed, path + ": not a readable EXR file: " + e.what());
  }
}

}  // namespace sdvi
