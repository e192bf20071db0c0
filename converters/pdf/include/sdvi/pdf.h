// SPDX-License-Identifier: GPL-3.0-or-later
// PDF export of an sdvi image: a vector file ordinary viewers open and print at any size
// (spec/PDF.md has the full mapping).
//
// The limit surface at level r (spec/SUBDIVISION.md) becomes one free-form Gouraud-shaded
// triangle mesh (ShadingType 4, ISO 32000-1 section 8.7.4.5.5) painted by the `sh`
// operator on a one-page document:
//   geometry   the fine triangles as strips: each vertex record carries an edge flag
//              (0 = new triangle, 1 / 2 = the new vertex shares an edge of the previous
//              triangle), so a strip of n triangles costs n + 2 records, not 3n;
//   quantised  coordinates in source pixels with BitsPerCoordinate chosen from the image
//              size (step <= 1/64 source pixel), colours with 8 bits per component; the
//              Decode array spans exactly the surface's range;
//   colour     DeviceRGB holding the sRGB values of sdvi::Image (see spec/PDF.md);
//   guards     two zero-area triangles below the surface's bounding box, outside the clip
//              (they work around pdf.js's mesh rasteriser, see spec/PDF.md);
//   clip       the domain's boundary (outer edge and holes, even-odd), so outside an object
//              image's domain the page stays transparent;
//   page       the source size at `dpi` (72 dpi: 1 source pixel = 1 pt), or `width_mm`.
// The document is built with qpdf's object API; the shading stream is Flate-compressed.
// Output is byte-identical for the same input and options (deterministic /ID, no dates).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "sdvi/image.h"
#include "sdvi/progress.h"
#include "sdvi/status.h"

namespace sdvi {

enum class PdfBackground {
  kNone,   // nothing is painted outside the domain (transparent in viewers that show it)
  kWhite,  // the whole page is filled white first
};

// The shading's colour space (spec/PDF.md "Colour"). Both mean sRGB; the values are the same.
enum class PdfColorSpace {
  kDeviceRgb,  // /DeviceRGB: shown as sRGB by the common viewers, no profile in the file
  kSrgbIcc,    // /ICCBased with Little CMS's sRGB profile (about 3 KB), for colour-managed print
};

struct PdfExportOptions {
  int levels = -1;          // subdivision level r in [0, kMaxPdfLevels]; -1 = DefaultExportLevels
  double dpi = 72;          // source pixels per inch: page = size * 72 / dpi points
  double width_mm = 0;      // > 0: page width in millimetres (overrides dpi), aspect kept
  PdfBackground background = PdfBackground::kNone;
  PdfColorSpace color_space = PdfColorSpace::kDeviceRgb;
  int coordinate_bits = 0;  // BitsPerCoordinate: 0 = chosen from the size, else 8, 12, 16, 24, 32
  int color_bits = 8;       // BitsPerComponent: 8, 12 or 16
  Progress* progress = nullptr;  // optional terminal progress (not owned)
};

// The largest level accepted, the fine-triangle budget of an explicit level, and the
// largest page side (points) viewers accept without UserUnit (Acrobat's 200 inches).
inline constexpr int kMaxPdfLevels = 6;
inline constexpr uint64_t kMaxPdfFineTriangles = uint64_t(1) << 24;
inline constexpr double kMaxPdfPageSide = 14400;

// Paint order (spec/PDF.md "Paint order"): viewers paint every pixel a triangle touches
// (poppler), so where triangles share a pixel the last one painted sets it. Fine triangles
// whose colour changes by more than kSteepColorGradient 8-bit levels per source pixel (in
// any of r, g, b) are painted first, the others after them, so that a shared pixel takes
// the colour of the flatter triangle, which is off by less where it misses the pixel's centre.
inline constexpr double kSteepColorGradient = 32;

// What an export produced (the numbers a reader of the file would find).
struct PdfExport {
  std::vector<uint8_t> bytes;      // the whole PDF file
  int levels = 0;                  // the level r used
  uint32_t vertices = 0;           // fine vertices of the surface
  uint32_t triangles = 0;          // fine triangles = triangles of the shading
  uint32_t records = 0;            // vertex records in the shading stream (6 guard records,
                                   // then the surface's strips; spec/PDF.md)
  uint32_t strips = 0;             // flag-0 triples (the 2 guard triangles and the strips)
  uint32_t steep_triangles = 0;    // fine triangles painted first (ColorGradient > kSteepColorGradient)
  int bits_per_coordinate = 0;
  int bits_per_component = 0;
  int bits_per_flag = 0;
  std::array<double, 10> decode{}; // the shading's Decode array: x, y (source px, including the
                                   // guard vertices), r, g, b (0..1)
  double page_width_pt = 0, page_height_pt = 0;
  uint64_t shading_bytes = 0;      // the compressed shading stream
  uint64_t shading_raw_bytes = 0;  // the same before Flate
};

// One vertex record of a type-4 shading: the edge flag and the fine vertex it carries.
struct ShadingRecord {
  uint8_t flag = 0;   // 0: starts a triangle (with the next two records, flag 0 too);
                      // 1: triangle (b, c, new) of the previous (a, b, c); 2: (a, c, new)
  uint32_t vertex = 0;
};

// The triangles as type-4 strips: every triangle appears exactly once, as a flag-0 triple
// or as one flag-1/2 record continuing the previous triangle. Greedy, deterministic.
std::vector<ShadingRecord> TriangleStrips(const std::vector<Triangle>& triangles);

// The triangles the records describe (the reading rule of ISO 32000-1 8.7.4.5.5);
// kCorrupt when a flag is out of range or a strip starts with a flag other than 0.
StatusOr<std::vector<Triangle>> TrianglesFromRecords(const std::vector<ShadingRecord>& records);

// The largest colour gradient of the triangle (a, b, c) over r, g, b, in 8-bit levels per
// source pixel: |grad c| of the plane through the three vertices' colours. A triangle of
// zero area with different colours at its vertices has an infinite gradient, one with equal
// colours 0.
double ColorGradient(const Vertex& a, const Vertex& b, const Vertex& c);

// The smallest BitsPerCoordinate (8, 12, 16, 24, 32) whose step over extent source pixels is
// at most 1/64 pixel.
int CoordinateBitsFor(double extent);

// Builds the PDF in memory. kEmptyInput without triangles, kInvalidArgument for bad options,
// kNonFinite for a NaN or infinite control value, the engine's code for topology it cannot
// subdivide, kLimitExceeded past the fine-triangle budget or the page size, kEncodeFailed when
// qpdf or zlib fail.
StatusOr<PdfExport> EncodePdf(const Image& image, const PdfExportOptions& options);

// Encodes image and writes it atomically to path; nothing is left behind on failure.
StatusOr<PdfExport> WritePdf(const std::string& path, const Image& image,
                             const PdfExportOptions& options);

}  // namespace sdvi
