// SPDX-License-Identifier: GPL-3.0-or-later
// bench_pdf IN.sdvi... [--levels r] [--svg]: for each file, the PDF export (type-4 strips, spec/PDF.md)
// against the size baseline of issue 12: cairo's PDF surface with a mesh pattern holding
// the same fine triangles (one Coons patch per triangle, which cairo writes as ShadingType 7),
// both measured in this run. Prints one table row per file:
//   level, fine triangles, records/triangle, sdvi PDF bytes, bytes/triangle, write ms,
//   cairo bytes, cairo ms, cairo / sdvi.
// --svg adds a second table, the flat-shaded SVG export's case (spec/SVG_EXPORT.md): SVG 1.1
// can only fill a triangle with one colour, so the best an SVG of the same fine triangles
// can show is the flat-shaded mesh (colour = mean of the three vertices) with no seams at
// all. That upper bound is rendered by sdvi's own rasteriser and compared with the
// Gouraud-shaded mesh at x1 and x4 (x4: the central 1024 x 1024 output pixels), and the
// bytes of `sdvi export-svg`'s document for it (EncodeSvg) are counted against the PDF's,
// at the PDF's level (export-svg's default is one coarser), one coarser and one finer.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <cairo-pdf.h>
#include <cairo.h>

#include "sdvi/codec.h"
#include "sdvi/file_util.h"
#include "sdvi/pdf.h"
#include "sdvi/svg_export.h"
#include "sdvi/render.h"
#include "sdvi/subdiv.h"

