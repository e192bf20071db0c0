// SPDX-License-Identifier: GPL-3.0-or-later
// librsvg handles for the importer's sources (the only place that names librsvg types).
#pragma once

#include <librsvg/rsvg.h>

#include <cairo.h>

#include <memory>
#include <string>

#include "svg_internal.h"

namespace sdvi {

struct RsvgHandleDeleter {
  void operator()(RsvgHandle* h) const { g_object_unref(h); }
};
using RsvgHandlePtr = std::unique_ptr<RsvgHandle, RsvgHandleDeleter>;

// librsvg's handle for document, from memory with no base file, 96 dpi; traced: from
// document.traced when there is one.
StatusOr<RsvgHandlePtr> OpenRsvg(const SvgDocument& document, SvgError* error, bool traced = false);

// Renders document (traced: document.traced when there is one) into cr at the viewport (0, 0, width, height).
Status RenderWithRsvg(const SvgDocument& document, cairo_t* cr, int width, int height, SvgError* error,
                      bool traced = false);

// cairo's write callback for a script surface: appends the bytes to the std::string closure.
inline cairo_status_t AppendScript(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

}  // namespace sdvi
