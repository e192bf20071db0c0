// SPDX-License-Identifier: GPL-3.0-or-later
// Render: subdivide the control mesh to a level chosen from the output scale, push the
// fine vertices to the limit surface and scan-convert them (spec/METHOD.md section 4).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "sdvi/parallel.h"
#include "sdvi/render.h"
#include "sdvi/progress.h"
#include "sdvi/subdiv.h"

namespace sdvi {
namespace {

constexpr int kMaxOutputSide = 1 << 16;
constexpr int64_t kMaxOutputPixels = int64_t(1) << 27;
constexpr double kMaxFineTriangles = double(1 << 25);  // LimitSurfaceOptions default
constexpr double kRegionMarginPx = 2.0;  // > the half pixel the domain-edge coverage reaches

Status CheckViewport(const Viewport& vp) {
  if (vp.width <= 0 || vp.height <= 0)
    return Status(StatusCode::kInvalidArgument, "render: output size " + std::to_string(vp.width) + "x" +
                                                    std::to_string(vp.height) + " is empty");
  if (vp.width > kMaxOutputSide || vp.height > kMaxOutputSide ||
      int64_t(vp.width) * vp.height > kMaxOutputPixels)
    return Status(StatusCode::kLimitExceeded, "render: output size " + std::to_string(vp.width) + "x" +
                                                  std::to_string(vp.height) + " exceeds the limit (" +
                                                  std::to_string(kMaxOutputSide) + " a side, 2^27 pixels)");
  if (!std::isfinite(vp.scale_x) || !std::isfinite(vp.scale_y) || vp.scale_x <= 0 || vp.scale_y <= 0 ||
      !std::isfinite(vp.origin_x) || !std::isfinite(vp.origin_y))
    return Status(StatusCode::kInvalidArgument, "render: viewport scale must be finite and > 0, origin finite");
  return Status::Ok();
}

}  // namespace

namespace {

// The level from the scale alone (see RenderOptions).
int LevelForScale(const Image& image, const RenderOptions& options) {
  double sum = 0;
  size_t count = 0;
  const size_t nv = image.vertices.size();
  for (const Triangle& t : image.triangles) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = t.v[k], b = t.v[(k + 1) % 3];
      if (a >= nv || b >= nv) continue;
      const double dx = double(image.vertices[a].x) - image.vertices[b].x;
      const double dy = double(image.vertices[a].y) - image.vertices[b].y;
      const double len = std::sqrt(dx * dx + dy * dy);
      if (std::isfinite(len)) sum += len, ++count;
    }
  }
  const int lo = std::max(0, options.min_levels);
  const int hi = std::min(kMaxLevels, std::max(lo, options.max_levels));
  if (count == 0 || !(options.max_fine_edge_px > 0)) return lo;
  const double scale = std::max(options.viewport.scale_x, options.viewport.scale_y);
  double edge = sum / double(count) * scale;  // mean control edge, output pixels
  int r = 0;
  while (r < hi && edge > options.max_fine_edge_px) edge *= 0.5, ++r;
  return std::clamp(r, std::min(lo, hi), hi);
}

// The automatic level, lowered until the region refines to at most kMaxFineTriangles.
int LevelWithinBudget(int level, size_t region_triangles) {
  while (level > 0 && double(region_triangles) * std::pow(4.0, level) > kMaxFineTriangles) --level;
  return level;
}

}  // namespace

int ChooseRenderLevels(const Image& image, const RenderOptions& options) {
  if (options.levels >= 0) return options.levels;
  return LevelWithinBudget(LevelForScale(image, options),
                           ControlTrianglesInViewport(image, options.viewport, kRegionMarginPx).size());
}

std::vector<uint32_t> ControlTrianglesInViewport(const Image& image, const Viewport& vp, double margin_px) {
  const size_t nv = image.vertices.size();
  struct Box {
    float x0 = 1e30f, y0 = 1e30f, x1 = -1e30f, y1 = -1e30f;
  };
  std::vector<Box> ring(nv);  // bounding box of each vertex's one-ring
  for (const Triangle& t : image.triangles) {
    if (t.v[0] >= nv || t.v[1] >= nv || t.v[2] >= nv) continue;
    for (int k = 0; k < 3; ++k) {
      Box& b = ring[t.v[k]];
      for (int m = 0; m < 3; ++m) {
        const Vertex& q = image.vertices[t.v[m]];
        b.x0 = std::min(b.x0, q.x), b.x1 = std::max(b.x1, q.x);
        b.y0 = std::min(b.y0, q.y), b.y1 = std::max(b.y1, q.y);
      }
    }
  }
  const double x0 = vp.origin_x - margin_px / vp.scale_x, x1 = vp.origin_x + (vp.width + margin_px) / vp.scale_x;
  const double y0 = vp.origin_y - margin_px / vp.scale_y, y1 = vp.origin_y + (vp.height + margin_px) / vp.scale_y;
  std::vector<uint32_t> out;
  for (uint32_t i = 0; i < image.triangles.size(); ++i) {
    const Triangle& t = image.triangles[i];
    if (t.v[0] >= nv || t.v[1] >= nv || t.v[2] >= nv) continue;
    Box b;
    for (int k = 0; k < 3; ++k) {
      const Box& r = ring[t.v[k]];
      b.x0 = std::min(b.x0, r.x0), b.x1 = std::max(b.x1, r.x1);
      b.y0 = std::min(b.y0, r.y0), b.y1 = std::max(b.y1, r.y1);
    }
    if (b.x1 >= x0 && b.x0 <= x1 && b.y1 >= y0 && b.y0 <= y1) out.push_back(i);
  }
  return out;
}

