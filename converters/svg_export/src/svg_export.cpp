// SPDX-License-Identifier: GPL-3.0-or-later
// SVG export: flat-shaded fine triangles written with libxml2's xmlTextWriter
// (svg_export.h, spec/SVG_EXPORT.md).
#include "sdvi/svg_export.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <new>
#include <vector>

#include <libxml/xmlwriter.h>

#include "sdvi/export_levels.h"
#include "sdvi/file_util.h"
#include "sdvi/subdiv.h"

namespace sdvi {
namespace {

Status CheckInput(const Image& image, const SvgExportOptions& options) {
  if (options.levels < -1 || options.levels > kMaxSvgLevels) {
    return Status(StatusCode::kInvalidArgument, "SVG export: level " + std::to_string(options.levels) +
                                                    " is out of range (-1.." +
                                                    std::to_string(kMaxSvgLevels) + ")");
  }
  SDVI_RETURN_IF_ERROR(CheckExportInput(image, "SVG export"));
  if (image.width == 0 || image.height == 0) {
    return Status(StatusCode::kEmptyInput, "SVG export: the image size is " + std::to_string(image.width) +
                                               " x " + std::to_string(image.height) + " pixels");
  }
  return Status::Ok();
}

struct WriterDeleter {
  void operator()(xmlTextWriter* w) const { xmlFreeTextWriter(w); }
};
struct BufferDeleter {
  void operator()(xmlBuffer* b) const { xmlBufferFree(b); }
};

const xmlChar* X(const char* s) { return reinterpret_cast<const xmlChar*>(s); }

// A colour channel of the flat fill: the mean of the corners, clamped and rounded to 8 bits.
int Channel(float a, float b, float c) {
  return int(std::lround(std::clamp((double(a) + b + c) / 3.0, 0.0, 255.0)));
}

// The PSNR of the flat-shaded fine mesh against the Gouraud-shaded one over the domain, exact
// for the continuous pictures: on a triangle a linear colour with corner values f0, f1, f2
// differs from its mean m by a mean square of sum (fi - m)^2 / 12.
double FlatShadingPsnr(const std::vector<Triangle>& triangles, const std::vector<Vertex>& fine) {
  double squared = 0, area = 0;
  for (const Triangle& t : triangles) {
    const Vertex &a = fine[t.v[0]], &b = fine[t.v[1]], &c = fine[t.v[2]];
    const double twice = std::abs((double(b.x) - a.x) * (double(c.y) - a.y) - (double(b.y) - a.y) * (double(c.x) - a.x));
    double sum = 0;
    for (auto channel : {&Vertex::r, &Vertex::g, &Vertex::b}) {
      const double m = (double(a.*channel) + b.*channel + c.*channel) / 3;
      for (const Vertex* v : {&a, &b, &c}) sum += (v->*channel - m) * (v->*channel - m);
    }
    squared += twice / 2 * sum / 12 / 3;  // mean over the three channels
    area += twice / 2;
  }
  if (!(area > 0) || !(squared > 0)) return std::numeric_limits<double>::infinity();
  return 10 * std::log10(255.0 * 255.0 * area / squared);
}

}  // namespace

StatusOr<SvgExport> EncodeSvg(const Image& image, const SvgExportOptions& options) {
  SDVI_RETURN_IF_ERROR(CheckInput(image, options));
  SvgExport result;
  // The level: explicit, or one below the PDF's, or the PDF's when the flat shading is
  // under kSvgFlatPsnr dB from the smooth surface there (and the PDF's is within the limit).
  const int pdf_levels = DefaultExportLevels(image);
  int levels = options.levels >= 0 ? options.levels : std::max(0, pdf_levels - 1);
  auto check_count = [&](int r) -> Status {
    const uint64_t fine_triangles = uint64_t(image.triangles.size()) << (2 * r);
    if (fine_triangles <= kMaxSvgFineTriangles) return Status::Ok();
    return Status(StatusCode::kLimitExceeded, "SVG export: level " + std::to_string(r) + " gives " +
                                                  std::to_string(fine_triangles) + " triangles, over the limit of " +
                                                  std::to_string(kMaxSvgFineTriangles));
  };
  SDVI_RETURN_IF_ERROR(check_count(levels));
  try {
    LimitSurface surface;
    std::vector<Vertex> fine;
    for (;;) {
      if (options.progress) options.progress->Phase("limit surface (level " + std::to_string(levels) + ")");
      LimitSurfaceOptions surface_options;
      surface_options.levels = levels;
      surface_options.to_limit = true;
      SDVI_ASSIGN_OR_RETURN(surface, BuildLimitSurface(image, surface_options));
      fine = EvaluateSurface(surface, image.vertices);
      for (const Triangle& t : surface.triangles) {
        for (uint32_t v : t.v) {
          if (v >= fine.size()) {
            return Status(StatusCode::kInternal, "SVG export: a fine triangle refers to vertex " + std::to_string(v) +
                                                     " of " + std::to_string(fine.size()));
          }
        }
      }
      result.flat_psnr = FlatShadingPsnr(surface.triangles, fine);
      if (options.levels >= 0 || result.flat_psnr >= kSvgFlatPsnr || levels >= pdf_levels ||
          !check_count(levels + 1).ok()) {
        break;
      }
      ++levels;
    }
    result.levels = levels;
    result.triangles = uint32_t(surface.triangles.size());

    if (options.progress) options.progress->Phase("writing SVG");
    std::unique_ptr<xmlBuffer, BufferDeleter> buffer(xmlBufferCreate());
    if (!buffer) return Status(StatusCode::kLimitExceeded, "SVG export: out of memory");
    // Doubling, not libxml2 2.9's default exact growth, which copies the whole document at
    // every flush of the writer under an allocator whose realloc copies (spec/SVG_EXPORT.md).
    xmlBufferSetAllocationScheme(buffer.get(), XML_BUFFER_ALLOC_DOUBLEIT);
    std::unique_ptr<xmlTextWriter, WriterDeleter> writer(xmlNewTextWriterMemory(buffer.get(), 0));
    if (!writer) return Status(StatusCode::kEncodeFailed, "SVG export: libxml2 could not start a writer");
    xmlTextWriter* w = writer.get();
    bool ok = xmlTextWriterStartDocument(w, nullptr, "UTF-8", nullptr) >= 0;
    ok = ok && xmlTextWriterStartElement(w, X("svg")) >= 0;
    ok = ok && xmlTextWriterWriteAttribute(w, X("xmlns"), X("http://www.w3.org/2000/svg")) >= 0;
    ok = ok && xmlTextWriterWriteAttribute(w, X("version"), X("1.1")) >= 0;
    ok = ok && xmlTextWriterWriteFormatAttribute(w, X("width"), "%u", image.width) >= 0;
    ok = ok && xmlTextWriterWriteFormatAttribute(w, X("height"), "%u", image.height) >= 0;
    ok = ok && xmlTextWriterWriteFormatAttribute(w, X("viewBox"), "0 0 %u %u", image.width, image.height) >= 0;
    ok = ok && xmlTextWriterWriteAttribute(w, X("shape-rendering"), X("crispEdges")) >= 0;
    ok = ok && xmlTextWriterWriteFormatElement(
                   w, X("desc"), "sdvi %s: the limit surface at level %d, %u flat-shaded triangles",
                   SDVI_VERSION, result.levels, result.triangles) >= 0;
    const size_t step = std::max<size_t>(1, surface.triangles.size() / 100);
    for (size_t i = 0; ok && i < surface.triangles.size(); ++i) {
      const Triangle& t = surface.triangles[i];
      const Vertex &a = fine[t.v[0]], &b = fine[t.v[1]], &c = fine[t.v[2]];
      ok = xmlTextWriterStartElement(w, X("path")) >= 0 &&
           xmlTextWriterWriteFormatAttribute(w, X("d"), "M%.1f %.1fL%.1f %.1f %.1f %.1fZ", a.x, a.y, b.x, b.y,
                                             c.x, c.y) >= 0 &&
           xmlTextWriterWriteFormatAttribute(w, X("fill"), "#%02x%02x%02x", Channel(a.r, b.r, c.r),
                                             Channel(a.g, b.g, c.g), Channel(a.b, b.b, c.b)) >= 0 &&
           xmlTextWriterEndElement(w) >= 0;
      if (options.progress && i % step == 0) options.progress->Update(double(i) / surface.triangles.size());
    }
    ok = ok && xmlTextWriterEndDocument(w) >= 0;  // closes <svg>
    writer.reset();                               // flushes into the buffer
    if (!ok) return Status(StatusCode::kEncodeFailed, "SVG export: libxml2 failed to write the document");
    result.bytes.assign(reinterpret_cast<const char*>(xmlBufferContent(buffer.get())),
                        size_t(xmlBufferLength(buffer.get())));
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::kLimitExceeded, "SVG export: out of memory");
  }
  return result;
}

StatusOr<SvgExport> WriteSvg(const std::string& path, const Image& image, const SvgExportOptions& options) {
  SDVI_ASSIGN_OR_RETURN(SvgExport result, EncodeSvg(image, options));
  SDVI_RETURN_IF_ERROR(WriteFileAtomic(path, result.bytes.data(), result.bytes.size()));
  return result;
}

}  // namespace sdvi
