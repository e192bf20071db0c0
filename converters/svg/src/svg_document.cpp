// SPDX-License-Identifier: GPL-3.0-or-later
// Loading (check + librsvg), the output size and the reference raster.
#include <gdk-pixbuf/gdk-pixbuf.h>
#include <librsvg/rsvg.h>

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

#include "svg_internal.h"
#include "svg_rsvg.h"

namespace sdvi {

StatusOr<RsvgHandlePtr> OpenRsvg(const SvgDocument& document, SvgError* error, bool traced) {
  GError* gerror = nullptr;
  const std::string& bytes = traced && !document.traced.empty() ? document.traced : document.bytes;
  // From memory, no base file: librsvg cannot resolve any external reference.
  RsvgHandle* handle = rsvg_handle_new_from_data(reinterpret_cast<const guint8*>(bytes.data()),
                                                 gsize(bytes.size()), &gerror);
  if (handle == nullptr) {
    std::string what = gerror != nullptr ? gerror->message : "unknown error";
    if (gerror != nullptr) g_error_free(gerror);
    return SvgFailure(SvgError::kRenderFailed, document.name, "librsvg cannot load the document: " + what, error);
  }
  rsvg_handle_set_dpi(handle, 96.0);
  return RsvgHandlePtr(handle);
}

Status RenderWithRsvg(const SvgDocument& document, cairo_t* cr, int width, int height, SvgError* error,
                      bool traced) {
  SDVI_ASSIGN_OR_RETURN(RsvgHandlePtr handle, OpenRsvg(document, error, traced));
  RsvgRectangle viewport{0, 0, double(width), double(height)};
  GError* gerror = nullptr;
  if (!rsvg_handle_render_document(handle.get(), cr, &viewport, &gerror)) {
    std::string what = gerror != nullptr ? gerror->message : "unknown error";
    if (gerror != nullptr) g_error_free(gerror);
    return SvgFailure(SvgError::kRenderFailed, document.name, "librsvg cannot render the document: " + what, error);
  }
  return Status::Ok();
}

namespace {

void OnSizePrepared(GdkPixbufLoader* loader, gint width, gint height, gpointer data) {
  auto* size = static_cast<std::pair<int, int>*>(data);
  *size = {width, height};
  gdk_pixbuf_loader_set_size(loader, 0, 0);  // decode nothing (as gdk_pixbuf_get_file_info)
}

// The size a raster image in a data: URL declares, read by gdk-pixbuf (librsvg's decoder)
// from its header before anything is decoded; {0, 0} when it has none.
std::pair<int, int> DataImageSize(const std::string& url) {
  const size_t comma = url.find(',');
  if (comma == std::string::npos) return {0, 0};
  const std::string header = url.substr(0, comma);
  std::string payload;
  if (header.size() >= 7 && header.compare(header.size() - 7, 7, ";base64") == 0) {
    gsize length = 0;
    guchar* decoded = g_base64_decode(url.c_str() + comma + 1, &length);
    if (decoded != nullptr) payload.assign(reinterpret_cast<const char*>(decoded), length);
    g_free(decoded);
  } else {
    GBytes* bytes = g_uri_unescape_bytes(url.c_str() + comma + 1, -1, nullptr, nullptr);
    if (bytes != nullptr) {
      gsize length = 0;
      const char* data = static_cast<const char*>(g_bytes_get_data(bytes, &length));
      payload.assign(data, length);
      g_bytes_unref(bytes);
    }
  }
  std::pair<int, int> size{0, 0};
  GdkPixbufLoader* loader = gdk_pixbuf_loader_new();
  g_signal_connect(loader, "size-prepared", G_CALLBACK(OnSizePrepared), &size);
  // Fed in small pieces, stopping once the header gave the size: nothing is decoded beyond it.
  for (size_t at = 0; at < payload.size() && size.first == 0; at += 4096) {
    const size_t n = std::min<size_t>(4096, payload.size() - at);
    if (!gdk_pixbuf_loader_write(loader, reinterpret_cast<const guchar*>(payload.data() + at), n, nullptr)) break;
  }
  gdk_pixbuf_loader_close(loader, nullptr);
  g_object_unref(loader);
  return size;
}

}  // namespace

StatusOr<SvgDocument> LoadSvg(std::string bytes, const std::string& name, const SvgLimits& limits,
                              SvgError* error) {
  SvgCheck check;
  SDVI_RETURN_IF_ERROR(CheckSvg(bytes, name, limits, &check, error));
  for (const SvgCheck::Image& image : check.images) {
    const auto [w, h] = DataImageSize(image.url);
    if (w > limits.max_dimension || h > limits.max_dimension || double(w) * h > double(limits.max_pixels)) {
      return SvgFailure(SvgError::kSizeTooLarge, name,
                        "line " + std::to_string(image.line) + ": an embedded image of " + std::to_string(w) + " x " +
                            std::to_string(h) + " px exceeds the limit of " + std::to_string(limits.max_dimension) +
                            " px a side / " + std::to_string(limits.max_pixels) + " pixels (max_dimension, max_pixels)",
                        error);
    }
  }
  SvgDocument document;
  document.name = name;
  document.bytes = std::move(bytes);
  document.elements = check.elements;
  document.unsupported = std::move(check.unsupported);
  document.warnings = std::move(check.warnings);
  document.limits = limits;
  document.shortest_dash = check.shortest_dash;
  if (document.shortest_dash > 0 || check.flat_shapes) {
    document.traced = TracedDocument(document.bytes);
    if (document.traced.empty()) {
      return SvgFailure(SvgError::kMalformedXml, name, "libxml2 cannot rewrite the document for tracing", error);
    }
  }
  SDVI_ASSIGN_OR_RETURN(RsvgHandlePtr handle, OpenRsvg(document, error, true));
  gdouble w = 0, h = 0;
  if (rsvg_handle_get_intrinsic_size_in_pixels(handle.get(), &w, &h)) {
    document.width = w;
    document.height = h;
  } else {
    gboolean has_width = FALSE, has_height = FALSE, has_viewbox = FALSE;
    RsvgLength lw, lh;
    RsvgRectangle viewbox{};
    rsvg_handle_get_intrinsic_dimensions(handle.get(), &has_width, &lw, &has_height, &lh, &has_viewbox, &viewbox);
    if (has_viewbox) {
      document.width = viewbox.width;
      document.height = viewbox.height;
    }
  }
  if (!std::isfinite(document.width) || !std::isfinite(document.height) || document.width < 0 ||
      document.height < 0) {
    document.width = document.height = 0;
  }
  return document;
}

Status CheckDashes(const SvgDocument& document, const SvgGeometry& geometry, SvgError* error) {
  if (!(geometry.dashes <= double(document.limits.max_dashes))) {
    char estimate[32];
    std::snprintf(estimate, sizeof estimate, "%.3g", geometry.dashes);
    return SvgFailure(SvgError::kTooManyDashes, document.name,
                      "the dashed strokes would draw about " + std::string(estimate) + " dashes, over the limit of " +
                          std::to_string(document.limits.max_dashes) + " (max_dashes)",
                      error);
  }
  return Status::Ok();
}

StatusOr<SvgDocument> LoadSvgFile(const std::string& path, const SvgLimits& limits, SvgError* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status(StatusCode::kNotFound, path + ": cannot open the file");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) return Status(StatusCode::kIoError, path + ": cannot read the file");
  if (uint64_t(size) > limits.max_bytes) {
    return SvgFailure(SvgError::kFileTooLarge, path,
                      std::to_string(size) + " bytes exceed the limit of " + std::to_string(limits.max_bytes) +
                          " bytes (max_bytes)",
                      error);
  }
  in.seekg(0, std::ios::beg);
  std::string bytes(size_t(size), '\0');
  if (!in.read(bytes.data(), size)) return Status(StatusCode::kIoError, path + ": cannot read the file");
  return LoadSvg(std::move(bytes), path, limits, error);
}

