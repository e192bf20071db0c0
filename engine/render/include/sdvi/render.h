// SPDX-License-Identifier: GPL-3.0-or-later
// Public contract of the renderer and metrics (spec/METHOD.md sections 4 and 9), used by the
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

class Progress;

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
// MapPixels into map, reusing the storage of map.samples (its contents are discarded): a
// caller that maps repeatedly (the vectorizer's rounds) writes into memory it already holds
// instead of fresh pages the kernel must zero. The same result as MapPixels.
void MapPixelsInto(const std::vector<Triangle>& triangles, const std::vector<Vertex>& fine,
                   const Viewport& viewport, CoverageMap& map);

// The pixel -> fine triangle map of MapPixels with one owner per pixel and no stored
// weights: 4 bytes a pixel instead of a PixelSample's 20, for the colour fit, which holds
// the map across the whole image (spec/METHOD.md 6, "Memory"). owner[j * width + i] is
// the fine triangle MapPixels gives pixel (i, j), kNoOwner where it gives none; a
// sample's weights are computed again from its triangle's fixed-point corners with the
// same exact edge functions, so they are MapPixels' bit for bit.
struct PixelOwners {
  static constexpr uint32_t kNoOwner = ~uint32_t(0);
  int width = 0, height = 0;
  std::vector<uint32_t> owner;   // width * height
  std::vector<int32_t> corners;  // x, y of each fine vertex in fixed point (kSubpixelBits
                                 // below); INT32_MIN where outside the exact range
};

// MapPixels' owners into map, reusing the storage of map.owner (its contents are discarded).
void MapPixelOwnersInto(const std::vector<Triangle>& triangles, const std::vector<Vertex>& fine,
                        const Viewport& viewport, PixelOwners& map);
// Appends to out the samples MapPixels gives fine triangle t (of the triangles map was made
// from), in pixel order.
void AppendOwnedSamples(const PixelOwners& map, const std::vector<Triangle>& triangles, uint32_t t,
                        std::vector<PixelSample>& out);
// Appends to out the samples MapPixels gives pixels [p0, p1), in pixel order.
void AppendSamplesInRange(const PixelOwners& map, const std::vector<Triangle>& triangles, size_t p0, size_t p1,
                          std::vector<PixelSample>& out);

struct RenderOptions {
  Viewport viewport;   // output size and mapping
  int levels = -1;     // subdivision level; -1 = chosen from the scale (~1 output px)
  // Level choice when levels = -1 (ChooseRenderLevels): the smallest r >= min_levels whose
  // fine edges (mean control edge length / 2^r, in output pixels) are <= max_fine_edge_px,
  // capped at max_levels and lowered until the refined region has at most 2^25 fine
  // triangles. Inside a fine triangle colour is interpolated linearly. The default of 16 px
  // (not 1): the piecewise-linear fine mesh converges so fast, and its error is so nearly
  // independent of the scale (the colour's error dominates; spec/METHOD.md section 4), that
  // level 3 is within 57-78 dB of level 5 at x8 and x16 alike, while level 4 costs 4-6x the
  // time of level 3. min_levels keeps the fit's level at scales <= 1; set
  // max_fine_edge_px = 1 for one-pixel fine triangles.
  double max_fine_edge_px = 16.0;
  int min_levels = 2;  // the colour fit's level (paper: r = 2); never render coarser
  int max_levels = 6;
  bool antialias = true;  // coverage anti-aliasing of the domain edge
  int threads = 0;        // worker threads for scan conversion; 0 = hardware concurrency
  Progress* progress = nullptr;  // optional terminal progress: phases "subdivide", "scan" (not owned)
};

// Renders image to an RGBA raster (colours 0..255 sRGB, alpha 0..1 coverage of the domain).
// Only control triangles whose surface can reach the viewport are refined (region
// rendering). Errors: kInvalidArgument (viewport), kEmptyInput, kNonFinite,
// kLimitExceeded (output too large, coordinates beyond the fixed-point range), and the
// topology errors of BuildLimitSurface.
StatusOr<Raster> Render(const Image& image, const RenderOptions& options);

// Renders image as Render does, straight into 8-bit RGBA (what an 8-bit PNG stores), without a
// float raster (spec/METHOD.md section 4, item 5): every byte equals the float render's value
// quantised by the PNG writer's rule, colours round(clamp(v, 0, 255)) and alpha
// round(255 clamp(a, 0, 1)), halves away from zero; the same bytes for any thread count.
// Errors: those of Render.
StatusOr<Raster8> Render8(const Image& image, const RenderOptions& options);

// ---- Building blocks (also used by tests, the colour fit and the benchmarks) ----

// Scan conversion works in output pixels with kSubpixelBits of fixed-point precision;
// vertices farther than kMaxOutputCoord output pixels from the viewport origin are
// outside the exact range (MapPixels skips their triangles, Render reports kLimitExceeded).
inline constexpr int kSubpixelBits = 8;
inline constexpr double kMaxOutputCoord = double(1 << 21);  // products fit in int64

