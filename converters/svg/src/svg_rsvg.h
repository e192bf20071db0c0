// SPDX-License-Identifier: GPL-3.0-or-later
// librsvg handles for the importer's sources (the only place that names librsvg types).
#pragma once

#include <librsvg/rsvg.h>

#include <cairo.h>

#include <memory>

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

}  // namespace sdvi
