// SPDX-License-Identifier: GPL-3.0-or-later
// File helpers shared by every module that reads or writes files.
// Every output is written atomically: to a temporary file beside the target, then
// renamed; a failed write leaves nothing behind. Precisely:
//  - a symbolic link is followed: the file it points to is replaced (the link stays);
//  - a replaced file keeps its permission bits (and, when running as root, its owner);
//  - a target that exists and is not a regular file (a device such as /dev/null or
//    /dev/stdout, a FIFO, a socket) is written through, never replaced; a failed write
//    there (e.g. /dev/full) is an error;
//  - SIGINT or SIGTERM during a write removes the temporary file (the handler is installed
//    on first use, only where the signal's disposition is the default) and then ends the
//    process as the signal would have.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sdvi/status.h"

namespace sdvi {

// True for "-", the path that means standard input (reading) or standard output (writing):
// every function here reads /dev/stdin or writes through /dev/stdout for it.
bool IsStdStream(const std::string& path);

// The whole file as bytes; kNotFound / kIoError name the path; kLimitExceeded when it
// holds more than max_bytes (checked before reading a regular file).
StatusOr<std::vector<uint8_t>> ReadFileBytes(const std::string& path,
                                             uint64_t max_bytes = UINT64_MAX);

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

// Checks, before any work, that path can be written: not a directory, its directory exists
// and is writable (or it is an existing non-regular file we may write), and it is not
// the same file (device and inode, symlinks followed) as any of inputs. Errors name path:
// kInvalidArgument (output = an input), kNotFound (no such directory), kIoError.
Status CheckOutputPath(const std::string& path, const std::vector<std::string>& inputs = {});

// Lower-case extension without the dot ("png"), or "" when there is none.
std::string FileExtension(const std::string& path);

}  // namespace sdvi
