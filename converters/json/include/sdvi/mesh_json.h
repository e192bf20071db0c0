// SPDX-License-Identifier: GPL-3.0-or-later
// The mesh JSON form (spec/MESH_JSON.md): a human-readable sdvi::Image for authoring and
// testing. Floats travel bit-exactly: the writer prints the shortest decimal that reads
// back (as float32) to the same float, the reader parses numbers directly as float32.
#pragma once

#include <string>
#include <string_view>

#include "sdvi/image.h"
#include "sdvi/status.h"

namespace sdvi {

// Parses mesh JSON. Crease edges are normalised to (smaller, larger) and, like corners,
// sorted and deduplicated (they are sets); vertices and triangles keep their order.
// Errors: kDecodeFailed (JSON syntax), kCorrupt (a key has the wrong shape or type),
// kInvalidArgument (unknown key or format name), then the ValidateImage codes.
StatusOr<Image> ParseMeshJson(std::string_view text, const std::string& source_name);

// The image as mesh JSON text (deterministic; one vertex, triangle or edge per line).
// The image should already be valid; this function does not check it.
std::string FormatMeshJson(const Image& image);

// Reads and parses a mesh JSON file.
StatusOr<Image> ReadMeshJsonFile(const std::string& path);

// Validates image and writes it as mesh JSON, atomically.
Status WriteMeshJsonFile(const std::string& path, const Image& image);

}  // namespace sdvi
