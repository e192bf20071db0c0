// SPDX-License-Identifier: GPL-3.0-or-later
// Reading and writing .sdvi files for the CLI: every reader reads both payloads
// (raw and Draco-compressed).
#pragma once

#include <string>

#include "sdvi/image.h"
#include "sdvi/status.h"

namespace sdvi::cli {

// Reads a .sdvi file whatever its payload.
StatusOr<Image> LoadSdvi(const std::string& path);
// Writes image as a raw-payload .sdvi file, atomically.
Status SaveSdvi(const std::string& path, const Image& image);
// An export's error as the user should read it: a write error names the output already;
// any other concerns the input image, which it names.
Status ExportError(const Status& status, const std::string& input);

}  // namespace sdvi::cli