// Fill rule (one for MapPixels and every render): a pixel belongs to a triangle when its
// centre is strictly inside, or exactly on a top or left edge (top-left rule), evaluated
// with exact integer edge functions on fixed-point vertices, so two triangles sharing an
// edge never both own, nor both miss, a pixel centre on it. Degenerate (zero-area after
// snapping) triangles own nothing. Folded triangles (the smoothing of positions can fold
// fine triangles over each other): the lowest fine triangle index wins. Since the fine
// triangles are ordered by parent control triangle, this is also "lowest parent wins".

// Renders fine triangles whose positions and colours are fine[i] directly: colour =
// barycentric interpolation of the vertices' (r, g, b), clamped to 0..255; alpha 1 where a
// pixel is owned, 0 elsewhere. When boundary is non-null, pixels within one output pixel of
// a boundary edge get alpha = clamp(0.5 + signed distance) (coverage of the domain edge),
// and uncovered ones there take the colour of the nearest boundary point.
Raster RenderFineMesh(const std::vector<Triangle>& triangles, const std::vector<Vertex>& fine,
                      const Viewport& viewport, const std::vector<Edge>* boundary = nullptr,
                      int threads = 0);

// RenderFineMesh straight into 8-bit RGBA, quantised as Render8 says.
Raster8 RenderFineMesh8(const std::vector<Triangle>& triangles, const std::vector<Vertex>& fine,
                        const Viewport& viewport, const std::vector<Edge>* boundary = nullptr,
                        int threads = 0);

// Storage for RenderFineMesh8Into at viewport's size (RGBA), its pages already mapped by the
// kernel (one byte a page written), its contents otherwise unspecified: Render8 prepares it
// on a thread of its own while the refinement runs (spec/METHOD.md section 4, item 5).
// An invalid viewport leaves out empty.
void PrepareRaster8(const Viewport& viewport, Raster8& out);

// RenderFineMesh8 into out, whose storage PrepareRaster8(viewport, out) made (every byte is
// written): the same bytes as RenderFineMesh8. Any other out is replaced by RenderFineMesh8's.
void RenderFineMesh8Into(const std::vector<Triangle>& triangles, const std::vector<Vertex>& fine,
                         const Viewport& viewport, const std::vector<Edge>* boundary, int threads,
                         Raster8& out);

// Edges used by exactly one triangle (the domain edge: outer boundary and holes), sorted.
// When tags is non-null, only edges whose two endpoints are not smooth are considered (a
// boundary edge is always crease), which makes this cheap on fine meshes.
std::vector<Edge> MeshBoundaryEdges(const std::vector<Triangle>& triangles,
                                    const std::vector<VertexTag>* tags = nullptr);

// The subdivision level Render uses for options.levels = -1 (see RenderOptions).
int ChooseRenderLevels(const Image& image, const RenderOptions& options);

// Control triangles whose limit surface can reach the viewport grown by margin_px output
// pixels: a triangle's limit patch lies in the convex hull of its vertices' one-rings, so
// the test uses that hull's bounding box. Sorted ascending.
std::vector<uint32_t> ControlTrianglesInViewport(const Image& image, const Viewport& viewport,
                                                 double margin_px);

// Metrics of spec/METHOD.md section 9 between a reconstruction and a reference of equal size,
// over the pixels where the reference's alpha (if any) and the reconstruction's alpha are
// > 0.5. Grey images count as R = G = B.
struct ImageMetrics {
  double psnr = 0;        // dB over R, G, B in 8-bit units
  double mssim = 0;       // Wang et al. 2004, Gaussian 11x11 sigma 1.5, mean over R, G, B
  double mean_error = 0;  // mean absolute difference, 8-bit units, over R, G, B
  double mse = 0;
  uint64_t pixels = 0;    // domain pixels compared
};
// MSSIM details: per colour channel, local means, variances (population) and covariance
// under a normalised 11x11 Gaussian window (sigma 1.5) restricted to the compared pixels
// (normalised convolution; identical to the plain window when every pixel counts), then
// SSIM averaged over the compared pixels at least 5 px from the image border (all compared
// pixels when the image is smaller than 11 px). C1 = (0.01 * 255)^2, C2 = (0.03 * 255)^2.
// psnr is +infinity when the images are equal. Errors: kInvalidArgument (sizes differ),
// kEmptyInput (empty image or no pixel in both domains).
// threads: rows of the MSSIM on that many threads (0: the hardware's); the result is the
// same for any number.
StatusOr<ImageMetrics> CompareImages(const Raster& reconstruction, const Raster& reference, int threads = 1);

// CompareImages of an 8-bit reconstruction (a Render8 output): colours 0..255, alpha a
// standing for a / 255 (compared where a > 127). The same metrics, bit for bit, as
// CompareImages of the float raster those bytes hold, without making it.
StatusOr<ImageMetrics> CompareImages(const Raster8& reconstruction, const Raster& reference, int threads = 1);

// CompareImages of an 8-bit reconstruction without the MSSIM (mssim is NaN): psnr, mse,
// mean_error and pixels, bit for bit those of CompareImages, at a fraction of its cost (one
// pass over the pixels). Rate control measures each candidate file this way.
StatusOr<ImageMetrics> ComparePixelErrors(const Raster8& reconstruction, const Raster& reference);

// Rounds colours to integers in 0..255 and alpha to multiples of 1/255, as an 8-bit PNG
// stores them: a render measured after this has the PSNR of its PNG (spec/RATE.md 1).
void RoundTo8Bit(Raster& raster);

}  // namespace sdvi
