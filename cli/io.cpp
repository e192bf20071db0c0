// SPDX-License-Identifier: GPL-3.0-or-later
#include "io.h"

#include "sdvi/codec.h"

namespace sdvi::cli {

StatusOr<Image> LoadSdvi(const std::string& path) { return ReadImage(path); }

Status SaveSdvi(const std::string& path, const Image& image) {
  return WriteImage(path, image, /*compress=*/nullptr);
}

Status ExportError(const Status& status, const std::string& input) {
  if (status.code() == StatusCode::kIoError) return status;
  return Status(status.code(), input + ": " + status.message());
}

}  // namespace sdvi::cli
