// SPDX-License-Identifier: GPL-3.0-or-later
// The library quick start: load an image, vectorize it, write the .sdvi, read it back and
// render it twice as large.   usage: quickstart IN.png OUT.sdvi OUT_x2.png
#include <cstdio>

#include <sdvi/codec.h>
#include <sdvi/raster_io.h>
#include <sdvi/render.h>
#include <sdvi/vectorize.h>
#include <sdvi/version.h>

int main(int argc, char** argv) {
  if (argc != 4) return std::fprintf(stderr, "usage: quickstart IN.png OUT.sdvi OUT_x2.png\n"), 2;
  sdvi::StatusOr<sdvi::Raster> raster = sdvi::LoadRaster(argv[1]);
  if (!raster.ok()) return std::fprintf(stderr, "%s\n", raster.status().ToString().c_str()), 1;
  sdvi::StatusOr<sdvi::VectorizeResult> result = sdvi::Vectorize(*raster, nullptr, sdvi::VectorizeOptions{});
  if (!result.ok()) return std::fprintf(stderr, "%s\n", result.status().ToString().c_str()), 1;
  if (sdvi::Status s = sdvi::WriteImage(argv[2], result->image, nullptr); !s.ok())
    return std::fprintf(stderr, "%s\n", s.ToString().c_str()), 1;
  sdvi::StatusOr<sdvi::Image> image = sdvi::ReadImage(argv[2]);
  if (!image.ok()) return std::fprintf(stderr, "%s\n", image.status().ToString().c_str()), 1;
  sdvi::RenderOptions options;
  options.viewport.width = 2 * int(image->width), options.viewport.height = 2 * int(image->height);
  options.viewport.scale_x = options.viewport.scale_y = 2.0;
  sdvi::StatusOr<sdvi::Raster> x2 = sdvi::Render(*image, options);
  if (!x2.ok()) return std::fprintf(stderr, "%s\n", x2.status().ToString().c_str()), 1;
  if (sdvi::Status s = sdvi::SaveRasterPng(argv[3], *x2); !s.ok())
    return std::fprintf(stderr, "%s\n", s.ToString().c_str()), 1;
  std::printf("sdvi %s: %zu vertices, PSNR %.2f dB\n", SDVI_VERSION_STRING, image->vertices.size(),
              result->report.psnr);
  return 0;
}