namespace {

double Millis(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

cairo_status_t CountBytes(void* closure, const unsigned char*, unsigned int length) {
  *static_cast<size_t*>(closure) += length;
  return CAIRO_STATUS_SUCCESS;
}

// The cairo baseline: the same limit surface (level r) as one mesh pattern, painted on a
// page of the image's size in points. Returns the PDF's size in bytes (0 on failure).
size_t CairoMeshPdfBytes(const sdvi::Image& image, int levels, double* ms) {
  const auto start = std::chrono::steady_clock::now();
  sdvi::LimitSurfaceOptions options;
  options.levels = levels;
  auto surface = sdvi::BuildLimitSurface(image, options);
  if (!surface.ok()) return 0;
  const std::vector<sdvi::Vertex> fine = sdvi::EvaluateSurface(*surface, image.vertices);
  size_t bytes = 0;
  cairo_surface_t* pdf = cairo_pdf_surface_create_for_stream(CountBytes, &bytes, image.width, image.height);
  cairo_t* cr = cairo_create(pdf);
  cairo_pattern_t* mesh = cairo_pattern_create_mesh();
  for (const sdvi::Triangle& t : surface->triangles) {
    cairo_mesh_pattern_begin_patch(mesh);
    for (int k = 0; k < 3; ++k) {
      const sdvi::Vertex& v = fine[t.v[k]];
      if (k == 0) cairo_mesh_pattern_move_to(mesh, v.x, v.y);
      else cairo_mesh_pattern_line_to(mesh, v.x, v.y);
    }
    // A triangle patch: the closing side makes the 4th corner the 1st point again.
    for (int k = 0; k < 4; ++k) {
      const sdvi::Vertex& v = fine[t.v[k % 3]];
      auto c = [](float x) { return std::clamp(double(x), 0.0, 255.0) / 255.0; };
      cairo_mesh_pattern_set_corner_color_rgb(mesh, k, c(v.r), c(v.g), c(v.b));
    }
    cairo_mesh_pattern_end_patch(mesh);
  }
  cairo_set_source(cr, mesh);
  cairo_paint(cr);
  cairo_pattern_destroy(mesh);
  cairo_destroy(cr);
  cairo_surface_finish(pdf);
  const bool ok = cairo_surface_status(pdf) == CAIRO_STATUS_SUCCESS;
  cairo_surface_destroy(pdf);
  *ms = Millis(start);
  return ok ? bytes : 0;
}

// One row of the SVG table: flat vs Gouraud PSNR at x1 and x4 (upper bounds for an SVG
// viewer), SVG bytes and their ratio to the PDF's.
void SvgRow(const std::string& name, const sdvi::Image& image, int levels, size_t pdf_bytes) {
  sdvi::LimitSurfaceOptions options;
  options.levels = levels;
  auto surface = sdvi::BuildLimitSurface(image, options);
  if (!surface.ok()) return;
  const std::vector<sdvi::Vertex> fine = sdvi::EvaluateSurface(*surface, image.vertices);
  std::vector<sdvi::Vertex> flat;
  std::vector<sdvi::Triangle> flat_triangles;
  flat.reserve(surface->triangles.size() * 3);
  for (const sdvi::Triangle& t : surface->triangles) {
    const sdvi::Vertex &a = fine[t.v[0]], &b = fine[t.v[1]], &c = fine[t.v[2]];
    const float r = (a.r + b.r + c.r) / 3, g = (a.g + b.g + c.g) / 3, bl = (a.b + b.b + c.b) / 3;
    const uint32_t base = uint32_t(flat.size());
    for (const sdvi::Vertex* v : {&a, &b, &c}) flat.push_back({v->x, v->y, r, g, bl});
    flat_triangles.push_back({{base, base + 1, base + 2}});
  }
  double psnr[2] = {0, 0};
  for (int i = 0; i < 2; ++i) {
    const int scale = i == 0 ? 1 : 4;
    sdvi::Viewport vp = sdvi::Viewport::Identity(int(image.width), int(image.height));
    if (scale == 4) {
      vp.width = std::min(1024, int(image.width) * 4);
      vp.height = std::min(1024, int(image.height) * 4);
      vp.scale_x = vp.scale_y = 4;
      vp.origin_x = (image.width * 4.0 - vp.width) / 2 / 4;
      vp.origin_y = (image.height * 4.0 - vp.height) / 2 / 4;
    }
    const sdvi::Raster gouraud = sdvi::RenderFineMesh(surface->triangles, fine, vp);
    const sdvi::Raster flat_raster = sdvi::RenderFineMesh(flat_triangles, flat, vp);
    auto metrics = sdvi::CompareImages(flat_raster, gouraud);
    psnr[i] = metrics.ok() ? metrics->psnr : 0;
  }
  sdvi::SvgExportOptions svg_options;
  svg_options.levels = levels;
  auto exported = sdvi::EncodeSvg(image, svg_options);
  const size_t svg = exported.ok() ? exported->bytes.size() : 0;
  std::printf("| %s | %d | %zu | %.2f | %.2f | %zu | %.1f |\n", name.c_str(), levels,
              surface->triangles.size(), psnr[0], psnr[1], svg, double(svg) / double(pdf_bytes));
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> files;
  int levels = -1;
  bool svg = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--levels" && i + 1 < argc) {
      levels = std::atoi(argv[++i]);
    } else if (a == "--svg") {
      svg = true;
    } else if (!a.empty() && a[0] != '-') {
      files.push_back(a);
    } else {
      std::fprintf(stderr, "usage: bench_pdf IN.sdvi... [--levels r] [--svg]\n");
      return 2;
    }
  }
  if (files.empty()) {
    std::fprintf(stderr, "usage: bench_pdf IN.sdvi... [--levels r] [--svg]\n");
    return 2;
  }
  std::printf("| file | level | fine triangles | records/tri | bits xy/rgb | sdvi PDF bytes | bytes/tri | "
              "write ms | cairo (type 7) bytes | cairo ms | cairo / sdvi |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  int status = 0;
  struct SvgInput {
    std::string name;
    sdvi::Image image;
    int levels;
    size_t pdf_bytes;
  };
  std::vector<SvgInput> svg_rows;
  for (const std::string& file : files) {
    auto image = sdvi::ReadImage(file);
    if (!image.ok()) {
      std::fprintf(stderr, "%s\n", image.status().ToString().c_str());
      status = 1;
      continue;
    }
    sdvi::PdfExportOptions options;
    options.levels = levels;
    const auto start = std::chrono::steady_clock::now();
    auto pdf = sdvi::EncodePdf(*image, options);
    const double ms = Millis(start);
    if (!pdf.ok()) {
      std::fprintf(stderr, "%s: %s\n", file.c_str(), pdf.status().ToString().c_str());
      status = 1;
      continue;
    }
    double cairo_ms = 0;
    const size_t cairo_bytes = CairoMeshPdfBytes(*image, pdf->levels, &cairo_ms);
    std::printf("| %s | %d | %u | %.3f | %d/%d | %zu | %.2f | %.0f | %zu | %.0f | %.2f |\n",
                file.substr(file.find_last_of('/') + 1).c_str(), pdf->levels, pdf->triangles,
                double(pdf->records) / pdf->triangles, pdf->bits_per_coordinate, pdf->bits_per_component,
                pdf->bytes.size(), double(pdf->bytes.size()) / pdf->triangles, ms, cairo_bytes, cairo_ms,
                double(cairo_bytes) / double(pdf->bytes.size()));
    std::fflush(stdout);
    if (svg) svg_rows.push_back({file.substr(file.find_last_of('/') + 1), std::move(*image), pdf->levels,
                                 pdf->bytes.size()});
  }
  if (svg) {
    std::printf("\nFlat-shaded SVG 1.1 (best case: sdvi's rasteriser, no seams) vs the Gouraud mesh:\n\n");
    std::printf("| file | level | triangles | PSNR x1 | PSNR x4 (1024^2 centre) | SVG bytes | SVG / PDF |\n");
    std::printf("|---|---|---|---|---|---|---|\n");
    for (const SvgInput& in : svg_rows) {
      for (int r : {in.levels - 1, in.levels, in.levels + 1}) {
        if (r >= 0) SvgRow(in.name, in.image, r, in.pdf_bytes);
      }
    }
  }
  return status;
}
