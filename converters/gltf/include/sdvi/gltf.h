// SPDX-License-Identifier: GPL-3.0-or-later
// glTF 2.0 export of an sdvi image for viewers (spec/GLTF.md has the full mapping).
//
// The limit surface at level r (spec/SUBDIVISION.md) becomes one indexed triangle mesh:
//   POSITION  (x, H - y, 0): 1 glTF unit = 1 source pixel, origin at the image's
//             bottom-left corner, +X right, +Y up; the image is upright seen from +Z and
//             every triangle is counter-clockwise seen from +Z.
//   COLOR_0   float RGB in linear light (the sRGB transfer function decoded from the
//             0..255 sRGB scale of sdvi::Image, clamped to 0..1).
//   material  KHR_materials_unlit (base colour white, so the vertex colour is the colour).
// Object images need nothing special: the mesh is the domain, nothing is drawn outside it.
// asset.extras.sdvi carries the source width/height, the level and the unit.
//
// Options: --draco compresses the surface with KHR_draco_mesh_compression (required
// extension, no uncompressed fallback); --control-mesh adds a second node with the
// control mesh (triangles with control colours + the crease edges, boundary included,
// as a LINES primitive) placed beside the surface.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sdvi/image.h"
#include "sdvi/status.h"

namespace sdvi {

class Progress;

enum class GltfContainer {
  kBinary,  // .glb: JSON chunk + one BIN chunk
  kText,    // .gltf: JSON; the buffer in a .bin file beside it (bin_uri), or embedded as a
            // base64 data: URI (embed, or no bin_uri)
};

struct GltfExportOptions {
  int levels = -1;           // subdivision level r in [0, kMaxGltfLevels]; -1 = DefaultGltfLevels
  bool draco = false;        // KHR_draco_mesh_compression for the surface mesh
  int position_bits = 14;    // Draco quantization bits of POSITION, 1..kMaxGltfDracoBits
  int color_bits = 12;       // Draco quantization bits of COLOR_0 (linear light), 1..kMaxGltfDracoBits
  int draco_speed = 3;       // Draco encoder/decoder speed 0 (smallest) .. 10 (fastest)
  bool control_mesh = false; // add the control mesh node (triangles + crease LINES)
  GltfContainer container = GltfContainer::kBinary;
  std::string copyright;     // asset.copyright; empty = metadata "copyright", else "unspecified"
  bool embed = false;        // .gltf: the buffer as a base64 data: URI, not a .bin file
  std::string bin_uri;       // .gltf without embed: the buffer's URI (WriteGltf sets it to
                             // the output's name with .bin, percent-encoded)
  Progress* progress = nullptr;  // optional terminal progress (not owned)
};

// The largest level accepted, and the fine-triangle budget of an explicit level.
inline constexpr int kMaxGltfLevels = 8;
// Largest Draco quantization accepted: Draco's entropy coder keeps tables of about
// 2^(bits + 1) entries, so memory doubles per bit (24 bits: about 0.4 GB at speed 0; 30 bits: more than 16 GB).
inline constexpr int kMaxGltfDracoBits = 24;
inline constexpr uint64_t kMaxGltfFineTriangles = uint64_t(1) << 25;

// What an export produced.
struct GltfExport {
  std::vector<uint8_t> bytes;     // the whole .glb or .gltf file
  std::vector<uint8_t> bin;       // the .bin a .gltf refers to (empty when embedded or .glb)
  int levels = 0;                 // the level r used
  uint32_t vertices = 0;          // surface vertices (after Draco decoding when compressed)
  uint32_t triangles = 0;         // surface triangles
  uint64_t draco_bytes = 0;       // size of the Draco buffer view (0 without --draco)
};

// DefaultExportLevels (sdvi/export_levels.h): fine triangles of ~2 source pixels in
// area, capped at 5 and at ~2M fine triangles; 0 for an empty mesh.
int DefaultGltfLevels(const Image& image);

// The sRGB transfer function decoded: 0..1 sRGB -> 0..1 linear light (IEC 61966-2-1).
float SrgbToLinear(float srgb);

// Builds the glTF file in memory. kEmptyInput without triangles, kInvalidArgument for bad
// options, kNonFinite for a NaN or infinite control value, the engine's code for topology
// it cannot subdivide, kLimitExceeded past the fine-triangle budget, kEncodeFailed when
// Draco or tinygltf fail.
StatusOr<GltfExport> EncodeGltf(const Image& image, const GltfExportOptions& options);

// The container a path asks for: ".glb" -> kBinary, ".gltf" -> kText, else kInvalidArgument.
StatusOr<GltfContainer> GltfContainerForPath(const std::string& path);

// The name of the .bin beside a .gltf: path's file name with its extension replaced by
// .bin ("scene.gltf" -> "scene.bin"), and that name as a relative URI (RFC 3986: bytes
// other than A-Z a-z 0-9 - . _ ~ percent-encoded).
std::string GltfBinPath(const std::string& gltf_path);
std::string GltfBinUri(const std::string& gltf_path);

// Encodes image (container from path's extension, overriding options.container) and
// writes it atomically to path; a .gltf without options.embed gets its buffer in
// GltfBinPath(path), written first (a .gltf never refers to a missing .bin); nothing is
// left behind on failure.
StatusOr<GltfExport> WriteGltf(const std::string& path, const Image& image,
                               GltfExportOptions options);

}  // namespace sdvi
