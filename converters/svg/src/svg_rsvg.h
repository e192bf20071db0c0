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

// librsvg's handle for document, from memory with no base file, 96 dpi.
StatusOr<RsvgHandlePtr> OpenRsvg(const SvgDocument& document, SvgError* error);

// Renders document into cr at the viewport (0, 0, width, height).
Status RenderWithRsvg(const SvgDocument& document, cairo_t* cr, int width, int height, SvgError* error);

}  // namespace sdvi
