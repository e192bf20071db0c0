// SPDX-License-Identifier: GPL-3.0-or-later
// The .sdvi container (spec/FORMAT.md): reading, writing, validating.
//
// A .sdvi file is one FlatBuffers buffer (schema/sdvi.fbs, identifier "SDVI") holding the
// control mesh of spec/METHOD.md section 8 (spec/FORMAT.md) at the paper's cost: 20 bytes a vertex, 6 bytes a
// triangle, tags implicit in triangle order and rotation. A raw file with no optional
// data and V <= 65535 is exactly 20V + 6T + 68 bytes (+2 when T is odd).
//
// Canonical form (what the writer stores and the reader returns):
//   * triangles are grouped 3-tagged, 2-tagged, 1-tagged, untagged, keeping the caller's
//     relative order inside each group (a stable partition);
//   * a 2-tagged triangle is rotated so its untagged edge is (c,a), a 1-tagged one so its
//     tagged edge is (a,b); 3-tagged and untagged triangles are not rotated;
//   * an edge is crease when any triangle tags it; the writer tags it in every triangle
//     that has it; crease_edges and corners are sorted and unique.
// Decoding a file and encoding the result gives the same bytes.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "sdvi/image.h"
#include "sdvi/mesh_rules.h"
#include "sdvi/status.h"

namespace sdvi {

// The format version this build writes; it reads every minor version of this major.
inline constexpr uint16_t kSdviVersionMajor = 1;
inline constexpr uint16_t kSdviVersionMinor = 0;
// Largest vertex count of the narrow profile (uint16 triangle indices).
inline constexpr uint32_t kNarrowProfileMaxVertices = 65535;

// The values a real image has (kMaxImageSide, kColorMargin, CheckImageValues) are in
// sdvi/mesh_rules.h, shared with the engine and the editor.

// Limits a reader enforces before allocating anything (kLimitExceeded beyond them).
struct ReadOptions {
  uint64_t max_file_bytes = uint64_t{1} << 30;  // 1 GiB
  uint32_t max_vertices = 50'000'000;
  uint32_t max_triangles = 100'000'000;
  uint32_t max_width = kMaxImageSide;
  uint32_t max_height = kMaxImageSide;
  // false: a CRC-32 that disagrees with the bytes is not an error. Only for fuzzing, so that
  // mutated inputs reach the checks behind the checksum (the fuzz targets in fuzz/).
  bool verify_checksums = true;
};

enum class PayloadKind { kRaw, kDraco };

// What the container says about a compressed payload without decoding it.
struct PayloadSummary {
  uint8_t codec_version_major = 0, codec_version_minor = 0;
  uint32_t vertex_count = 0, triangle_count = 0;       // of the mesh inside the payload
  std::vector<std::pair<std::string, std::string>> params;  // codec settings, in order
  friend bool operator==(const PayloadSummary&, const PayloadSummary&) = default;
};

// A decoded container.
struct SdviFile {
  uint16_t version_major = 0, version_minor = 0;
  PayloadKind payload = PayloadKind::kRaw;
  // The full image for kRaw (canonical form); for kDraco everything except vertices,
  // triangles, crease_edges and corners (width, height, feature layer and metadata live
  // outside the payload).
  Image image;
  std::vector<uint8_t> compressed_payload;  // the Draco bytes when payload == kDraco
  PayloadSummary payload_summary;           // when payload == kDraco
  uint64_t file_bytes = 0;
  // The paper's triangle groups as stored (kRaw): counts of 3-, 2- and 1-tagged triangles.
  uint32_t tagged3 = 0, tagged2 = 0, tagged1 = 0;
};

// Decodes a container from memory; source_name (usually the path) prefixes every message.
// Checks, in order: size limits (kLimitExceeded), identifier (kWrongIdentifier), major
// version (kUnsupportedVersion), CRC-32 (kTruncated when a list runs past the end of the
// file, else kCorrupt), FlatBuffers structure (kCorrupt), counts (kCountMismatch), limits
// (kLimitExceeded), then ValidateImage.
StatusOr<SdviFile> DecodeSdvi(std::span<const uint8_t> bytes, const std::string& source_name,
                              const ReadOptions& options = {});

// Encodes image as a raw-payload container in canonical form (ValidateImage first).
StatusOr<std::vector<uint8_t>> EncodeSdvi(const Image& image);

// Encodes a container whose mesh is the given Draco payload. image_without_mesh must have
// no vertices, triangles, crease_edges or corners (kInvalidArgument otherwise); its
// feature layer may index the payload's vertices (not checked here: the codec checks
// after decoding).
StatusOr<std::vector<uint8_t>> EncodeSdviCompressed(const Image& image_without_mesh,
                                                    const std::vector<uint8_t>& draco_payload,
                                                    const PayloadSummary& summary = {});

// Reads and decodes a file (kNotFound, kIoError, or any DecodeSdvi error).
StatusOr<SdviFile> ReadSdviFile(const std::string& path, const ReadOptions& options = {});

// Encodes image (raw payload) and writes it atomically: nothing is left on failure.
Status WriteSdvi(const std::string& path, const Image& image);

// The one validation every reader and writer applies (spec/FORMAT.md section 9): width
// and height positive (kEmptyInput) and at most kMaxImageSide (kLimitExceeded), finite
// coordinates and colours (kNonFinite) within the ranges above (kValueOutOfRange), vertex
// indices in range (kIndexOutOfRange), no repeated vertex in a triangle
// (kDegenerateTriangle), no two triangles on the same vertices (kDuplicateTriangle), at
// most two triangles on an edge (kNonManifoldEdge), the two triangles of an edge
// traversing it in opposite directions (kInvalidMesh) and lying on opposite sides of it
// (kFoldedTriangle), crease edges with a < b, sorted, unique and each an edge of some
// triangle (kCreaseNotAnEdge / kInvalidArgument), corners sorted and unique, feature
// pairs naming existing polylines with sharpness in [0,1].
Status ValidateImage(const Image& image, const std::string& source_name);

// The distance (pixels) past which ValidateImage counts the vertex opposite an edge as
// across it (kFoldedTriangle: both opposite vertices of an edge farther than this on the
// same side; spec/FORMAT.md section 9, check 24): 1/1024 px plus float rounding at the
// image's scale.
double FoldTolerance(const Image& image);

// Returns image in canonical form (see the top of this file): triangles partitioned and
// rotated, crease_edges and corners sorted and unique. Other fields unchanged.
Image CanonicalizeImage(const Image& image);

// Bytes the paper counts for a mesh: 20 V + 6 T + 8.
inline uint64_t PaperSizeBytes(uint64_t vertices, uint64_t triangles) {
  return 20 * vertices + 6 * triangles + 8;
}

// CRC-32 (ISO-HDLC, polynomial 0xEDB88320 reflected, init and xor-out 0xFFFFFFFF).
uint32_t Crc32(std::span<const uint8_t> bytes, uint32_t crc = 0);

}  // namespace sdvi
