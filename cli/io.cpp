// Placeholder until the format and codec modules land.
#include "io.h"

namespace sdvi::cli {

StatusOr<Image> LoadSdvi(const std::string& path) {
  return Status(StatusCode::kUnsupportedFormat, path + ": the .sdvi reader is not built yet");
}
Status SaveSdvi(const std::string& path, const Image&) {
  return Status(StatusCode::kUnsupportedFormat, path + ": the .sdvi writer is not built yet");
}

}  // namespace sdvi::cli
