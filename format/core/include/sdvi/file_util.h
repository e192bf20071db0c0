// File helpers shared by every module that reads or writes files.
// Every output is written atomically: to a temporary file beside the target, then
// renamed; a failed write leaves nothing behind.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sdvi/status.h"

namespace sdvi {

// The whole file as bytes; kNotFound / kIoError name the path.
StatusOr<std::vector<uint8_t>> ReadFileBytes(const std::string& path);

// Writes bytes to path atomically (temp file + fsync + rename).
Status WriteFileAtomic(const std::string& path, const void* data, size_t size);
inline Status WriteFileAtomic(const std::string& path, const std::vector<uint8_t>& bytes) {
  return WriteFileAtomic(path, bytes.data(), bytes.size());
}

// For writers that need a file name (OpenCV, OpenEXR, tinygltf): calls write(temp_path),
// which must create temp_path; on success renames it to path, on failure removes it.
// The temporary keeps path's extension so that extension-driven writers still work.
Status WriteViaTempFile(const std::string& path,
                        const std::function<Status(const std::string& temp_path)>& write);

// Lower-case extension without the dot ("png"), or "" when there is none.
std::string FileExtension(const std::string& path);

}  // namespace sdvi
