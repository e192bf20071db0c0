// SPDX-License-Identifier: GPL-3.0-or-later
// bench_raster_io [DATA_DIR] (default ../shared/data): why sdvi_raster_io reads images with
// OpenImageIO (and PNGs with libpng) rather than OpenCV imgcodecs (spec/RASTER_INPUT.md).
//   Table 1, per image of DATA_DIR/photos, graphics and large: load time (best of 3, from
//   memory, into the float sdvi::Raster) of cv::imdecode(IMREAD_UNCHANGED) plus the
//   conversion sdvi did before, and of sdvi::DecodeRaster (libpng for PNGs, OpenImageIO for
//   the rest, plus conversion, orientation and colour management), the ratio, and the largest sample difference
//   between the two (0: the same decoder underneath; ICC-tagged files differ by design).
//   Table 2, what each reads of inputs written here with OpenImageIO: an EXIF orientation
//   6 JPEG (upright?), a GIF, an OpenEXR and a Radiance HDR file, an ICC profile.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "sdvi/file_util.h"
#include "sdvi/raster_io.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

template <typename F>
double BestOf3(F&& f) {
  double best = 1e30;
  for (int i = 0; i < 3; ++i) {
    const auto start = Clock::now();
    f();
    best = std::min(best, std::chrono::duration<double, std::milli>(Clock::now() - start).count());
  }
  return best;
}

// OpenCV's BGR(A) 8- or 16-bit samples as a float raster (the conversion sdvi used to do).
sdvi::Raster FromMat(const cv::Mat& m) {
  sdvi::Raster r(m.cols, m.rows, m.channels());
  const bool wide = m.depth() == CV_16U;
  const double colour = wide ? 255.0 / 65535.0 : 1.0, alpha = wide ? 1.0 / 65535 : 1.0 / 255;
  const int ch = m.channels();
  for (int y = 0; y < m.rows; ++y)
    for (int x = 0; x < m.cols; ++x)
      for (int c = 0; c < ch; ++c) {
        const int src = ch >= 3 && c < 3 ? 2 - c : c;
        const double v = wide ? m.ptr<uint16_t>(y)[x * ch + src] : m.ptr<uint8_t>(y)[x * ch + src];
        const bool is_alpha = (ch == 2 || ch == 4) && c == ch - 1;
        r.at(x, y, c) = float(v * (is_alpha ? alpha : colour));
      }
  return r;
}

// Largest |OpenCV sample - sdvi sample| on the 8-bit scale (OpenCV's BGR(A) reordered);
// -1 when the shapes differ.
double MaxDifference(const cv::Mat& m, const sdvi::Raster& r) {
  if (m.cols != r.width || m.rows != r.height || m.channels() != r.channels) return -1;
  const double scale = m.depth() == CV_16U ? 255.0 / 65535.0 : 1.0;
  double worst = 0;
  for (int y = 0; y < m.rows; ++y)
    for (int x = 0; x < m.cols; ++x)
      for (int c = 0; c < r.channels; ++c) {
        const int src = r.channels >= 3 && c < 3 ? 2 - c : c;
        const double v = m.depth() == CV_16U ? m.ptr<uint16_t>(y)[x * r.channels + src] : m.ptr<uint8_t>(y)[x * r.channels + src];
        const bool alpha = r.has_alpha() && c == r.channels - 1;
        worst = std::max(worst, std::abs(v * scale - r.at(x, y, c) * (alpha ? 255.0 : 1.0)));
      }
  return worst;
}

// Writes a small image with OpenImageIO to bytes (format from name), with extra attributes.
std::vector<uint8_t> Write(const std::string& name, int channels, OIIO::TypeDesc type,
                           const std::vector<std::pair<std::string, int>>& ints = {}) {
  OIIO::ImageSpec spec(16, 8, channels, type);
  for (const auto& [key, value] : ints) spec.attribute(key, value);
  std::vector<float> pixels(size_t(16) * 8 * channels);
  for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = float(i % 7) / 7.0f;
  std::vector<uint8_t> bytes;
  OIIO::Filesystem::IOVecOutput out(bytes);
  auto writer = OIIO::ImageOutput::create(name);
  writer->set_ioproxy(&out);
  if (!writer->open(name, spec) || !writer->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) || !writer->close())
    std::fprintf(stderr, "cannot write %s: %s\n", name.c_str(), writer->geterror().c_str());
  return bytes;
}

}  // namespace

