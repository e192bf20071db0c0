// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target over the SVG importer's input side (converters/svg): the safety pass
// (LoadSvg: libxml2 SAX check, path-data grammar, use expansion), the output size, librsvg's
// rendering and the geometry trace (cairo script reader) at a small size, and the artwork
// mode's outline features on them (no vectorizer: too slow for fuzzing). Besides "never
// crash": a refusal carries a message naming the input and an SvgError; every traced
// point is finite; the raster has the requested size; every feature point is finite.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "sdvi/svg.h"
#include "svg_internal.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  sdvi::SvgLimits limits;
  limits.max_bytes = 1 << 20;
  limits.max_elements = 5000;
  limits.max_use_expansion = 20000;
  limits.max_path_commands = 50000;
  sdvi::SvgError error = sdvi::SvgError::kNone;
  auto document = sdvi::LoadSvg(std::string(reinterpret_cast<const char*>(data), size), "fuzz.svg", limits, &error);
  if (!document.ok()) {
    if (document.status().message().find("fuzz.svg") == std::string::npos) std::abort();
    if (error == sdvi::SvgError::kNone) std::abort();
    return 0;
  }
  // Small rasters keep an execution short whatever the document's own size.
  auto chosen = sdvi::ChooseSvgSize(*document, 48, 0, limits, &error);
  if (!chosen.ok()) return 0;
  if (chosen->width != 48 || chosen->height < 1) std::abort();
  if (chosen->height > 256) return 0;
  auto raster = sdvi::RenderSvg(*document, chosen->width, chosen->height);
  if (raster.ok() && (raster->width != chosen->width || raster->height != chosen->height)) std::abort();
  auto shapes = sdvi::TraceSvgGeometry(*document, chosen->width, chosen->height);
  if (raster.ok() && shapes.ok()) {
    sdvi::SvgArtworkOptions options;
    if (sdvi::OutlineSampleCount(shapes->shapes, *raster, options.sample_spacing) <= 200000) {
      for (const sdvi::FeatureCurve& curve : sdvi::ArtworkFeatures(shapes->shapes, *raster, options)) {
        for (const sdvi::Point2& p : curve.points) {
          if (!std::isfinite(p.x) || !std::isfinite(p.y)) std::abort();
        }
      }
    }
  }
  if (!raster.ok() && raster.status().message().find("fuzz.svg") == std::string::npos) std::abort();
  if (shapes.ok()) {
    for (const sdvi::SvgShape& shape : shapes->shapes) {
      if (!std::isfinite(shape.stroke_width) || shape.stroke_width < 0) std::abort();
      for (const sdvi::SvgOutline& o : shape.outlines) {
        if (o.points.size() < 4 || (o.points.size() - 1) % 3 != 0) std::abort();
        for (const sdvi::Point2& p : o.points) {
          if (!std::isfinite(p.x) || !std::isfinite(p.y)) std::abort();
        }
      }
    }
  }
  return 0;
}
