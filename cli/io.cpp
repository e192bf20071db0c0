// SPDX-License-Identifier: GPL-3.0-or-later
#include "io.h"

#include "sdvi/codec.h"

namespace sdvi::cli {

StatusOr<Image> LoadSdvi(const std::string& path) { return ReadImage(path); }

Status SaveSdvi(const std::string& path, const Image& image) {
  return WriteImage(path, image, /*compress=*/nullptr);
}

}  // namespace sdvi::cli
