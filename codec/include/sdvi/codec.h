// SPDX-License-Identifier: GPL-3.0-or-later
// The compressed payload of a .sdvi file (spec/FORMAT.md, "Compressed payload (Draco)").
//
// The control mesh (vertices, triangles, crease edges, explicit corners) travels as one
// byte string: a 40-byte header, a Draco mesh (POSITION = (x, y), COLOR = (R, G, B) or
// one grey value when R = G = B at every vertex, or decorrelated colours L, C1, C2 in three
// attributes (ColorCoding), all quantized; optionally a GENERIC uint32 attribute holding
// original vertex ids) and a tag stream (adaptive binary range
// coding: one bit per mesh edge, crease or not; one per vertex, explicit corner or not;
// then, by default, the feature layer as walks along crease edges; in payload 1.4 opened by
// the positions on Draco's grid, predicted by the mean of the decoded neighbours). The rest of the
// image (size, metadata; the feature layer when the payload does not carry it) stays in
// the container.
//
// What travels exactly and what does not:
//  - topology (which vertex triples form triangles, with their orientation), crease
//    edges, corners and the feature layer (polylines, pairs, sharpness): exactly;
//  - positions and colours: within half a quantization step (CompressionErrorBound);
//  - vertex order: kept when CompressOptions::keep_vertex_order is set; otherwise the
//    decoded order is Draco's traversal order and the encoder reports the renumbering
//    (RenumberVertices applies it to the feature layer, so it points at the same
//    vertices after decode);
//  - triangle order and the rotation of each triangle's vertex list: never (the paper's
//    layout reorders triangles anyway). Decoded triangles are canonical: rotated so that
//    the smallest vertex index comes first (orientation kept), sorted lexicographically.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "sdvi/format.h"
#include "sdvi/image.h"
#include "sdvi/status.h"

