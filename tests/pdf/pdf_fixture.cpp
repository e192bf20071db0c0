// SPDX-License-Identifier: GPL-3.0-or-later
// Helper for the PDF script tests (viewer_test.sh, check_test.sh) and scripts/pdf_report.sh:
//   sdvi_pdf_fixture sdvi gradient|annulus W H OUT.sdvi
//       writes a test image built in code (pdf_test_images.h)
//   sdvi_pdf_fixture pdf IN.sdvi OUT.pdf [LEVELS]
//       sdvi::WritePdf with default options (or the given level)
//   sdvi_pdf_fixture compare VIEWER.png OURS.png [MIN_PSNR]
//       a viewer's render of the PDF against `sdvi render` of the same .sdvi, same size.
//       Prints one JSON line:
//         psnr            dB over R, G, B where both are opaque (alpha >= 0.99; a viewer
//                         PNG without alpha counts as opaque everywhere)
//         pixels          the pixels that PSNR covers
//         edge_mismatch   pixels within one pixel of the domain's edge whose alphas differ
//                         by more than 0.5 (viewers place the edge within a pixel their
//                         own way: MuPDF samples the mesh half a pixel off poppler)
//         far_mismatch    the same away from the edge: `sdvi render` has one alpha, 0 or
//                         1, over the pixel's whole 3x3 neighbourhood
//         outside_alpha   the largest viewer alpha where `sdvi render` has alpha 0 over
//                         the 3x3 neighbourhood (null for a viewer PNG without alpha)
//       With MIN_PSNR: exit 1 below it, or when far_mismatch > 0 or outside_alpha > 0.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "pdf_test_images.h"
#include "sdvi/codec.h"
#include "sdvi/format.h"
#include "sdvi/pdf.h"
#include "sdvi/raster.h"
#include "sdvi/raster_io.h"

namespace {

constexpr float kOpaque = 0.99f;

int Usage() {
  std::fprintf(stderr,
               "usage: sdvi_pdf_fixture sdvi gradient|annulus W H OUT.sdvi\n"
               "       sdvi_pdf_fixture pdf IN.sdvi OUT.pdf [LEVELS]\n"
               "       sdvi_pdf_fixture compare VIEWER.png OURS.png [MIN_PSNR]\n");
  return 2;
}

float Alpha(const sdvi::Raster& r, int x, int y) { return r.has_alpha() ? r.at(x, y, r.channels - 1) : 1.0f; }

float Channel(const sdvi::Raster& r, int x, int y, int c) {
  return r.channels >= 3 ? r.at(x, y, c) : r.at(x, y, 0);
}

int Compare(const std::string& viewer_path, const std::string& ours_path, bool gate, double min_psnr) {
  auto viewer = sdvi::LoadRaster(viewer_path);
  auto ours = sdvi::LoadRaster(ours_path);
  for (const auto* r : {&viewer, &ours}) {
    if (!r->ok()) {
      std::fprintf(stderr, "compare: %s\n", r->status().ToString().c_str());
      return 2;
    }
  }
  if (viewer->width != ours->width || viewer->height != ours->height) {
    std::fprintf(stderr, "compare: %s is %dx%d, %s is %dx%d\n", viewer_path.c_str(), viewer->width,
                 viewer->height, ours_path.c_str(), ours->width, ours->height);
    return 2;
  }
  const int w = ours->width, h = ours->height;
  double sse = 0;
  uint64_t pixels = 0, edge_mismatch = 0, far_mismatch = 0;
  float outside_alpha = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float av = Alpha(*viewer, x, y), ao = Alpha(*ours, x, y);
      if (av >= kOpaque && ao >= kOpaque) {
        for (int c = 0; c < 3; ++c) {
          const double d = double(Channel(*viewer, x, y, c)) - std::clamp(Channel(*ours, x, y, c), 0.0f, 255.0f);
          sse += d * d;
        }
        ++pixels;
      }
      if (!viewer->has_alpha()) continue;
      bool uniform = ao == 0.0f || ao == 1.0f;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = std::clamp(x + dx, 0, w - 1), yy = std::clamp(y + dy, 0, h - 1);
          uniform = uniform && Alpha(*ours, xx, yy) == ao;
        }
      }
      const bool mismatch = std::abs(av - ao) > 0.5f;
      (uniform ? far_mismatch : edge_mismatch) += mismatch;
      if (uniform && ao == 0.0f) outside_alpha = std::max(outside_alpha, av);
    }
  }
  const double mse = pixels > 0 ? sse / (3.0 * double(pixels)) : 0;
  const double psnr = mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : 99.0;
  auto or_null = [&viewer](const std::string& text) { return viewer->has_alpha() ? text : std::string("null"); };
  std::printf("{\"psnr\": %.3f, \"pixels\": %llu, \"edge_mismatch\": %s, \"far_mismatch\": %s, "
              "\"outside_alpha\": %s}\n",
              psnr, (unsigned long long)pixels, or_null(std::to_string(edge_mismatch)).c_str(),
              or_null(std::to_string(far_mismatch)).c_str(), or_null(std::to_string(outside_alpha)).c_str());
  if (!gate) return 0;
  int status = 0;
  if (pixels == 0 || psnr < min_psnr) {
    std::fprintf(stderr, "compare: PSNR %.2f dB over %llu pixels is below %.2f dB\n", psnr,
                 (unsigned long long)pixels, min_psnr);
    status = 1;
  }
  if (far_mismatch > 0) {
    std::fprintf(stderr, "compare: %llu pixels away from the domain's edge differ in alpha by > 0.5\n",
                 (unsigned long long)far_mismatch);
    status = 1;
  }
  if (outside_alpha > 0) {
    std::fprintf(stderr, "compare: the viewer paints alpha %.3f outside the domain\n", outside_alpha);
    status = 1;
  }
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty()) return Usage();
  if (args[0] == "compare" && (args.size() == 3 || args.size() == 4)) {
    return Compare(args[1], args[2], args.size() == 4, args.size() == 4 ? std::atof(args[3].c_str()) : 0);
  }
  if (args[0] == "pdf" && (args.size() == 3 || args.size() == 4)) {
    auto image = sdvi::ReadImage(args[1]);
    if (!image.ok()) {
      std::fprintf(stderr, "%s\n", image.status().ToString().c_str());
      return 2;
    }
    sdvi::PdfExportOptions options;
    if (args.size() == 4) options.levels = std::atoi(args[3].c_str());
    auto written = sdvi::WritePdf(args[2], *image, options);
    if (!written.ok()) {
      std::fprintf(stderr, "%s: %s\n", args[2].c_str(), written.status().ToString().c_str());
      return 2;
    }
    std::printf("%s: level %d, %u triangles, %u records, %zu bytes\n", args[2].c_str(),
                written->levels, written->triangles, written->records, written->bytes.size());
    return 0;
  }
  if (args[0] != "sdvi" || args.size() != 5) return Usage();
  const int w = std::atoi(args[2].c_str()), h = std::atoi(args[3].c_str());
  if (w <= 0 || h <= 0) return Usage();
  sdvi::Image image;
  if (args[1] == "gradient") {
    image = sdvi::pdf_test::Gradient(uint32_t(w), uint32_t(h));
  } else if (args[1] == "annulus") {
    image = sdvi::pdf_test::Annulus(uint32_t(w), uint32_t(h));
  } else {
    return Usage();
  }
  const sdvi::Status status = sdvi::WriteSdvi(args[4], image);
  if (!status.ok()) {
    std::fprintf(stderr, "%s: %s\n", args[4].c_str(), status.ToString().c_str());
    return 2;
  }
  return 0;
}
