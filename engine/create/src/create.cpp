// SPDX-License-Identifier: GPL-3.0-or-later
// Creating an image from coloured curves (spec/CURVES.md).
// FIRST MERGE ONLY: the API compiles and links, the implementation is not there yet.
#include "sdvi/create.h"

namespace sdvi {

StatusOr<Image> CreateFromCurves(const CurveDrawing&, const CreateOptions&) {
  return Status(StatusCode::kInternal, "CreateFromCurves: not implemented yet (engine/create)");
}

}  // namespace sdvi