namespace sdvi {

// Largest quantization (bits per component) the codec uses or accepts. Draco's entropy
// coder keeps tables of about 2^(bits + 1) entries per attribute, so memory doubles with
// every bit whatever the mesh size (measured on a 1,681-vertex mesh at speed 0: 20 bits
// 26 MB, 22 bits 88 MB, 24 bits 0.4 GB; 30 bits was killed past 23 GB). 24 bits bounds it
// (spec/FORMAT.md 8.2) and still steps 1/21 px over the largest image an .sdvi file holds
// with its margins (3 x 262144 px).
inline constexpr int kMaxQuantizationBits = 24;

// How the colours travel in a Draco payload (spec/FORMAT.md 8.2). kRgb: one COLOR attribute
// (R, G, B; one grey value when R = G = B everywhere). kDecorrelated: the orthonormal
// luminance/opponent transform L = (R + G + B)/sqrt(3), C1 = (R - B)/sqrt(2),
// C2 = (R - 2G + B)/sqrt(6), each component its own attribute on the same step, predicted
// by difference: the same squared error in R, G, B, fewer bytes on most photos (Draco codes
// each attribute's residuals with its own entropy model, so the small opponent residuals no
// longer share the luminance's). kSmallest: both, and decorrelated with neighbour-mean
// prediction (L, C1, C2 on their grids, each predicted by the rounded mean of its neighbours
// decoded before it, payload 1.3) when the mesh travels without vertex ids: the smallest file
// (kRgb on ties; grey images always kRgb).
enum class ColorCoding { kRgb, kDecorrelated, kSmallest };

struct CompressOptions {
  int position_bits = 0;  // 1..kMaxQuantizationBits; 0 = from the image size (DefaultPositionBits)
  int color_bits = 0;     // 1..kMaxQuantizationBits; 0 = from the colour range (DefaultColorBits)
  int speed = 0;          // Draco encoding/decoding speed 0 (smallest) .. 10 (fastest)
  ColorCoding color_coding = ColorCoding::kRgb;
  bool keep_vertex_order = false;  // store original vertex ids (costs bytes)
  bool feature_layer = true;       // carry polylines and pairs in the payload (compactly)
  // With the feature layer: code it before the crease edges, its polylines along mesh edges
  // (payload 1.2, spec/FORMAT.md 8.5); false writes payload 1.1.
  bool features_first = true;
  // With kSmallest: also try neighbour-mean colours (payload 1.3, spec/FORMAT.md 8.2).
  bool neighbour_mean = true;
  // With kSmallest and no vertex ids: also try the positions coded in the tag stream, each
  // predicted by the mean of its neighbours decoded before it (payload 1.4, spec/FORMAT.md
  // 8.7), kept when the payload is smaller.
  bool stream_positions = true;
  // With stream_positions and neighbour_mean: also try the neighbour-mean colours coded in the
  // tag stream after the positions, the Draco mesh left with the connectivity alone (payload
  // 1.5, spec/FORMAT.md 8.8), kept when the payload is smaller.
  bool stream_colors = true;
  // With stream_colors and a grey image (R = G = B at every vertex): also try its one colour
  // component coded in the tag stream the same way (payload 1.6, spec/FORMAT.md 8.9).
  bool stream_grey_colors = true;
  // Repeat the payload header's settings as container params (spec/FORMAT.md 8): what v1.0
  // writers did; redundant with the header and ~220 bytes a file, so off by default.
  bool container_params = false;
  // MSE (8-bit units, over R, G, B) of the image's render against its source, when known
  // (the vectorizer reports it): lets the default quantization spend 1% of it (see
  // DefaultPositionBits). 0 = unknown: the conservative defaults.
  double reference_mse = 0;
};

// Default position quantization: the smallest bit count (at least 8, at most
// kMaxQuantizationBits) whose step over
// max(width, height, extent of the vertex positions) is at most s_p. Without a reference
// MSE s_p = 1/128 px (17 bits for 512 x 512), safe for fits up to ~57 dB: colour-
// discontinuity pairs can be a fraction of a pixel apart, so positions need fine steps
// (measured on vectorized data, PSNR drop of the render against the raw file's render:
// tango_face-smile at 46 dB lost 0.038 dB at 1/16 px, 0.008 at 1/32; adwaita computer at
// 56.8 dB lost 0.116 dB at 1/64 px and 1/4 level, 0.006 at 1/128 px and 1/8 level).
// With a reference MSE M (CompressOptions::reference_mse > 0) the steps follow from a
// distortion budget: quantization adds about 13 s_p^2 (measured worst case, sharp
// graphics) + s_c^2 / 24 (colour step s_c) to the MSE; each gets half of 0.01 M (a PSNR
// drop of ~0.043 dB): s_p = sqrt(0.01 M / 26) clamped to [1/512, 1/4] px.
int DefaultPositionBits(const Image& image, double reference_mse = 0);
// Default colour quantization: the smallest bit count (8 .. kMaxQuantizationBits) whose step over the
// colour range of the vertices is at most s_c: 1/8 of an 8-bit level without a reference
// MSE (11 bits for 0..255; control colours overshoot 0..255), with one
// s_c = sqrt(0.12 M) clamped to [1/32, 4] levels.
int DefaultColorBits(const Image& image, double reference_mse = 0);

// Upper bounds of |decoded - original| for positions and colours of image at the
// given (resolved, non-zero) bit counts: half a Draco quantization step, where the step
// is the largest per-component extent of the attribute divided by 2^bits - 1 (for colours
// the extent of R, G, B whatever the coding). Decorrelated colours are quantised on that
// step in L, C1, C2, so an R, G or B component errs by at most
// kDecorrelatedErrorFactor = 1/sqrt(3) + 1/sqrt(2) + 1/sqrt(6) half steps (its mean squared
// error is that of RGB coding on the same step).
struct ErrorBound {
  double position = 0, color = 0;
};
inline constexpr double kDecorrelatedErrorFactor = 1.6927053409;
ErrorBound CompressionErrorBound(const Image& image, int position_bits, int color_bits,
                                 bool decorrelated = false);

// Positions on the grid of a payload at position_bits, with the defects that rounding makes
// mended locally (spec/RATE.md section 3). The grid is Draco's: per component
// min + q * range / (2^bits - 1), computed in float as its decoder does, so encoding the
// result at these bits codes exactly these positions (min and range unchanged). Each vertex
// goes to its nearest grid point, as the codec would round it. The defects: an edge that
// folds (ValidateImage's rule, FoldTolerance) and a triangle whose area collapses to zero or
// reverses (where the unquantised mesh's is positive in its orientation). While there are
// some (a few rounds at most), one vertex of a defect moves to another grid point at most
// kMendRadius steps from its nearest one (a vertex whose nearest grid point is on the lowest
// or highest grid line of a component keeps that coordinate): the move that removes the most defects around it, nearest to the
// unquantised position on ties. *moved: the vertices not at their nearest grid point.
// kFoldedTriangle when defects remain, kInvalidArgument for bits outside
// 1..kMaxQuantizationBits; colours and topology untouched.
inline constexpr int kMendRadius = 2;
StatusOr<Image> SnapPositionsToGrid(const Image& image, int position_bits, int* moved = nullptr);

// Encodes the control mesh and tags of image. If new_index_of_vertex is given it
// receives, for every original vertex i, its index in the decoded image (the identity
// when the vertex order is kept). Fails with kInvalidArgument for bad options,
// ValidateImage's codes (kIndexOutOfRange, kCreaseNotAnEdge, kNonFinite,
// kValueOutOfRange, kFoldedTriangle, ...) or kEmptyInput for an image that cannot be
// encoded, kEncodeFailed when Draco fails or does not round trip, or when the positions'
// or colours' span is below 2^(bits - 126), where Draco's float quantiser overflows.
StatusOr<std::vector<uint8_t>> EncodeDracoPayload(const Image& image,
                                                  const CompressOptions& options,
                                                  std::vector<uint32_t>* new_index_of_vertex = nullptr);

// Decodes a payload made by EncodeDracoPayload into image->vertices, triangles,
// crease_edges, corners and, when the payload carries it, polylines and pairs (other
// fields untouched). Errors name source_name:
// kTruncated (shorter than its header says), kCorrupt (bad magic, checksum, counts or
// tag stream), kUnsupportedVersion (newer major version), kDecodeFailed (Draco refused
// the mesh), kLimitExceeded (counts beyond max_vertices). On error *image is unchanged.
// verify_checksum false (ReadOptions::verify_checksums, for fuzzing) ignores a wrong CRC-32.
Status DecodeDracoPayload(std::span<const uint8_t> payload, const std::string& source_name,
                          Image* image, uint64_t max_vertices = uint64_t{1} << 26,
                          bool verify_checksum = true);

// Applies a renumbering (new_index_of_vertex[old] = new) to every vertex reference
// of image: vertices, triangles, crease edges, corners, feature polylines. Returns
// kInvalidArgument unless it is a permutation of the vertex indices.
Status RenumberVertices(const std::vector<uint32_t>& new_index_of_vertex, Image* image);

// Rotates every triangle so that its smallest vertex index comes first (cyclic order
// kept) and sorts the triangles: the order in which a Draco payload decodes them.
void CanonicalizeTriangles(std::vector<Triangle>* triangles);

// What a payload holds, read from its header only (for `sdvi info`).
struct DracoPayloadInfo {
  uint32_t version_major = 0, version_minor = 0;
  uint32_t vertex_count = 0, triangle_count = 0, crease_edge_count = 0, corner_count = 0;
  uint32_t draco_bytes = 0, tag_bytes = 0;
  uint64_t payload_bytes = 0;
  int position_bits = 0, color_bits = 0, speed = 0;
  bool has_vertex_ids = false;
  bool has_feature_layer = false;
  bool grey = false;  // every vertex has R = G = B: one colour component coded
  bool decorrelated = false;  // colours coded as L, C1, C2 (ColorCoding::kDecorrelated)
  bool neighbour_mean = false;  // ... predicted by the decoded neighbours' mean (payload 1.3)
  bool stream_positions = false;  // positions in the tag stream, not in the Draco mesh (payload 1.4)
  bool stream_colors = false;     // neighbour-mean colours (payload 1.5) or, grey, the grey value (1.6) in the tag stream too
};
StatusOr<DracoPayloadInfo> InspectDracoPayload(std::span<const uint8_t> payload,
                                               const std::string& source_name);

// ---- Images in .sdvi files, whatever the payload --------------------------------------

// Decodes a .sdvi container held in memory, raw or Draco payload. Both give the format's
// canonical form (CanonicalizeImage), so reading a compressed file and its decompressed
// copy gives equal images. Errors: any DecodeSdvi error, any DecodeDracoPayload error,
// kCountMismatch when the container's payload summary disagrees with the payload, and
// ValidateImage's codes (e.g. a feature polyline naming a vertex the payload lacks).
StatusOr<Image> DecodeImage(std::span<const uint8_t> bytes, const std::string& source_name,
                            const ReadOptions& options = {});

// Reads a .sdvi file whatever its payload (kNotFound, kIoError, or DecodeImage's errors).
StatusOr<Image> ReadImage(const std::string& path, const ReadOptions& options = {});

// The bytes of a .sdvi container for image: raw payload when compress is null, else a
// Draco payload (the feature layer renumbered to the decoded vertex order). Validates
// the image first (ValidateImage, naming source_name).
StatusOr<std::vector<uint8_t>> EncodeImage(const Image& image, const CompressOptions* compress,
                                           const std::string& source_name = "image");

// Writes image to path atomically: raw payload when compress is null, else Draco.
Status WriteImage(const std::string& path, const Image& image, const CompressOptions* compress);

// What `sdvi info` reports about a file's payload and its cost.
struct CompressionReport {
  PayloadKind payload = PayloadKind::kRaw;
  uint64_t file_bytes = 0;        // the whole container
  uint64_t payload_bytes = 0;     // the Draco payload (kDraco), or the file (kRaw)
  uint64_t paper_bytes = 0;       // 20 V + 6 T + 8: the paper's raw cost of this mesh
  uint32_t vertex_count = 0, triangle_count = 0;
  double bits_per_pixel = 0;      // 8 * file_bytes / (width * height)
  double bytes_per_vertex = 0;    // file_bytes / vertex_count
  double ratio_to_paper = 0;      // file_bytes / paper_bytes
  DracoPayloadInfo draco;         // kDraco only
};
// Computes the report from a decoded container (header reads only; no Draco decoding).
StatusOr<CompressionReport> ReportCompression(const SdviFile& file, const std::string& source_name);

// Where the bytes of a file go (`sdvi info`), in bytes; the parts sum to the file size.
//  raw payload (exact): positions 8 V, colours 12 V, connectivity 6 T (12 T wide; the tags
//    of crease edges are implicit in triangle order), tags = explicit corners, feature layer
//    = what the container grows by with it, container = the rest (header, tables, metadata).
//  Draco payload (measured by re-encoding parts of the decoded mesh at the file's settings):
//    connectivity = the Draco mesh with 1-bit positions and no colours, positions = the
//    mesh with positions minus that (payload 1.4 with the positions in the tag stream: the
//    stream's bytes up to their end), colours = the rest of the Draco mesh (vertex ids, when
//    present, included), tags = crease and corner bits, feature layer = the rest of the tag
//    stream, container = payload header, container, metadata.
struct PartBytes {
  uint64_t connectivity = 0, positions = 0, colors = 0, tags = 0, feature_layer = 0, container = 0;
};
StatusOr<PartBytes> MeasureParts(std::span<const uint8_t> file_bytes, const std::string& source_name);

}  // namespace sdvi
