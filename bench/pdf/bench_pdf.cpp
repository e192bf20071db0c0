// SPDX-License-Identifier: GPL-3.0-or-later
// bench_pdf IN.sdvi... [--levels r]: for each file, the PDF export (type-4 strips, spec/PDF.md)
// against the size baseline of issue 12: cairo's PDF surface with a mesh pattern holding
// the same fine triangles (one Coons patch per triangle, which cairo writes as ShadingType 7),
// both measured in this run. Prints one table row per file:
//   level, fine triangles, records/triangle, sdvi PDF bytes, bytes/triangle, write ms,
//   cairo bytes, cairo ms, cairo / sdvi.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <cairo-pdf.h>
#include <cairo.h>

#include "sdvi/codec.h"
#include "sdvi/pdf.h"
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

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> files;
  int levels = -1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--levels" && i + 1 < argc) {
      levels = std::atoi(argv[++i]);
    } else if (!a.empty() && a[0] != '-') {
      files.push_back(a);
    } else {
      std::fprintf(stderr, "usage: bench_pdf IN.sdvi... [--levels r]\n");
      return 2;
    }
  }
  if (files.empty()) {
    std::fprintf(stderr, "usage: bench_pdf IN.sdvi... [--levels r]\n");
    return 2;
  }
  std::printf("| file | level | fine triangles | records/tri | bits xy/rgb | sdvi PDF bytes | bytes/tri | "
              "write ms | cairo (type 7) bytes | cairo ms | cairo / sdvi |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  int status = 0;
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
  }
  return status;
}