StatusOr<SvgSize> ChooseSvgSize(const SvgDocument& document, int width, double scale, const SvgLimits& limits,
                                SvgError* error) {
  if (width < 0 || !(scale >= 0) || !std::isfinite(scale)) {
    return Status(StatusCode::kInvalidArgument, document.name + ": width and scale must be >= 0");
  }
  const bool has_size = document.width > 0 && document.height > 0;
  if (!has_size) {
    return SvgFailure(SvgError::kNoSize, document.name,
                      "the document has no width, height or viewBox; give the output width", error);
  }
  double w = document.width, h = document.height;
  if (width > 0) {
    h = h * double(width) / w;
    w = width;
  } else if (scale > 0) {
    w *= scale;
    h *= scale;
  }
  const double max_side = double(limits.max_dimension);
  if (!(w <= max_side) || !(h <= max_side) || !(w * h <= double(limits.max_pixels))) {
    return SvgFailure(SvgError::kSizeTooLarge, document.name,
                      "output size " + std::to_string(w) + " x " + std::to_string(h) + " px exceeds the limit of " +
                          std::to_string(limits.max_dimension) + " px a side / " + std::to_string(limits.max_pixels) +
                          " pixels (max_dimension, max_pixels)",
                      error);
  }
  SvgSize size;
  size.width = std::max(1, int(std::lround(w)));
  size.height = std::max(1, int(std::lround(h)));
  return size;
}

