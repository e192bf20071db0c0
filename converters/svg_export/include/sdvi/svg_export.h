// SPDX-License-Identifier: GPL-3.0-or-later
// SVG export of an sdvi image (spec/SVG_EXPORT.md): SVG 1.1 fills a shape with one colour
// only, so the limit surface at level r becomes its fine triangles, each filled with the
// mean colour of its three corners, drawn with shape-rendering="crispEdges" (no
// anti-aliasing, so triangles sharing an edge leave no seam). The default level is one
// below the PDF's (DefaultExportLevels - 1), or the PDF's when the flat shading there is
// under kSvgFlatPsnr dB from the smooth surface (spec/SVG_EXPORT.md).
// Outside an object image's domain there is no triangle, so the picture stays transparent.
// The document is written with libxml2's xmlTextWriter; output is byte-identical for the
// same input and options.
#pragma once

#include <cstdint>
#include <string>

#include "sdvi/image.h"
#include "sdvi/progress.h"
#include "sdvi/status.h"

namespace sdvi {

// The largest level accepted and the fine-triangle limit of any level.
inline constexpr int kMaxSvgLevels = 6;
inline constexpr uint64_t kMaxSvgFineTriangles = uint64_t(1) << 22;
// The default level's bar: the PSNR of the flat-shaded fine mesh against the Gouraud-shaded
// one (exact over the domain), 3 dB above the 35 dB that viewers must reach against
// `sdvi render`, which they lose to sampling the triangles' edges their own way.
inline constexpr double kSvgFlatPsnr = 38;

struct SvgExportOptions {
  int levels = -1;  // subdivision level r in [0, kMaxSvgLevels]; -1 = chosen (header comment)
  Progress* progress = nullptr;  // optional terminal progress (not owned)
};

struct SvgExport {
  int levels = 0;          // the level r used
  uint32_t triangles = 0;  // fine triangles written (one <path> each)
  double flat_psnr = 0;    // dB, flat against smooth shading of the fine mesh (infinite: equal)
  std::string bytes;       // the document
};

// Errors: kEmptyInput (no triangles, zero size), kNonFinite (a NaN or infinite vertex
// value), kInvalidArgument (levels out of range), kLimitExceeded (more fine triangles than
// kMaxSvgFineTriangles, or out of memory), errors of BuildLimitSurface, kEncodeFailed when
// libxml2 fails.
StatusOr<SvgExport> EncodeSvg(const Image& image, const SvgExportOptions& options);

// EncodeSvg, then the bytes written atomically to path ('-': standard output).
StatusOr<SvgExport> WriteSvg(const std::string& path, const Image& image, const SvgExportOptions& options);

}  // namespace sdvi