int main(int argc, char** argv) {
  const fs::path dir = argc > 1 ? argv[1] : "../shared/data";
  std::vector<fs::path> files;
  for (const char* sub : {"photos", "graphics", "large"}) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir / sub, ec)) {
      const std::string ext = sdvi::FileExtension(e.path().string());
      if (ext == "png" || ext == "jpg" || ext == "jpeg") files.push_back(e.path());
    }
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) {
    std::fprintf(stderr, "bench_raster_io: no PNG/JPEG under %s/{photos,graphics,large}\n", dir.c_str());
    return 1;
  }
  std::printf("Table 1: load from memory into sdvi::Raster, best of 3 (ms)\n");
  std::printf("%-40s %11s %9s %9s %6s %9s\n", "image", "size", "opencv", "sdvi", "ratio", "max diff");
  double sum_cv = 0, sum_oiio = 0, worst = 0;
  for (const fs::path& path : files) {
    auto bytes = sdvi::ReadFileBytes(path.string());
    if (!bytes.ok()) continue;
    const cv::Mat encoded(1, int(bytes->size()), CV_8U, bytes->data());
    cv::Mat mat;
    sdvi::StatusOr<sdvi::Raster> raster = sdvi::Raster();
    sdvi::Raster from_cv;
    const double t_cv = BestOf3([&] {
      mat = cv::imdecode(encoded, cv::IMREAD_UNCHANGED);
      if (!mat.empty()) from_cv = FromMat(mat);
    });
    const double t_oiio = BestOf3([&] { raster = sdvi::DecodeRaster(*bytes, path.string()); });
    if (!raster.ok() || mat.empty()) {
      std::printf("%-40s decode failed\n", path.filename().c_str());
      continue;
    }
    const double diff = MaxDifference(mat, *raster);
    sum_cv += t_cv, sum_oiio += t_oiio, worst = std::max(worst, diff);
    std::printf("%-40s %5dx%-5d %9.2f %9.2f %6.2f %9.3f\n", path.filename().c_str(), raster->width,
                raster->height, t_cv, t_oiio, t_oiio / t_cv, diff);
  }
  std::printf("%-40s %11s %9.1f %9.1f %6.2f %9.3f\n\n", "total", "", sum_cv, sum_oiio, sum_oiio / sum_cv, worst);

  std::printf("Table 2: what each reads (inputs written here with OpenImageIO)\n");
  std::printf("%-34s %-26s %-26s\n", "input", "opencv IMREAD_UNCHANGED", "sdvi");
  struct Case {
    const char* label;
    std::vector<uint8_t> bytes;
    const char* name;
  };
  std::vector<Case> cases;
  cases.push_back({"JPEG 16x8, EXIF orientation 6", Write("a.jpg", 3, OIIO::TypeDesc::UINT8, {{"Orientation", 6}}), "a.jpg"});
  cases.push_back({"GIF 16x8", Write("a.gif", 4, OIIO::TypeDesc::UINT8), "a.gif"});
  cases.push_back({"OpenEXR 16x8 half RGBA", Write("a.exr", 4, OIIO::TypeDesc::HALF), "a.exr"});
  cases.push_back({"Radiance HDR 16x8", Write("a.hdr", 3, OIIO::TypeDesc::FLOAT), "a.hdr"});
  for (const Case& c : cases) {
    const cv::Mat m = cv::imdecode(cv::Mat(1, int(c.bytes.size()), CV_8U, const_cast<uint8_t*>(c.bytes.data())),
                                   cv::IMREAD_UNCHANGED);
    sdvi::RasterSource source;
    auto r = sdvi::DecodeRaster(c.bytes, c.name, &source);
    char a[64], b[64];
    if (m.empty())
      std::snprintf(a, sizeof a, "refused");
    else
      std::snprintf(a, sizeof a, "%dx%d, %d ch", m.cols, m.rows, m.channels());
    if (!r.ok())
      std::snprintf(b, sizeof b, "refused");
    else
      std::snprintf(b, sizeof b, "%dx%d, %d ch%s", r->width, r->height, r->channels, source.orientation != 1 ? ", rotated" : "");
    std::printf("%-34s %-26s %-26s\n", c.label, a, b);
  }
  std::printf("%-34s %-26s %-26s\n", "embedded ICC profile", "not exposed", "converted (Little CMS)");
  std::printf("%-34s %-26s %-26s\n", "PNG sRGB chunk on output", "no", "yes (sRGB, gAMA, cHRM)");
  return 0;
}