StatusOr<Raster> RenderSvg(const SvgDocument& document, int width, int height) {
  if (width <= 0 || height <= 0) {
    return Status(StatusCode::kInvalidArgument, document.name + ": render size must be positive");
  }
  if (document.shortest_dash > 0) {
    // cairo materialises every dash (also for the extents librsvg asks for): bound them first.
    SDVI_ASSIGN_OR_RETURN(SvgGeometry geometry, TraceSvgGeometry(document, width, height));
    SDVI_RETURN_IF_ERROR(CheckDashes(document, geometry, nullptr));
  }
  return RenderSvgUnchecked(document, width, height);
}

StatusOr<Raster> RenderSvgUnchecked(const SvgDocument& document, int width, int height) {
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, width, height);
  std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface_owner(surface, cairo_surface_destroy);
  if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
    return Status(StatusCode::kLimitExceeded, document.name + ": cannot allocate a " + std::to_string(width) + " x " +
                                                  std::to_string(height) + " raster");
  }
  cairo_t* cr = cairo_create(surface);
  Status rendered = RenderWithRsvg(document, cr, width, height, nullptr);
  cairo_destroy(cr);
  SDVI_RETURN_IF_ERROR(rendered);
  cairo_surface_flush(surface);
  const unsigned char* data = cairo_image_surface_get_data(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  Raster raster(width, height, 4);
  for (int y = 0; y < height; ++y) {
    const uint32_t* row = reinterpret_cast<const uint32_t*>(data + size_t(y) * stride);
    for (int x = 0; x < width; ++x) {
      const uint32_t p = row[x];  // premultiplied ARGB, native endian
      const float a = float((p >> 24) & 255u);
      const float r = float((p >> 16) & 255u), g = float((p >> 8) & 255u), b = float(p & 255u);
      const float scale = a > 0 ? 255.f / a : 0.f;
      raster.at(x, y, 0) = std::min(255.f, r * scale);
      raster.at(x, y, 1) = std::min(255.f, g * scale);
      raster.at(x, y, 2) = std::min(255.f, b * scale);
      raster.at(x, y, 3) = a / 255.f;
    }
  }
  return raster;
}

}  // namespace sdvi