namespace {

// What Render scan-converts: the fine mesh of the limit surface over the viewport's region
// (none when no control triangle reaches the viewport) and its domain edge.
struct ViewportSurface {
  bool empty = true;
  RefinedMesh surface;
  std::vector<Edge> boundary;
};

StatusOr<ViewportSurface> SurfaceForViewport(const Image& image, const RenderOptions& options) {
  const Viewport& vp = options.viewport;
  SDVI_RETURN_IF_ERROR(CheckViewport(vp));
  if (image.vertices.empty() || image.triangles.empty())
    return Status(StatusCode::kEmptyInput, "render: the image has " + std::to_string(image.vertices.size()) +
                                               " vertices and " + std::to_string(image.triangles.size()) +
                                               " triangles; nothing to render");
  for (size_t i = 0; i < image.vertices.size(); ++i) {
    const Vertex& v = image.vertices[i];
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.r) || !std::isfinite(v.g) ||
        !std::isfinite(v.b))
      return Status(StatusCode::kNonFinite, "render: control vertex " + std::to_string(i) + " is not finite");
  }
  if (options.levels > kMaxLevels)
    return Status(StatusCode::kInvalidArgument, "render: --levels " + std::to_string(options.levels) +
                                                    " is above the maximum " + std::to_string(kMaxLevels));
  ViewportSurface out;
  std::vector<uint32_t> region = ControlTrianglesInViewport(image, vp, kRegionMarginPx);
  if (region.empty()) return out;  // nothing reaches the viewport
  const int levels =
      options.levels >= 0 ? options.levels : LevelWithinBudget(LevelForScale(image, options), region.size());
  const double fine_estimate = double(region.size()) * std::pow(4.0, levels);
  if (fine_estimate > kMaxFineTriangles)
    return Status(StatusCode::kLimitExceeded,
                  "render: level " + std::to_string(levels) + " gives ~" + std::to_string(int64_t(fine_estimate)) +
                      " fine triangles (limit 2^25); lower --levels or render a smaller region");
  LimitSurfaceOptions lso;
  lso.levels = levels;
  lso.to_limit = true;
  lso.max_fine_triangles = uint64_t(kMaxFineTriangles);
  lso.threads = options.threads;
  if (region.size() < image.triangles.size()) lso.control_triangles = std::move(region);

  // One evaluation of this topology: direct refinement is cheaper than building stencils.
  if (options.progress) options.progress->Phase("subdivide (level " + std::to_string(levels) + ")");
  SDVI_ASSIGN_OR_RETURN(out.surface, RefineImage(image, lso));
  for (const Vertex& v : out.surface.vertices) {
    const double ox = (double(v.x) - vp.origin_x) * vp.scale_x, oy = (double(v.y) - vp.origin_y) * vp.scale_y;
    if (!(std::abs(ox) <= kMaxOutputCoord && std::abs(oy) <= kMaxOutputCoord))
      return Status(StatusCode::kLimitExceeded,
                    "render: a surface point maps to output pixel (" + std::to_string(ox) + ", " + std::to_string(oy) +
                        "), beyond the exact range of +-2^21; render a smaller scale or region");
  }
  if (options.progress)
    options.progress->Phase("scan conversion (" + std::to_string(out.surface.triangles.size()) + " triangles)");
  if (options.antialias) out.boundary = MeshBoundaryEdges(out.surface.triangles, &out.surface.vertex_tags);
  out.empty = false;
  return out;
}

}  // namespace

StatusOr<Raster> Render(const Image& image, const RenderOptions& options) {
  SDVI_ASSIGN_OR_RETURN(ViewportSurface s, SurfaceForViewport(image, options));
  const Viewport& vp = options.viewport;
  if (s.empty) return Raster(vp.width, vp.height, 4);
  Raster out = RenderFineMesh(s.surface.triangles, s.surface.vertices, vp, options.antialias ? &s.boundary : nullptr,
                              options.threads);
  if (options.progress) options.progress->Done();
  return out;
}

StatusOr<Raster8> Render8(const Image& image, const RenderOptions& options) {
  const Viewport& vp = options.viewport;
  // A large output's pages mapped beside the refinement, which leaves a core mostly idle
  // (spec/METHOD.md section 4, item 5), unless one thread is asked for; joined before any
  // return (declared after out). A smaller output is not worth a thread.
  constexpr int64_t kPrepareBytes = int64_t(4) << 20;
  Raster8 out;
  BackgroundTask prepare;
  if (options.threads != 1 && CheckViewport(vp).ok() && int64_t(vp.width) * vp.height * 4 >= kPrepareBytes)
    prepare.Start([&out, &vp] { PrepareRaster8(vp, out); });
  SDVI_ASSIGN_OR_RETURN(ViewportSurface s, SurfaceForViewport(image, options));
  prepare.Wait();
  if (s.empty) return Raster8(vp.width, vp.height, 4);
  RenderFineMesh8Into(s.surface.triangles, s.surface.vertices, vp, options.antialias ? &s.boundary : nullptr,
                      options.threads, out);
  if (options.progress) options.progress->Done();
  return out;
}

}  // namespace sdvi
