// Public contract of the renderer and metrics (DESIGN.md sections 4 and 9), used by the
// colour fit, the CLI and the exporters. The render module owns the implementation and
// may add declarations; the names below are what other modules rely on.
#pragma once

#include <cstdint>
#include <vector>

#include "sdvi/image.h"
#include "sdvi/raster.h"
#include "sdvi/status.h"
#include "sdvi/subdiv.h"

namespace sdvi {

// Maps output pixels to source coordinates: the centre of output pixel (i, j) is the
// source point (origin_x + (i + 0.5) / scale_x, origin_y + (j + 0.5) / scale_y).
struct Viewport {
  int width = 0, height = 0;          // output size in pixels
  double scale_x = 1, scale_y = 1;    // output pixels per source pixel
  double origin_x = 0, origin_y = 0;  // source point at the output's top-left corner
  static Viewport Identity(int w, int h) { return {w, h, 1, 1, 0, 0}; }
};

// A pixel centre inside a fine triangle, with its barycentric weights (w0+w1+w2 = 1) for
// the triangle's vertices v[0], v[1], v[2].
struct PixelSample {
  uint32_t pixel = 0;     // j * width + i
  uint32_t triangle = 0;  // fine triangle index
  float w0 = 0, w1 = 0, w2 = 0;
};

// The pixel -> fine triangle map shared by rendering and fitting: at most one sample per
// pixel (one fill rule for shared edges, one deterministic rule for folded triangles),
// sorted by pixel.
struct CoverageMap {
  int width = 0, height = 0;
  std::vector<PixelSample> samples;
};

// Scan-converts fine triangles whose vertex positions are fine[i].x/.y (source pixels).
CoverageMap MapPixels(const std::vector<Triangle>& triangles, const std::vector<Vertex>& fine,
                      const Viewport& viewport);

struct RenderOptions {
  Viewport viewport;   // output size and mapping
  int levels = -1;     // subdivision level; -1 = chosen from the scale (~1 output px)
};

// Renders image to an RGBA raster (colours 0..255 sRGB, alpha 0..1 coverage of the domain).
StatusOr<Raster> Render(const Image& image, const RenderOptions& options);

// Metrics of DESIGN.md section 9 between a reconstruction and a reference of equal size,
// over the pixels where the reference's alpha (if any) and the reconstruction's alpha are
// > 0.5. Grey images count as R = G = B.
struct ImageMetrics {
  double psnr = 0;        // dB over R, G, B in 8-bit units
  double mssim = 0;       // Wang et al. 2004, Gaussian 11x11 sigma 1.5, mean over R, G, B
  double mean_error = 0;  // mean absolute difference, 8-bit units, over R, G, B
  double mse = 0;
  uint64_t pixels = 0;    // domain pixels compared
};
StatusOr<ImageMetrics> CompareImages(const Raster& reconstruction, const Raster& reference);

}  // namespace sdvi
