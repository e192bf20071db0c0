// SPDX-License-Identifier: GPL-3.0-or-later
// The Draco payload: header, Draco mesh, tag stream (spec/FORMAT.md, "Compressed
// payload (Draco)").
#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <new>
#include <numeric>

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/compression/expert_encode.h>
#include <draco/compression/point_cloud/point_cloud_decoder.h>
#include <draco/core/varint_decoding.h>
#include <draco/mesh/mesh.h>
#include <draco/metadata/geometry_metadata.h>
#include <draco/metadata/metadata_decoder.h>

#include "color_stream.h"
#include "neighbour_mean.h"
#include "position_stream.h"
#include "range_coder.h"
#include "sdvi/codec.h"
#include "tag_stream.h"

namespace sdvi {
namespace {

using codec_internal::MeshEdge;

// Header layout (little-endian), 40 bytes.
constexpr char kMagic[4] = {'S', 'D', 'R', 'C'};
constexpr uint8_t kVersionMajor = 1;
// Written: the lowest of 1.1 to 1.6 that allows the flags used (1.1: flag bits 3, 4 and 5
// allowed; 1.2: bit 6 too; 1.3: bit 7 too; 1.4: the second flag byte's bit 0; 1.5: its bit 1;
// 1.6: its bit 1 with the grey flag); read: 1.0 .. 1.6 (spec/FORMAT.md 8.1).
constexpr uint8_t kVersionMinor = 6;
constexpr size_t kHeaderSize = 40;
constexpr size_t kCrcOffset = 36;
constexpr uint8_t kFlagVertexIds = 1;     // the Draco mesh has the vertex id attribute
constexpr uint8_t kFlagFeatureLayer = 2;  // the tag stream carries the feature layer
constexpr uint8_t kFlagGrey = 4;          // R = G = B everywhere: COLOR has 1 component
constexpr uint8_t kFlagDecorrelated = 8;  // colours as L (COLOR), C1, C2 (GENERIC ids 3, 4)
constexpr uint8_t kFlagCompactPairs = 16;  // the feature layer's pairs coded compactly
constexpr uint8_t kFlagRankedStarts = 32;  // the feature layer's polyline starts ranked
constexpr uint8_t kFlagFeaturesFirst = 64;  // the feature layer first, polylines along mesh edges
constexpr uint8_t kFlagMeanColors = 128;    // decorrelated colours predicted by the decoded neighbours' mean
// Header byte 10, the second flag byte (payload 1.4; reserved and 0 before).
constexpr uint8_t kFlag2Positions = 1;  // positions in the tag stream, not in the Draco mesh (8.7)
constexpr uint8_t kFlag2Colors = 2;     // neighbour-mean colours (1.5, 8.8) or the grey value (1.6, 8.9) in the tag stream too
constexpr uint8_t kKnownFlags = kFlagVertexIds | kFlagFeatureLayer | kFlagGrey | kFlagDecorrelated |
                                kFlagCompactPairs | kFlagRankedStarts | kFlagFeaturesFirst | kFlagMeanColors;

// Draco attribute unique ids, in the order the attributes are added.
constexpr uint32_t kPositionUniqueId = 0;
constexpr uint32_t kColorUniqueId = 1;
constexpr uint32_t kVertexIdUniqueId = 2;
constexpr uint32_t kC1UniqueId = 3;
constexpr uint32_t kC2UniqueId = 4;

// The orthonormal luminance/opponent transform of decorrelated colours (spec/FORMAT.md
// 8.2), computed in double and rounded to float.
const double kInvSqrt3 = 1 / std::sqrt(3.0), kInvSqrt2 = 1 / std::sqrt(2.0), kInvSqrt6 = 1 / std::sqrt(6.0);
std::array<float, 3> ToDecorrelated(const Vertex& v) {
  const double r = v.r, g = v.g, b = v.b;
  return {float((r + g + b) * kInvSqrt3), float((r - b) * kInvSqrt2), float((r - 2 * g + b) * kInvSqrt6)};
}
std::array<float, 3> FromDecorrelated(float l, float c1, float c2) {
  const double y = l * kInvSqrt3, u = c1 * kInvSqrt2, w = c2 * kInvSqrt6;
  return {float(y + u + w), float(y - 2 * w), float(y - u + w)};
}

// Neighbour-mean colours (payload 1.3, flag bit 7; spec/FORMAT.md 8.2): L, C1, C2 as indices q
// on grids value = origin + q step (the step and origins in the Draco mesh's metadata), each
// coded as q minus its prediction from the points decoded before it.
const char kMeanStepKey[] = "sdvi_colour_step";
const char kMeanOriginKey[] = "sdvi_colour_origin";

// Point p's colour from its L, C1, C2 grid indices q (each at most kMaxColorIndex in size):
// origin + q step computed in double and rounded to float, through the inverse transform;
// false when a float cannot hold a component.
bool ColorFromGrid(const std::array<double, 3>& origin, double step, const std::array<int64_t, 3>& q, Vertex* p) {
  float lcc[3];
  for (int k = 0; k < 3; ++k) {
    const double value = origin[k] + double(q[k]) * step;
    if (!(std::abs(value) <= std::numeric_limits<float>::max())) return false;
    lcc[k] = static_cast<float>(value);
  }
  const std::array<float, 3> back = FromDecorrelated(lcc[0], lcc[1], lcc[2]);
  p->r = back[0];
  p->g = back[1];
  p->b = back[2];
  return true;
}

// Vertex p's colour from the colour stream's grid (payload 1.5: through ColorFromGrid; grey,
// payload 1.6: R = G = B = origin + q step in double, rounded to float); false when a float
// cannot hold it.
bool ColorFromStream(const codec_internal::ColorStream& grid, size_t p, Vertex* v) {
  if (grid.components != 1)
    return ColorFromGrid({grid.origin[0], grid.origin[1], grid.origin[2]}, grid.step, grid.q[p], v);
  const double value = double(grid.origin[0]) + double(grid.q[p][0]) * grid.step;
  if (!(std::abs(value) <= std::numeric_limits<float>::max())) return false;
  v->r = v->g = v->b = static_cast<float>(value);
  return true;
}

// The mesh edges of faces (point triples).
std::vector<MeshEdge> FaceEdges(const std::vector<std::array<uint32_t, 3>>& faces) {
  std::vector<Triangle> triangles(faces.size());
  for (size_t f = 0; f < faces.size(); ++f) triangles[f].v = faces[f];
  return codec_internal::CollectMeshEdges(triangles);
}

// How the colour attributes of a Draco mesh are laid out.
enum class ColorLayout { kRgb, kGrey, kDecorrelated, kNone };

void PutU32(std::vector<uint8_t>& out, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) out[at + i] = static_cast<uint8_t>(v >> (8 * i));
}
uint32_t GetU32(std::span<const uint8_t> in, size_t at) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= uint32_t{in[at + i]} << (8 * i);
  return v;
}

struct Header {
  uint8_t major = 0, minor = 0, flags = 0, flags2 = 0;
  uint8_t position_bits = 0, color_bits = 0, speed = 0;
  uint32_t vertex_count = 0, triangle_count = 0, crease_edge_count = 0, corner_count = 0;
  uint32_t draco_size = 0, tags_size = 0, crc = 0;
};

// CRC of everything except the CRC field itself.
uint32_t PayloadCrc(std::span<const uint8_t> payload) {
  uint32_t crc = Crc32(payload.subspan(0, kCrcOffset));
  return Crc32(payload.subspan(kHeaderSize), crc);
}

StatusOr<Header> ParseHeader(std::span<const uint8_t> payload, const std::string& source) {
  const std::string what = source + ": Draco payload";
  if (payload.size() < kHeaderSize)
    return Status(StatusCode::kTruncated, what + " is " + std::to_string(payload.size()) +
                                              " bytes, shorter than its 40-byte header");
  if (std::memcmp(payload.data(), kMagic, 4) != 0)
    return Status(StatusCode::kCorrupt, what + " does not start with the magic 'SDRC'");
  Header h;
  h.major = payload[4];
  h.minor = payload[5];
  h.flags = payload[6];
  h.position_bits = payload[7];
  h.color_bits = payload[8];
  h.speed = payload[9];
  if (h.minor >= 4) h.flags2 = payload[10];  // before 1.4 reserved: never read
  h.vertex_count = GetU32(payload, 12);
  h.triangle_count = GetU32(payload, 16);
  h.crease_edge_count = GetU32(payload, 20);
  h.corner_count = GetU32(payload, 24);
  h.draco_size = GetU32(payload, 28);
  h.tags_size = GetU32(payload, 32);
  h.crc = GetU32(payload, kCrcOffset);
  if (h.major != kVersionMajor || h.minor > kVersionMinor)
    return Status(h.major < kVersionMajor ? StatusCode::kCorrupt : StatusCode::kUnsupportedVersion,
                  what + " has version " + std::to_string(h.major) + "." +
                      std::to_string(h.minor) + "; this build reads versions 1.0 to 1.6");
  constexpr uint8_t kFlags11 = kFlagDecorrelated | kFlagCompactPairs | kFlagRankedStarts;
  constexpr uint8_t kFlagsUnderFirst = kFlagFeatureLayer | kFlagCompactPairs | kFlagRankedStarts;
  if ((h.flags & ~kKnownFlags) || (h.minor == 0 && (h.flags & kFlags11)) ||
      (h.minor < 2 && (h.flags & kFlagFeaturesFirst)) || (h.minor < 3 && (h.flags & kFlagMeanColors)) ||
      ((h.flags & kFlagMeanColors) && (h.flags & (kFlagDecorrelated | kFlagVertexIds)) != kFlagDecorrelated) ||
      ((h.flags & (kFlagCompactPairs | kFlagRankedStarts)) && !(h.flags & kFlagFeatureLayer)) ||
      ((h.flags & kFlagFeaturesFirst) && (h.flags & kFlagsUnderFirst) != kFlagsUnderFirst) ||
      (h.minor >= 4 && (payload[11] != 0 || (h.flags2 & ~(kFlag2Positions | kFlag2Colors)))) ||
      ((h.flags2 & kFlag2Positions) && (h.flags & kFlagVertexIds)) ||
      ((h.flags2 & kFlag2Colors) &&
       (h.minor < 5 || !(h.flags2 & kFlag2Positions) ||
        !((h.flags & kFlagMeanColors) || (h.minor >= 6 && (h.flags & kFlagGrey))))))
    return Status(StatusCode::kCorrupt, what + " (version " + std::to_string(h.major) + "." +
                                            std::to_string(h.minor) + ") has unknown flags " +
                                            std::to_string(h.flags) + ", " + std::to_string(h.flags2));
  if ((h.flags & kFlagGrey) && (h.flags & kFlagDecorrelated))
    return Status(StatusCode::kCorrupt, what + " flags both grey and decorrelated colours");

  const uint64_t expected = kHeaderSize + uint64_t{h.draco_size} + h.tags_size;
  if (payload.size() < expected)
    return Status(StatusCode::kTruncated,
                  what + " is " + std::to_string(payload.size()) + " bytes, its header says " +
                      std::to_string(expected));
  if (payload.size() > expected)
    return Status(StatusCode::kCorrupt, what + " is " + std::to_string(payload.size()) +
                                            " bytes, its header says " + std::to_string(expected));
  return h;
}

// A Draco mesh as decoded: per point its values (and original id when present), faces
// as point triples in Draco's order.
struct DecodedMesh {
  bool grey = false;  // COLOR had one component
  std::vector<Vertex> points;
  std::vector<uint32_t> ids;
  std::vector<std::array<uint32_t, 3>> faces;
};

template <typename T>
bool ReadAttribute(const draco::PointAttribute* attribute, uint32_t point, T* out) {
  const draco::AttributeValueIndex index = attribute->mapped_index(draco::PointIndex(point));
  if (index.value() >= attribute->size()) return false;
  return attribute->ConvertValue<T>(index, out);
}

// The face count that the Draco mesh's connectivity header declares, checked against the
// payload header's triangle count before Draco decodes the mesh: Draco reserves memory for
// the faces it is told of, whatever the bytes after them hold (a 266-byte payload found by
// fuzzing declared faces for 2.9 GB). Read with Draco's own header, metadata and varint
// decoders; the connectivity header is, for bitstream 2.2, edgebreaker: the traversal type
// (one byte), the encoded vertices, the faces; sequential: the faces, the points.
Status CheckDracoFaceCount(std::span<const uint8_t> bytes, uint32_t triangles, const std::string& what) {
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  draco::DracoHeader header;
  const draco::Status read = draco::PointCloudDecoder::DecodeHeader(&buffer, &header);
  if (!read.ok()) return Status(StatusCode::kDecodeFailed, what + ": " + read.error_msg_string());
  if (header.version_major != 2 || header.version_minor != 2)
    return Status(StatusCode::kDecodeFailed, what + " is Draco bitstream " + std::to_string(header.version_major) +
                                                 "." + std::to_string(header.version_minor) + "; sdvi reads 2.2");
  if (header.flags & METADATA_FLAG_MASK) {
    draco::GeometryMetadata metadata;
    if (!draco::MetadataDecoder().DecodeGeometryMetadata(&buffer, &metadata))
      return Status(StatusCode::kDecodeFailed, what + ": damaged Draco metadata");
  }
  // The traversal type and the encoded vertices are read only to reach the faces.
  uint32_t faces = 0, encoded_vertices = 0;
  uint8_t traversal = 0;
  bool ok = false;
  if (header.encoder_method == draco::MESH_EDGEBREAKER_ENCODING)
    ok = buffer.Decode(&traversal) && draco::DecodeVarint(&encoded_vertices, &buffer) &&
         draco::DecodeVarint(&faces, &buffer);
  else if (header.encoder_method == draco::MESH_SEQUENTIAL_ENCODING)
    ok = draco::DecodeVarint(&faces, &buffer);
  else
    return Status(StatusCode::kDecodeFailed, what + " has unknown Draco method " + std::to_string(header.encoder_method));
  if (!ok) return Status(StatusCode::kDecodeFailed, what + " ends inside its connectivity header");
  if (faces != triangles)
    return Status(StatusCode::kCorrupt, what + " declares " + std::to_string(faces) + " faces, the payload header " +
                                            std::to_string(triangles) + " triangles");
  return Status::Ok();
}

// positions_outside: POSITION is (0, 0) at every point (payload 1.4); colors_outside too: the
// mesh has no other attribute, the points' colours are left 0 (payload 1.5).
StatusOr<DecodedMesh> DecodeDracoMesh(std::span<const uint8_t> bytes, const std::string& source,
                                      bool decorrelated, bool mean = false, bool positions_outside = false,
                                      bool colors_outside = false) {
  const std::string what = source + ": Draco mesh";
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
  if (!type.ok())
    return Status(StatusCode::kDecodeFailed, what + ": " + type.status().error_msg_string());
  if (type.value() != draco::TRIANGULAR_MESH)
    return Status(StatusCode::kDecodeFailed, what + " is not a triangular mesh");
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok())
    return Status(StatusCode::kDecodeFailed, what + ": " + decoded.status().error_msg_string());
  const draco::Mesh& mesh = *decoded.value();
  const draco::PointAttribute* position = mesh.GetAttributeByUniqueId(kPositionUniqueId);
  const draco::PointAttribute* color = mesh.GetAttributeByUniqueId(kColorUniqueId);
  const draco::PointAttribute* id = mesh.GetAttributeByUniqueId(kVertexIdUniqueId);
  if (!position || position->attribute_type() != draco::GeometryAttribute::POSITION ||
      position->num_components() != 2)
    return Status(StatusCode::kCorrupt, what + " lacks the 2-component POSITION attribute (unique id 0)");
  if (colors_outside && mesh.num_attributes() != 1)
    return Status(StatusCode::kCorrupt, what + " has attributes besides POSITION; its colours are in the tag stream");
  if (!colors_outside && (!color || color->attribute_type() != draco::GeometryAttribute::COLOR ||
      (color->num_components() != 3 && color->num_components() != 1)))
    return Status(StatusCode::kCorrupt, what + " lacks the 3- or 1-component COLOR attribute (unique id 1)");
  const draco::PointAttribute* c1 = mesh.GetAttributeByUniqueId(kC1UniqueId);
  const draco::PointAttribute* c2 = mesh.GetAttributeByUniqueId(kC2UniqueId);
  if (decorrelated) {
    const draco::DataType type = mean ? draco::DT_INT32 : draco::DT_FLOAT32;
    auto opponent = [type](const draco::PointAttribute* a) {
      return a && a->attribute_type() == draco::GeometryAttribute::GENERIC && a->num_components() == 1 &&
             a->data_type() == type;
    };
    if (color->num_components() != 1 || (mean && color->data_type() != type) || !opponent(c1) || !opponent(c2))
      return Status(StatusCode::kCorrupt, what + " lacks the decorrelated colours its header flags (1-component "
                                                 "COLOR, GENERIC unique ids 3 and 4, " +
                                                 (mean ? "int32" : "float32") + ")");
  }
  double mean_step = 0;
  std::vector<double> mean_origin;
  if (mean) {
    const draco::GeometryMetadata* metadata = mesh.GetMetadata();
    if (!metadata || !metadata->GetEntryDouble(kMeanStepKey, &mean_step) ||
        !metadata->GetEntryDoubleArray(kMeanOriginKey, &mean_origin) || mean_origin.size() != 3 ||
        !(mean_step > 0) || !std::isfinite(mean_step) ||
        !std::all_of(mean_origin.begin(), mean_origin.end(), [](double o) { return std::isfinite(o); }))
      return Status(StatusCode::kCorrupt, what + " lacks the colour grid (metadata " + kMeanStepKey + " > 0, " +
                                              kMeanOriginKey + " of 3 finite values) its header flags");
  }
  std::vector<std::array<int64_t, 3>> residuals(mean ? mesh.num_points() : 0);
  if (id && (id->attribute_type() != draco::GeometryAttribute::GENERIC ||
             id->num_components() != 1 || id->data_type() != draco::DT_UINT32))
    return Status(StatusCode::kCorrupt, what + ": attribute unique id 2 is not a 1-component uint32 GENERIC");
  DecodedMesh out;
  out.grey = !colors_outside && color->num_components() == 1 && !decorrelated;
  const uint32_t n = mesh.num_points();
  out.points.resize(n);
  if (id) out.ids.resize(n);
  for (uint32_t p = 0; p < n; ++p) {
    float xy[2] = {0.f, 0.f}, rgb[3] = {0.f, 0.f, 0.f};
    bool color_ok = colors_outside || ReadAttribute(color, p, rgb);  // 1 or 3 components
    if (out.grey) rgb[1] = rgb[2] = rgb[0];
    if (mean) {
      int32_t r[3] = {0, 0, 0};
      color_ok = ReadAttribute(color, p, &r[0]) && ReadAttribute(c1, p, &r[1]) && ReadAttribute(c2, p, &r[2]);
      residuals[p] = {r[0], r[1], r[2]};
    } else if (decorrelated) {
      color_ok = color_ok && ReadAttribute(c1, p, &rgb[1]) && ReadAttribute(c2, p, &rgb[2]);
      const std::array<float, 3> back = FromDecorrelated(rgb[0], rgb[1], rgb[2]);
      std::copy(back.begin(), back.end(), rgb);
    }
    if (!ReadAttribute(position, p, xy) || !color_ok ||
        (id && !ReadAttribute(id, p, &out.ids[p])))
      return Status(StatusCode::kCorrupt, what + ": point " + std::to_string(p) +
                                              " has no attribute value");
    if (positions_outside && (xy[0] != 0.f || xy[1] != 0.f))  // the positions follow in the tag stream
      return Status(StatusCode::kCorrupt, what + ": point " + std::to_string(p) + "'s POSITION is not (0, 0)");
    out.points[p] = {xy[0], xy[1], rgb[0], rgb[1], rgb[2]};
  }
  out.faces.resize(mesh.num_faces());
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    const auto& face = mesh.face(draco::FaceIndex(f));
    for (int k = 0; k < 3; ++k) {
      if (face[k].value() >= n)
        return Status(StatusCode::kCorrupt, what + ": face " + std::to_string(f) +
                                                " names point " + std::to_string(face[k].value()));
      out.faces[f][k] = face[k].value();
    }
  }
  if (mean) {
    // The grid indices point by point from the residuals, then L, C1, C2 on the grids.
    const auto earlier = codec_internal::EarlierNeighbours(n, FaceEdges(out.faces));
    std::vector<std::array<int64_t, 3>> q(n);
    const std::array<double, 3> origin = {mean_origin[0], mean_origin[1], mean_origin[2]};
    for (uint32_t p = 0; p < n; ++p) {
      bool on_grid = true;
      for (int k = 0; k < 3; ++k) {
        q[p][k] = codec_internal::MeanPrediction(earlier[p], q, p, k) + residuals[p][k];
        on_grid = on_grid && std::abs(q[p][k]) <= codec_internal::kMaxColorIndex;
      }
      if (!on_grid || !ColorFromGrid(origin, mean_step, q[p], &out.points[p]))
        return Status(StatusCode::kCorrupt, what + ": point " + std::to_string(p) + "'s colour lies off its grid");
    }
  }
  return out;
}

// Neighbour-mean colours (payload 1.3 and 1.5): L, C1, C2 on grids of step from their minimums,
// the indices in the decoded order (vertex i is point decoded_index[i]), and their residuals
// (index minus MeanPrediction over the earlier neighbours in that order).
struct MeanColors {
  codec_internal::ColorStream grid;
  std::vector<std::array<int32_t, 3>> residuals;  // per point
};

// Fails (kInvalidArgument) when a residual does not fit int32.
StatusOr<MeanColors> MeanColorIndices(const Image& image, const std::vector<uint32_t>& decoded_index, double step) {
  const uint32_t n = static_cast<uint32_t>(image.vertices.size());
  MeanColors out;
  std::vector<std::array<float, 3>> lcc(n);
  std::array<float, 3>& origin = out.grid.origin;
  origin.fill(std::numeric_limits<float>::infinity());
  for (uint32_t i = 0; i < n; ++i) {
    lcc[i] = ToDecorrelated(image.vertices[i]);
    for (int k = 0; k < 3; ++k) origin[k] = std::min(origin[k], lcc[i][k]);
  }
  out.grid.step = step;
  std::vector<std::array<int64_t, 3>>& q = out.grid.q;
  q.resize(n);
  for (uint32_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k)
      q[decoded_index[i]][k] = std::llround((double(lcc[i][k]) - double(origin[k])) / step);
  std::vector<std::array<uint32_t, 3>> faces(image.triangles.size());
  for (size_t t = 0; t < faces.size(); ++t)
    for (int k = 0; k < 3; ++k) faces[t][k] = decoded_index[image.triangles[t].v[k]];
  const auto earlier = codec_internal::EarlierNeighbours(n, FaceEdges(faces));
  out.residuals.resize(n);
  for (uint32_t p = 0; p < n; ++p)
    for (int k = 0; k < 3; ++k) {
      const int64_t r = q[p][k] - codec_internal::MeanPrediction(earlier[p], q, p, k);
      if (r < std::numeric_limits<int32_t>::min() || r > std::numeric_limits<int32_t>::max())
        return Status(StatusCode::kInvalidArgument, "a colour residual does not fit 32 bits");
      out.residuals[p][k] = static_cast<int32_t>(r);
    }
  return out;
}

// A grey image's colour stream (payload 1.6): the grey value on a grid of step from its minimum,
// the indices in the decoded order (vertex i is point decoded_index[i]). Fails
// (kInvalidArgument) when an index exceeds 2^30 (its residuals must stay below 2^31).
StatusOr<codec_internal::ColorStream> GreyColorIndices(const Image& image, const std::vector<uint32_t>& decoded_index,
                                                      double step) {
  codec_internal::ColorStream out;
  out.components = 1;
  out.step = step;
  out.origin.fill(0.f);
  float origin = std::numeric_limits<float>::infinity();
  for (const Vertex& v : image.vertices) origin = std::min(origin, v.r);
  out.origin[0] = origin;
  out.q.assign(image.vertices.size(), {0, 0, 0});
  for (size_t i = 0; i < image.vertices.size(); ++i) {
    const double q = std::round((double(image.vertices[i].r) - double(origin)) / step);
    if (!(q >= 0 && q <= double(int64_t{1} << 30)))
      return Status(StatusCode::kInvalidArgument, "a grey colour index exceeds 2^30");
    out.q[decoded_index[i]][0] = static_cast<int64_t>(q);
  }
  return out;
}

// The Draco mesh of image's control mesh (no vertex ids) with neighbour-mean colours (payload
// 1.3): the positions, and per vertex the residuals of colors (vertex i is point
// decoded_index[i]), the grid in the metadata.
std::unique_ptr<draco::Mesh> BuildMeanColorMesh(const Image& image, const MeanColors& colors,
                                                const std::vector<uint32_t>& decoded_index,
                                                bool index_positions = false) {
  const uint32_t n = static_cast<uint32_t>(image.vertices.size());
  auto mesh = std::make_unique<draco::Mesh>();
  mesh->set_num_points(n);
  draco::GeometryAttribute position;
  position.Init(draco::GeometryAttribute::POSITION, nullptr, 2, draco::DT_FLOAT32, false, 2 * sizeof(float), 0);
  const int position_id = mesh->AddAttribute(position, true, n);
  mesh->attribute(position_id)->set_unique_id(kPositionUniqueId);
  int ids[3];
  const uint32_t unique_ids[3] = {kColorUniqueId, kC1UniqueId, kC2UniqueId};
  for (int k = 0; k < 3; ++k) {
    draco::GeometryAttribute residual;
    residual.Init(k == 0 ? draco::GeometryAttribute::COLOR : draco::GeometryAttribute::GENERIC, nullptr, 1,
                  draco::DT_INT32, false, sizeof(int32_t), 0);
    ids[k] = mesh->AddAttribute(residual, true, n);
    mesh->attribute(ids[k])->set_unique_id(unique_ids[k]);
  }
  for (uint32_t i = 0; i < n; ++i) {
    const Vertex& v = image.vertices[i];
    const float xy[2] = {v.x, v.y};
    const uint32_t p = decoded_index[i];
    const float zero[2] = {0.f, 0.f};
    mesh->attribute(position_id)->SetAttributeValue(draco::AttributeValueIndex(i), index_positions ? zero : xy);
    for (int k = 0; k < 3; ++k)
      mesh->attribute(ids[k])->SetAttributeValue(draco::AttributeValueIndex(i), &colors.residuals[p][k]);
  }
  mesh->SetNumFaces(image.triangles.size());
  for (size_t t = 0; t < image.triangles.size(); ++t) {
    const auto& tri = image.triangles[t].v;
    mesh->SetFace(draco::FaceIndex(static_cast<uint32_t>(t)),
                  {draco::PointIndex(tri[0]), draco::PointIndex(tri[1]), draco::PointIndex(tri[2])});
  }
  auto metadata = std::make_unique<draco::GeometryMetadata>();
  const auto& origin = colors.grid.origin;
  metadata->AddEntryDouble(kMeanStepKey, colors.grid.step);
  metadata->AddEntryDoubleArray(kMeanOriginKey, std::vector<double>(origin.begin(), origin.end()));
  mesh->AddMetadata(std::move(metadata));
  return mesh;
}

// A mesh of BuildMeanColorMesh: positions at position_bits, the residuals as they are (no
// quantization, no prediction).
StatusOr<std::vector<uint8_t>> EncodeMeanColorMesh(const draco::Mesh& mesh, int position_bits, int speed) {
  draco::ExpertEncoder encoder(mesh);
  for (int a = 0; a < mesh.num_attributes(); ++a) {
    const draco::PointAttribute& attribute = *mesh.attribute(a);
    if (attribute.attribute_type() == draco::GeometryAttribute::POSITION && attribute.data_type() == draco::DT_INT32)
      encoder.SetAttributePredictionScheme(a, draco::PREDICTION_DIFFERENCE);  // the decoded index (payload 1.4)
    else if (attribute.attribute_type() == draco::GeometryAttribute::POSITION)
      encoder.SetAttributeQuantization(a, position_bits);
    else
      encoder.SetAttributePredictionScheme(a, draco::PREDICTION_NONE);
  }
  encoder.SetSpeedOptions(speed, speed);
  encoder.SetEncodingMethod(draco::MESH_EDGEBREAKER_ENCODING);
  draco::EncoderBuffer buffer;
  const draco::Status status = encoder.EncodeToBuffer(&buffer);
  if (!status.ok()) return Status(StatusCode::kEncodeFailed, "Draco encoder: " + status.error_msg_string());
  const auto* data = reinterpret_cast<const uint8_t*>(buffer.data());
  return std::vector<uint8_t>(data, data + buffer.size());
}

// The Draco mesh of image's control mesh, with or without the vertex id attribute.
// With index_of (positions in the tag stream, payload 1.4) POSITION is one int32 per vertex:
// its index in the decoded order, (*index_of)[i].
std::unique_ptr<draco::Mesh> BuildDracoMesh(const Image& image, bool with_ids, ColorLayout layout,
                                            const std::vector<uint32_t>* index_of = nullptr) {
  const bool grey = layout == ColorLayout::kGrey;
  const bool with_color = layout != ColorLayout::kNone;
  const bool decorrelated = layout == ColorLayout::kDecorrelated;
  auto mesh = std::make_unique<draco::Mesh>();
  const uint32_t n = static_cast<uint32_t>(image.vertices.size());
  mesh->set_num_points(n);
  draco::GeometryAttribute position;
  position.Init(draco::GeometryAttribute::POSITION, nullptr, 2, draco::DT_FLOAT32, false,
                2 * sizeof(float), 0);
  draco::GeometryAttribute color;
  const int color_components = grey || decorrelated ? 1 : 3;
  color.Init(draco::GeometryAttribute::COLOR, nullptr, color_components, draco::DT_FLOAT32, false,
             color_components * sizeof(float), 0);
  const int position_id = mesh->AddAttribute(position, true, n);
  mesh->attribute(position_id)->set_unique_id(kPositionUniqueId);
  const int color_id = with_color ? mesh->AddAttribute(color, true, n) : -1;
  if (with_color) mesh->attribute(color_id)->set_unique_id(kColorUniqueId);
  int c1_id = -1, c2_id = -1;
  if (decorrelated) {
    draco::GeometryAttribute opponent;
    opponent.Init(draco::GeometryAttribute::GENERIC, nullptr, 1, draco::DT_FLOAT32, false, sizeof(float), 0);
    c1_id = mesh->AddAttribute(opponent, true, n);
    mesh->attribute(c1_id)->set_unique_id(kC1UniqueId);
    c2_id = mesh->AddAttribute(opponent, true, n);
    mesh->attribute(c2_id)->set_unique_id(kC2UniqueId);
  }
  int id_id = -1;
  if (with_ids) {
    draco::GeometryAttribute id;
    id.Init(draco::GeometryAttribute::GENERIC, nullptr, 1, draco::DT_UINT32, false,
            sizeof(uint32_t), 0);
    id_id = mesh->AddAttribute(id, true, n);
    mesh->attribute(id_id)->set_unique_id(kVertexIdUniqueId);
  }
  for (uint32_t i = 0; i < n; ++i) {
    const Vertex& v = image.vertices[i];
    const float xy[2] = {v.x, v.y};
    const float rgb[3] = {v.r, v.g, v.b};
    const float zero[2] = {0.f, 0.f};
    mesh->attribute(position_id)->SetAttributeValue(draco::AttributeValueIndex(i), index_of ? zero : xy);
    if (decorrelated) {
      const std::array<float, 3> lcc = ToDecorrelated(v);
      mesh->attribute(color_id)->SetAttributeValue(draco::AttributeValueIndex(i), &lcc[0]);
      mesh->attribute(c1_id)->SetAttributeValue(draco::AttributeValueIndex(i), &lcc[1]);
      mesh->attribute(c2_id)->SetAttributeValue(draco::AttributeValueIndex(i), &lcc[2]);
    } else if (with_color) {
      mesh->attribute(color_id)->SetAttributeValue(draco::AttributeValueIndex(i), rgb);
    }
    if (with_ids) mesh->attribute(id_id)->SetAttributeValue(draco::AttributeValueIndex(i), &i);
  }
  mesh->SetNumFaces(image.triangles.size());
  for (size_t t = 0; t < image.triangles.size(); ++t) {
    const auto& tri = image.triangles[t].v;
    mesh->SetFace(draco::FaceIndex(static_cast<uint32_t>(t)),
                  {draco::PointIndex(tri[0]), draco::PointIndex(tri[1]), draco::PointIndex(tri[2])});
  }
  return mesh;
}

StatusOr<std::vector<uint8_t>> EncodeDracoMesh(const draco::Mesh& mesh, int method,
                                               int position_bits, int color_bits, int speed) {
  draco::Encoder encoder;
  if (mesh.GetNamedAttribute(draco::GeometryAttribute::POSITION)->data_type() == draco::DT_INT32)
    encoder.SetAttributePredictionScheme(draco::GeometryAttribute::POSITION, draco::PREDICTION_DIFFERENCE);
  else
    encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, position_bits);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::COLOR, color_bits);
  encoder.SetSpeedOptions(speed, speed);
  encoder.SetEncodingMethod(method);
  draco::EncoderBuffer buffer;
  const draco::Status status = encoder.EncodeMeshToBuffer(mesh, &buffer);
  if (!status.ok())
    return Status(StatusCode::kEncodeFailed, "Draco encoder: " + status.error_msg_string());
  const auto* data = reinterpret_cast<const uint8_t*>(buffer.data());
  return std::vector<uint8_t>(data, data + buffer.size());
}

// A mesh of BuildDracoMesh(kDecorrelated): positions at position_bits as EncodeDracoMesh
// does; L, C1, C2 each on its own grid of step color_step from its minimum (Draco's
// explicit quantization, enough bits to cover its extent), predicted by difference.
StatusOr<std::vector<uint8_t>> EncodeDecorrelatedMesh(const draco::Mesh& mesh, int method, int position_bits,
                                                      double color_step, int speed) {
  draco::ExpertEncoder encoder(mesh);
  for (int a = 0; a < mesh.num_attributes(); ++a) {
    const draco::PointAttribute& attribute = *mesh.attribute(a);
    if (attribute.attribute_type() == draco::GeometryAttribute::POSITION) {
      if (attribute.data_type() == draco::DT_INT32)  // the decoded index (payload 1.4)
        encoder.SetAttributePredictionScheme(a, draco::PREDICTION_DIFFERENCE);
      else
        encoder.SetAttributeQuantization(a, position_bits);
      continue;
    }
    if (attribute.data_type() != draco::DT_FLOAT32) continue;  // the vertex ids: lossless
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (draco::AttributeValueIndex i(0); i < attribute.size(); ++i) {
      float value = 0;
      attribute.GetValue(i, &value);
      lo = std::min(lo, value);
      hi = std::max(hi, value);
    }
    // One step of margin above the extent against float rounding of the range.
    const double levels = std::max(double(hi) - double(lo), 0.0) / color_step + 2;
    const int bits = std::max(1, static_cast<int>(std::ceil(std::log2(levels))));
    if (bits > kMaxQuantizationBits)
      return Status(StatusCode::kInvalidArgument, "decorrelated colours need more than " +
                                                      std::to_string(kMaxQuantizationBits) + " bits");
    encoder.SetAttributeExplicitQuantization(a, bits, 1, &lo,
                                             static_cast<float>(color_step * double((1u << bits) - 1)));
    encoder.SetAttributePredictionScheme(a, draco::PREDICTION_DIFFERENCE);
  }
  encoder.SetSpeedOptions(speed, speed);
  encoder.SetEncodingMethod(method);
  draco::EncoderBuffer buffer;
  const draco::Status status = encoder.EncodeToBuffer(&buffer);
  if (!status.ok())
    return Status(StatusCode::kEncodeFailed, "Draco encoder: " + status.error_msg_string());
  const auto* data = reinterpret_cast<const uint8_t*>(buffer.data());
  return std::vector<uint8_t>(data, data + buffer.size());
}

// Largest per-component extent of the positions (xy) or colours (rgb): Draco's range.
double AttributeRange(const Image& image, bool colors, double* max_abs) {
  const int n = colors ? 3 : 2;
  double lo[3], hi[3];
  std::fill(lo, lo + 3, std::numeric_limits<double>::infinity());
  std::fill(hi, hi + 3, -std::numeric_limits<double>::infinity());
  *max_abs = 0;
  for (const Vertex& v : image.vertices) {
    const float c[5] = {v.x, v.y, v.r, v.g, v.b};
    for (int k = 0; k < n; ++k) {
      const double value = c[(colors ? 2 : 0) + k];
      lo[k] = std::min(lo[k], value);
      hi[k] = std::max(hi[k], value);
      *max_abs = std::max(*max_abs, std::abs(value));
    }
  }
  double range = 0;
  for (int k = 0; k < n && !image.vertices.empty(); ++k) range = std::max(range, hi[k] - lo[k]);
  return range > 0 ? range : 1.0;
}

// Quantization defaults (codec.h, DefaultPositionBits / DefaultColorBits).
constexpr double kPositionStep = 1.0 / 128;   // px, without a reference MSE
constexpr double kColorStep = 0.125;          // 8-bit levels, without a reference MSE
constexpr double kMinPositionStep = 1.0 / 512, kMaxPositionStep = 0.25;  // px, with one
constexpr double kMinColorStep = 1.0 / 32, kMaxColorStep = 4.0;          // levels, with one
constexpr double kErrorBudget = 0.01;         // added MSE / reference MSE (0.043 dB)
constexpr double kPositionMseFactor = 13.0;   // added MSE per squared position step
constexpr double kColorMseFactor = 1.0 / 24;  // added MSE per squared colour step

int BitsForStep(double extent, double step) {
  const double levels = extent / step + 1;
  const int bits = static_cast<int>(std::ceil(std::log2(std::max(levels, 2.0))));
  return std::clamp(bits, 8, kMaxQuantizationBits);
}

// image as ValidateImage expects it: crease edges and corners sorted and unique (the
// codec accepts them in any order), the feature layer dropped when it does not travel.
// A copy only when one of those applies.
class ValidationView {
 public:
  ValidationView(const Image& image, bool feature_layer) : image_(&image) {
    const bool sets_normal =
        std::is_sorted(image.crease_edges.begin(), image.crease_edges.end()) &&
        std::adjacent_find(image.crease_edges.begin(), image.crease_edges.end()) == image.crease_edges.end() &&
        std::all_of(image.crease_edges.begin(), image.crease_edges.end(), [](const Edge& e) { return e.a < e.b; }) &&
        std::is_sorted(image.corners.begin(), image.corners.end()) &&
        std::adjacent_find(image.corners.begin(), image.corners.end()) == image.corners.end();
    const bool drop_features = !feature_layer && (!image.polylines.empty() || !image.pairs.empty());
    if (sets_normal && !drop_features) return;
    copy_ = image;
    for (Edge& e : copy_.crease_edges) e = Edge::Of(e.a, e.b);
    std::sort(copy_.crease_edges.begin(), copy_.crease_edges.end());
    copy_.crease_edges.erase(std::unique(copy_.crease_edges.begin(), copy_.crease_edges.end()),
                             copy_.crease_edges.end());
    std::sort(copy_.corners.begin(), copy_.corners.end());
    copy_.corners.erase(std::unique(copy_.corners.begin(), copy_.corners.end()), copy_.corners.end());
    if (drop_features) {
      copy_.polylines.clear();
      copy_.pairs.clear();
    }
    image_ = &copy_;
  }
  operator const Image&() const { return *image_; }  // NOLINT: a view by design

 private:
  const Image* image_;
  Image copy_;
};

Status ValidateForEncoding(const Image& image, bool feature_layer) {
  const size_t n = image.vertices.size();
  if (n == 0 || image.triangles.empty())
    return Status(StatusCode::kEmptyInput, "image to compress has no vertices or no triangles");
  if (n > std::numeric_limits<uint32_t>::max() / 2 ||
      image.triangles.size() > std::numeric_limits<uint32_t>::max() / 4)
    return Status(StatusCode::kLimitExceeded, "image to compress is too large for a Draco payload");
  // The one validation of every reader and writer: values a real image has, a manifold,
  // unfolded mesh (on the sets in normal form, and without the feature layer when it
  // does not travel). Then what the payload needs besides.
  SDVI_RETURN_IF_ERROR(ValidateImage(ValidationView(image, feature_layer), "image to compress"));
  for (size_t t = 0; t < image.triangles.size(); ++t)
    for (uint32_t v : image.triangles[t].v)
      if (v >= n)
        return Status(StatusCode::kIndexOutOfRange,
                      "image to compress: triangle " + std::to_string(t) + " names vertex " +
                          std::to_string(v) + " of " + std::to_string(n));
  for (uint32_t c : image.corners)
    if (c >= n)
      return Status(StatusCode::kIndexOutOfRange,
                    "image to compress: corner " + std::to_string(c) + " of " + std::to_string(n) +
                        " vertices");
  for (const Edge& e : image.crease_edges)
    if (e.a >= e.b || e.b >= n)
      return Status(StatusCode::kIndexOutOfRange,
                    "image to compress: crease edge (" + std::to_string(e.a) + ", " +
                        std::to_string(e.b) + ") is not a vertex pair a < b < " + std::to_string(n));
  return Status::Ok();
}

Status ValidateFeatureLayer(const Image& image) {
  const size_t n = image.vertices.size();
  for (size_t p = 0; p < image.polylines.size(); ++p)
    for (uint32_t v : image.polylines[p].vertices)
      if (v >= n)
        return Status(StatusCode::kIndexOutOfRange,
                      "image to compress: feature polyline " + std::to_string(p) + " names vertex " +
                          std::to_string(v) + " of " + std::to_string(n));
  for (const FeaturePair& pair : image.pairs)
    if (pair.first >= image.polylines.size() || pair.second >= image.polylines.size())
      return Status(StatusCode::kIndexOutOfRange,
                    "image to compress: a feature pair names polyline " +
                        std::to_string(std::max(pair.first, pair.second)) + " of " +
                        std::to_string(image.polylines.size()));
  return Status::Ok();
}

// True when decoded (with ids) is image up to quantization, vertex order and triangle
// order and rotation.
bool MapsBack(const DecodedMesh& decoded, const Image& image, const ErrorBound& bound) {
  const size_t n = image.vertices.size();
  if (decoded.ids.size() != decoded.points.size()) return false;
  std::vector<char> seen(n, 0);
  for (size_t p = 0; p < decoded.points.size(); ++p) {
    const uint32_t id = decoded.ids[p];
    if (id >= n) return false;
    seen[id] = 1;
    const Vertex& a = decoded.points[p];
    const Vertex& b = image.vertices[id];
    if (std::abs(a.x - b.x) > bound.position || std::abs(a.y - b.y) > bound.position ||
        std::abs(a.r - b.r) > bound.color || std::abs(a.g - b.g) > bound.color ||
        std::abs(a.b - b.b) > bound.color)
      return false;
  }
  if (std::find(seen.begin(), seen.end(), 0) != seen.end()) return false;
  if (decoded.faces.size() != image.triangles.size()) return false;
  std::vector<Triangle> got(decoded.faces.size());
  for (size_t f = 0; f < decoded.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) got[f].v[k] = decoded.ids[decoded.faces[f][k]];
  std::vector<Triangle> want = image.triangles;
  CanonicalizeTriangles(&got);
  CanonicalizeTriangles(&want);
  return got == want;
}

bool SameMesh(const DecodedMesh& a, const DecodedMesh& b) {
  return a.points == b.points && a.faces == b.faces;
}

// Whether decoded faces (point triples) are image's triangles with vertex i as point order[i],
// in any order and rotation.
bool FacesInOrder(const std::vector<std::array<uint32_t, 3>>& faces, const Image& image,
                  const std::vector<uint32_t>& order) {
  if (faces.size() != image.triangles.size()) return false;
  std::vector<Triangle> got(faces.size()), want(image.triangles.size());
  for (size_t f = 0; f < got.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      got[f].v[k] = faces[f][k];
      want[f].v[k] = order[image.triangles[f].v[k]];
    }
  CanonicalizeTriangles(&got);
  CanonicalizeTriangles(&want);
  return got == want;
}

}  // namespace

int DefaultPositionBits(const Image& image, double reference_mse) {
  double max_abs = 0;
  const double extent = std::max({double(image.width), double(image.height),
                                  image.vertices.empty() ? 0.0 : AttributeRange(image, false, &max_abs)});
  double step = kPositionStep;
  if (reference_mse > 0)
    step = std::clamp(std::sqrt(kErrorBudget * reference_mse / (2 * kPositionMseFactor)), kMinPositionStep,
                      kMaxPositionStep);
  return BitsForStep(extent, step);
}

int DefaultColorBits(const Image& image, double reference_mse) {
  double max_abs = 0;
  double step = kColorStep;
  if (reference_mse > 0)
    step = std::clamp(std::sqrt(kErrorBudget * reference_mse / (2 * kColorMseFactor)), kMinColorStep,
                      kMaxColorStep);
  return BitsForStep(AttributeRange(image, true, &max_abs), step);
}

ErrorBound CompressionErrorBound(const Image& image, int position_bits, int color_bits, bool decorrelated) {
  // Half a step, plus the float rounding of Draco's dequantization (min + q * step).
  auto bound = [&](bool colors, int bits) {
    double max_abs = 0;
    const double range = AttributeRange(image, colors, &max_abs);
    const double step = range / double((uint64_t{1} << bits) - 1);
    if (colors && decorrelated)  // three components of up to sqrt(3) max_abs, each rounded
      return kDecorrelatedErrorFactor * (0.5 * step + 16 * FLT_EPSILON * (max_abs + range + step));
    return 0.5 * step + 4 * FLT_EPSILON * (max_abs + range);
  };
  return {bound(false, position_bits), bound(true, color_bits)};
}

void CanonicalizeTriangles(std::vector<Triangle>* triangles) {
  for (Triangle& t : *triangles) {
    const int k = static_cast<int>(std::min_element(t.v.begin(), t.v.end()) - t.v.begin());
    std::rotate(t.v.begin(), t.v.begin() + k, t.v.end());
  }
  std::sort(triangles->begin(), triangles->end(),
            [](const Triangle& a, const Triangle& b) { return a.v < b.v; });
}

Status RenumberVertices(const std::vector<uint32_t>& new_index_of_vertex, Image* image) {
  const size_t n = image->vertices.size();
  if (new_index_of_vertex.size() != n)
    return Status(StatusCode::kInvalidArgument,
                  "vertex renumbering has " + std::to_string(new_index_of_vertex.size()) +
                      " entries for " + std::to_string(n) + " vertices");
  std::vector<Vertex> vertices(n);
  std::vector<char> used(n, 0);
  for (size_t i = 0; i < n; ++i) {
    const uint32_t j = new_index_of_vertex[i];
    if (j >= n || used[j])
      return Status(StatusCode::kInvalidArgument, "vertex renumbering is not a permutation");
    used[j] = 1;
    vertices[j] = image->vertices[i];
  }
  auto map = [&](uint32_t v) { return v < n ? new_index_of_vertex[v] : v; };
  image->vertices = std::move(vertices);
  for (Triangle& t : image->triangles)
    for (uint32_t& v : t.v) v = map(v);
  for (Edge& e : image->crease_edges) e = Edge::Of(map(e.a), map(e.b));
  std::sort(image->crease_edges.begin(), image->crease_edges.end());
  for (uint32_t& c : image->corners) c = map(c);
  std::sort(image->corners.begin(), image->corners.end());
  for (FeaturePolyline& p : image->polylines)
    for (uint32_t& v : p.vertices) v = map(v);
  return Status::Ok();
}

StatusOr<std::vector<uint8_t>> EncodeDracoPayload(const Image& image, const CompressOptions& options,
                                                  std::vector<uint32_t>* new_index_of_vertex) {
  const std::string bit_range = " not in 1.." + std::to_string(kMaxQuantizationBits) + " (0 = default)";
  if (options.position_bits < 0 || options.position_bits > kMaxQuantizationBits)
    return Status(StatusCode::kInvalidArgument,
                  "position bits " + std::to_string(options.position_bits) + bit_range);
  if (options.color_bits < 0 || options.color_bits > kMaxQuantizationBits)
    return Status(StatusCode::kInvalidArgument,
                  "colour bits " + std::to_string(options.color_bits) + bit_range);
  if (options.speed < 0 || options.speed > 10)
    return Status(StatusCode::kInvalidArgument,
                  "speed " + std::to_string(options.speed) + " not in 0..10");
  SDVI_RETURN_IF_ERROR(ValidateForEncoding(image, options.feature_layer));
  if (options.feature_layer) SDVI_RETURN_IF_ERROR(ValidateFeatureLayer(image));
  const uint32_t n = static_cast<uint32_t>(image.vertices.size());

  // Crease edges and corners: sorted, unique, crease edges on the mesh.
  std::vector<Edge> creases = image.crease_edges;
  std::sort(creases.begin(), creases.end());
  creases.erase(std::unique(creases.begin(), creases.end()), creases.end());
  std::vector<uint32_t> corners = image.corners;
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  {
    const std::vector<MeshEdge> edges = codec_internal::CollectMeshEdges(image.triangles);
    for (const Edge& e : creases) {
      const auto it = std::lower_bound(edges.begin(), edges.end(), e, [](const MeshEdge& m, const Edge& x) {
        return m.a != x.a ? m.a < x.a : m.b < x.b;
      });
      if (it == edges.end() || it->a != e.a || it->b != e.b)
        return Status(StatusCode::kCreaseNotAnEdge,
                      "image to compress: crease edge (" + std::to_string(e.a) + ", " +
                          std::to_string(e.b) + ") is not an edge of any triangle");
    }
  }

  if (!(options.reference_mse >= 0) || !std::isfinite(options.reference_mse))
    return Status(StatusCode::kInvalidArgument, "reference MSE must be finite and >= 0");
  const int position_bits =
      options.position_bits ? options.position_bits : DefaultPositionBits(image, options.reference_mse);
  const int color_bits =
      options.color_bits ? options.color_bits : DefaultColorBits(image, options.reference_mse);
  const bool grey = std::all_of(image.vertices.begin(), image.vertices.end(), [](const Vertex& v) {
    return std::memcmp(&v.r, &v.g, sizeof(float)) == 0 && std::memcmp(&v.r, &v.b, sizeof(float)) == 0;
  });
  // Draco's quantiser divides 2^bits - 1 by an attribute's span in float (its Quantizer):
  // below 2^(bits - 126) the quotient overflows and the quantised values are garbage, on
  // which its encoder reads out of bounds. No real image comes near (spans of pixels and
  // colour levels); the decorrelated colours' step, span / (2^bits - 1), then stays a normal
  // float too.
  double max_abs = 0;
  const double position_span = AttributeRange(image, false, &max_abs);
  const double color_span = AttributeRange(image, true, &max_abs);
  for (const bool colors : {false, true}) {
    const double span = colors ? color_span : position_span;
    const int bits = colors ? color_bits : position_bits;
    if (span < std::ldexp(1.0, bits - 126)) {
      char text[200];
      std::snprintf(text, sizeof text,
                    "image to compress: its %s span %g, too small to quantise at %d bits (Draco needs at "
                    "least %g)",
                    colors ? "colours" : "positions", span, bits, std::ldexp(1.0, bits - 126));
      return Status(StatusCode::kEncodeFailed, text);
    }
  }
  const double color_step = color_span / double((uint64_t{1} << color_bits) - 1);

  // The Draco mesh with colours laid out one way. Try, in order: edgebreaker without ids
  // (decoded order = Draco's), edgebreaker with ids, sequential with ids. Each candidate
  // is decoded and checked before it is kept.
  struct DracoMesh {
    std::vector<uint8_t> bytes;
    std::vector<uint32_t> renumbering;  // empty: the identity
    bool with_ids = true;
    std::vector<Vertex> decoded;  // what the reader gets, in the decoded vertex numbering
  };
  // The decoded mesh's vertices as the reader numbers them (DecodeDracoPayload).
  auto decoded_vertices = [n](const DecodedMesh& mesh) {
    std::vector<Vertex> out(n);
    for (size_t p = 0; p < mesh.points.size(); ++p) out[mesh.ids.empty() ? p : mesh.ids[p]] = mesh.points[p];
    return out;
  };
  auto encode_layout = [&](ColorLayout layout) -> StatusOr<DracoMesh> {
    const bool decorrelated = layout == ColorLayout::kDecorrelated;
    const ErrorBound bound = CompressionErrorBound(image, position_bits, color_bits, decorrelated);
    auto encode = [&](const draco::Mesh& mesh, int method) {
      return decorrelated ? EncodeDecorrelatedMesh(mesh, method, position_bits, color_step, options.speed)
                          : EncodeDracoMesh(mesh, method, position_bits, color_bits, options.speed);
    };
    DracoMesh out;
    const std::string self = "compressed image (self-check)";
    if (options.speed < 10) {
      auto mesh_ids = BuildDracoMesh(image, true, layout);
      SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes_ids, encode(*mesh_ids, draco::MESH_EDGEBREAKER_ENCODING));
      StatusOr<DecodedMesh> decoded_ids = DecodeDracoMesh(bytes_ids, self, decorrelated);
      if (decoded_ids.ok() && MapsBack(*decoded_ids, image, bound)) {
        if (!options.keep_vertex_order && decoded_ids->points.size() == n) {
          auto mesh_plain = BuildDracoMesh(image, false, layout);
          StatusOr<std::vector<uint8_t>> bytes_plain = encode(*mesh_plain, draco::MESH_EDGEBREAKER_ENCODING);
          if (bytes_plain.ok()) {
            StatusOr<DecodedMesh> decoded_plain = DecodeDracoMesh(*bytes_plain, self, decorrelated);
            if (decoded_plain.ok() && SameMesh(*decoded_plain, *decoded_ids)) {
              out.bytes = std::move(bytes_plain).value();
              out.decoded = decoded_vertices(*decoded_plain);
              out.renumbering.assign(n, 0);
              for (uint32_t p = 0; p < n; ++p) out.renumbering[decoded_ids->ids[p]] = p;
              out.with_ids = false;
            }
          }
        }
        if (out.with_ids) {
          out.bytes = std::move(bytes_ids);
          out.decoded = decoded_vertices(*decoded_ids);
        }
      }
    }
    if (out.bytes.empty()) {
      auto mesh_ids = BuildDracoMesh(image, true, layout);
      SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, encode(*mesh_ids, draco::MESH_SEQUENTIAL_ENCODING));
      StatusOr<DecodedMesh> decoded = DecodeDracoMesh(bytes, self, decorrelated);
      if (!decoded.ok())
        return Status(StatusCode::kEncodeFailed,
                      "Draco cannot decode its own encoding of the image to compress (" +
                          decoded.status().message() + ")");
      if (!MapsBack(*decoded, image, bound))
        return Status(StatusCode::kEncodeFailed,
                      "Draco does not reproduce the control mesh of the image to compress");
      out.bytes = std::move(bytes);
      out.decoded = decoded_vertices(*decoded);
    }
    return out;
  };

  // The colours predicted by the mean of the neighbours decoded before (payload 1.3), in the
  // decoded order of reference (a mesh without vertex ids): decoded and checked against it
  // (the same points and faces, colours within the decorrelated bound) before it is kept.
  auto encode_mean = [&](const DracoMesh& reference) -> StatusOr<DracoMesh> {
    const std::string self = "compressed image (self-check)";
    SDVI_ASSIGN_OR_RETURN(const MeanColors colors, MeanColorIndices(image, reference.renumbering, color_step));
    const std::unique_ptr<draco::Mesh> mesh = BuildMeanColorMesh(image, colors, reference.renumbering);
    SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, EncodeMeanColorMesh(*mesh, position_bits, options.speed));
    SDVI_ASSIGN_OR_RETURN(DecodedMesh decoded, DecodeDracoMesh(bytes, self, true, true));
    const ErrorBound bound = CompressionErrorBound(image, position_bits, color_bits, true);
    bool same = decoded.ids.empty() && decoded.points.size() == n && decoded.faces.size() == image.triangles.size();
    for (uint32_t i = 0; i < n && same; ++i) {
      const Vertex& a = decoded.points[reference.renumbering[i]];
      const Vertex& b = image.vertices[i];
      const Vertex& c = reference.decoded[reference.renumbering[i]];
      same = a.x == c.x && a.y == c.y && std::abs(a.r - b.r) <= bound.color && std::abs(a.g - b.g) <= bound.color &&
             std::abs(a.b - b.b) <= bound.color;
    }
    same = same && FacesInOrder(decoded.faces, image, reference.renumbering);
    if (!same) return Status(StatusCode::kEncodeFailed, "neighbour-mean colours do not decode in the same order");
    DracoMesh out;
    out.bytes = std::move(bytes);
    out.renumbering = reference.renumbering;
    out.with_ids = false;
    out.decoded = std::move(decoded.points);
    return out;
  };

  DracoMesh chosen;
  bool decorrelated = false;
  try {
    if (grey || options.color_coding != ColorCoding::kDecorrelated) {
      SDVI_ASSIGN_OR_RETURN(chosen, encode_layout(grey ? ColorLayout::kGrey : ColorLayout::kRgb));
    }
    if (!grey && options.color_coding != ColorCoding::kRgb) {
      StatusOr<DracoMesh> other = encode_layout(ColorLayout::kDecorrelated);
      if (options.color_coding == ColorCoding::kDecorrelated) SDVI_RETURN_IF_ERROR(other.status());
      if (other.ok() && (chosen.bytes.empty() || other->bytes.size() < chosen.bytes.size())) {
        chosen = std::move(other).value();
        decorrelated = true;
      }
    }
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::kLimitExceeded, "out of memory while compressing the image");
  }
  // Neighbour-mean colours (kSmallest): in the traversal of a candidate without vertex ids,
  // kept when smaller.
  bool mean_colors = false;
  if (!grey && options.color_coding == ColorCoding::kSmallest && options.neighbour_mean && !chosen.with_ids &&
      !chosen.renumbering.empty()) {
    try {
      StatusOr<DracoMesh> mean = encode_mean(chosen);
      if (mean.ok() && mean->bytes.size() < chosen.bytes.size()) {
        chosen = std::move(mean).value();
        decorrelated = mean_colors = true;
      }
    } catch (const std::bad_alloc&) {
      return Status(StatusCode::kLimitExceeded, "out of memory while compressing the image");
    }
  }
  // Positions in the tag stream (payload 1.4, kSmallest): the same Draco mesh without its
  // POSITION attribute, decoded and checked to give the chosen mesh's points, faces and
  // colours, and the positions' indices on Draco's grid, checked to give the chosen mesh's
  // positions bit for bit; kept below when the payload is smaller.
  std::vector<uint8_t> positionless;
  codec_internal::PositionStream position_stream;
  if (options.color_coding == ColorCoding::kSmallest && options.stream_positions && !chosen.with_ids &&
      !chosen.renumbering.empty()) {
    try {
      const std::vector<uint32_t>& order = chosen.renumbering;
      StatusOr<std::vector<uint8_t>> bytes = Status(StatusCode::kInternal, "no layout");
      if (mean_colors) {
        StatusOr<MeanColors> colors = MeanColorIndices(image, order, color_step);
        if (colors.ok()) bytes = EncodeMeanColorMesh(*BuildMeanColorMesh(image, *colors, order, true), 1, options.speed);
      } else {
        const ColorLayout layout = decorrelated ? ColorLayout::kDecorrelated : grey ? ColorLayout::kGrey : ColorLayout::kRgb;
        auto mesh = BuildDracoMesh(image, false, layout, &order);
        bytes = decorrelated ? EncodeDecorrelatedMesh(*mesh, draco::MESH_EDGEBREAKER_ENCODING, 1, color_step,
                                                      options.speed)
                             : EncodeDracoMesh(*mesh, draco::MESH_EDGEBREAKER_ENCODING, 1, color_bits, options.speed);
      }
      StatusOr<DecodedMesh> decoded = bytes.ok() ? DecodeDracoMesh(*bytes, "compressed image (self-check)",
                                                                   decorrelated, mean_colors, true)
                                                 : StatusOr<DecodedMesh>(bytes.status());
      bool same = decoded.ok() && decoded->ids.empty() && decoded->points.size() == n &&
                  decoded->faces.size() == image.triangles.size();
      for (uint32_t p = 0; p < n && same; ++p) {
        const Vertex& a = decoded->points[p];
        const Vertex& b = chosen.decoded[p];
        same = std::memcmp(&a.r, &b.r, 3 * sizeof(float)) == 0;
      }
      same = same && FacesInOrder(decoded->faces, image, order);
      const codec_internal::DracoPositionGrid grid(image, position_bits);
      position_stream.min_x = grid.min(0);
      position_stream.min_y = grid.min(1);
      position_stream.range = grid.range();
      position_stream.bits = position_bits;
      position_stream.q.assign(n, {0, 0});
      const int32_t top = static_cast<int32_t>((uint32_t{1} << position_bits) - 1);
      for (uint32_t i = 0; i < n && same; ++i) {
        const Vertex& v = image.vertices[i];
        const uint32_t p = order[i];
        const float c[2] = {v.x, v.y};
        for (int k = 0; k < 2 && same; ++k) {
          const int32_t q = grid.Quantize(c[k], k);
          const float back = grid.Position(q, k);
          same = q >= 0 && q <= top && std::memcmp(&back, k ? &chosen.decoded[p].y : &chosen.decoded[p].x, 4) == 0;
          position_stream.q[p][k] = q;
        }
      }
      if (same) positionless = std::move(bytes).value();
    } catch (const std::bad_alloc&) {
      return Status(StatusCode::kLimitExceeded, "out of memory while compressing the image");
    }
  }
  std::vector<uint8_t> draco_bytes = chosen.bytes;
  std::vector<uint32_t> renumbering = std::move(chosen.renumbering);
  const bool with_ids = chosen.with_ids;
  if (renumbering.empty()) {
    renumbering.resize(n);
    std::iota(renumbering.begin(), renumbering.end(), 0u);
  }

  // The tag stream in a decoded numbering (vertex i is numbering[i]), with the positions and
  // colours given (null: in the Draco mesh); decoded: the reader's positions in that numbering.
  const bool features_first = options.feature_layer && options.features_first;
  auto encode_tags = [&](const std::vector<uint32_t>& numbering, const codec_internal::PositionStream* positions,
                         const codec_internal::ColorStream* colors,
                         const std::vector<Vertex>& decoded) -> StatusOr<std::vector<uint8_t>> {
    Image renumbered;
    renumbered.vertices = image.vertices;
    renumbered.triangles = image.triangles;
    renumbered.crease_edges = creases;
    renumbered.corners = corners;
    if (options.feature_layer) {
      renumbered.polylines = image.polylines;
      renumbered.pairs = image.pairs;
    }
    SDVI_RETURN_IF_ERROR(RenumberVertices(numbering, &renumbered));
    codec_internal::Tags tag_set;
    tag_set.crease_edges = std::move(renumbered.crease_edges);
    tag_set.corners = std::move(renumbered.corners);
    tag_set.has_feature_layer = options.feature_layer;
    tag_set.polylines = std::move(renumbered.polylines);
    tag_set.pairs = std::move(renumbered.pairs);
    tag_set.features_first = features_first;
    tag_set.positions = positions;
    tag_set.colors = colors;
    return codec_internal::EncodeTags(n, codec_internal::CollectMeshEdges(renumbered.triangles), tag_set, decoded);
  };
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> tags, encode_tags(renumbering, nullptr, nullptr, chosen.decoded));
  const bool positions_streamable = !positionless.empty();
  bool stream_positions = false;
  if (positions_streamable) {
    SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> tags_with,
                          encode_tags(renumbering, &position_stream, nullptr, chosen.decoded));
    if (positionless.size() + tags_with.size() < draco_bytes.size() + tags.size()) {
      draco_bytes = std::move(positionless);
      tags = std::move(tags_with);
      stream_positions = true;
    }
  }

  // Colours in the tag stream too (payload 1.5, kSmallest, with the positions there): the Draco
  // mesh holds the connectivity alone, and the colours are neighbour-mean colours on the
  // decorrelated grid (whatever the chosen mesh's colour coding). Draco numbers the points of a
  // mesh with one attribute as its connectivity decoder meets them, those of a mesh with more
  // otherwise; both decode the same faces in the same order and rotation, so the chosen
  // numbering maps to the new one corner by corner (checked to be one to one, the faces then
  // checked against the image's, the colours within the decorrelated bound). Kept when the
  // payload is smaller.
  // A grey image (payload 1.6) codes its one component, the grey value, on the grid of the
  // grey Draco COLOR's step, so with the same error bound.
  bool stream_colors = false;
  if (positions_streamable && options.stream_colors &&
      (grey ? options.stream_grey_colors : options.neighbour_mean)) {
    try {
      const std::string self = "compressed image (self-check)";
      StatusOr<std::vector<uint8_t>> bytes =
          EncodeDracoMesh(*BuildDracoMesh(image, false, ColorLayout::kNone, &renumbering),
                          draco::MESH_EDGEBREAKER_ENCODING, 1, color_bits, options.speed);
      StatusOr<DecodedMesh> alone = bytes.ok() ? DecodeDracoMesh(*bytes, self, false, false, true, true)
                                               : StatusOr<DecodedMesh>(bytes.status());
      StatusOr<DecodedMesh> reference = DecodeDracoMesh(chosen.bytes, self, decorrelated, mean_colors);
      bool same = alone.ok() && reference.ok() && alone->ids.empty() && alone->points.size() == n &&
                  alone->faces.size() == reference->faces.size() && alone->faces.size() == image.triangles.size();
      constexpr uint32_t kUnset = std::numeric_limits<uint32_t>::max();
      std::vector<uint32_t> to_alone(n, kUnset), from_alone(n, kUnset);
      for (size_t f = 0; same && f < alone->faces.size(); ++f)
        for (int k = 0; k < 3 && same; ++k) {
          const uint32_t a = alone->faces[f][k], r = reference->faces[f][k];
          if (to_alone[r] == kUnset && from_alone[a] == kUnset) to_alone[r] = a, from_alone[a] = r;
          same = to_alone[r] == a && from_alone[a] == r;
        }
      std::vector<uint32_t> order(n);
      for (uint32_t i = 0; i < n && same; ++i) {
        order[i] = to_alone[renumbering[i]];
        same = order[i] != kUnset;
      }
      same = same && FacesInOrder(alone->faces, image, order);
      StatusOr<codec_internal::ColorStream> colors = Status(StatusCode::kInternal, "no order");
      if (same && grey) {
        colors = GreyColorIndices(image, order, color_step);
      } else if (same) {
        StatusOr<MeanColors> mean = MeanColorIndices(image, order, color_step);
        colors = mean.ok() ? StatusOr<codec_internal::ColorStream>(std::move(mean->grid)) : mean.status();
      }
      same = same && colors.ok();
      if (same) {
        const ErrorBound bound = CompressionErrorBound(image, position_bits, color_bits, !grey);
        for (uint32_t i = 0; i < n && same; ++i) {
          Vertex a;
          const Vertex& b = image.vertices[i];
          same = ColorFromStream(*colors, order[i], &a) && std::abs(a.r - b.r) <= bound.color &&
                 std::abs(a.g - b.g) <= bound.color && std::abs(a.b - b.b) <= bound.color;
        }
      }
      if (same) {
        codec_internal::PositionStream positions = position_stream;
        std::vector<Vertex> decoded(n);
        for (uint32_t i = 0; i < n; ++i) {
          positions.q[order[i]] = position_stream.q[renumbering[i]];
          decoded[order[i]] = chosen.decoded[renumbering[i]];
        }
        SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> tags_with, encode_tags(order, &positions, &*colors, decoded));
        if (bytes->size() + tags_with.size() < draco_bytes.size() + tags.size()) {
          draco_bytes = std::move(bytes).value();
          tags = std::move(tags_with);
          renumbering = std::move(order);
          stream_positions = stream_colors = true;
          decorrelated = mean_colors = !grey;
        }
      }
    } catch (const std::bad_alloc&) {
      return Status(StatusCode::kLimitExceeded, "out of memory while compressing the image");
    }
  }

  std::vector<uint8_t> payload(kHeaderSize + draco_bytes.size() + tags.size(), 0);
  std::memcpy(payload.data(), kMagic, 4);
  payload[4] = kVersionMajor;
  payload[5] = stream_colors && grey ? 6 : stream_colors ? 5 : stream_positions ? 4 : mean_colors ? 3 : features_first ? 2 : 1;
  payload[6] = static_cast<uint8_t>((with_ids ? kFlagVertexIds : 0) |
                                    (options.feature_layer ? kFlagFeatureLayer : 0) |
                                    (grey ? kFlagGrey : 0) | (decorrelated ? kFlagDecorrelated : 0) |
                                    (options.feature_layer ? kFlagCompactPairs | kFlagRankedStarts : 0) |
                                    (features_first ? kFlagFeaturesFirst : 0) | (mean_colors ? kFlagMeanColors : 0));
  payload[7] = static_cast<uint8_t>(position_bits);
  payload[8] = static_cast<uint8_t>(color_bits);
  payload[9] = static_cast<uint8_t>(options.speed);
  payload[10] = static_cast<uint8_t>((stream_positions ? kFlag2Positions : 0) | (stream_colors ? kFlag2Colors : 0));
  PutU32(payload, 12, n);
  PutU32(payload, 16, static_cast<uint32_t>(image.triangles.size()));
  PutU32(payload, 20, static_cast<uint32_t>(creases.size()));
  PutU32(payload, 24, static_cast<uint32_t>(corners.size()));
  PutU32(payload, 28, static_cast<uint32_t>(draco_bytes.size()));
  PutU32(payload, 32, static_cast<uint32_t>(tags.size()));
  std::copy(draco_bytes.begin(), draco_bytes.end(), payload.begin() + kHeaderSize);
  std::copy(tags.begin(), tags.end(), payload.begin() + kHeaderSize + draco_bytes.size());
  PutU32(payload, kCrcOffset, PayloadCrc(payload));
  if (new_index_of_vertex) *new_index_of_vertex = std::move(renumbering);
  return payload;
}

Status DecodeDracoPayload(std::span<const uint8_t> payload, const std::string& source_name,
                          Image* image, uint64_t max_vertices, bool verify_checksum) {
  SDVI_ASSIGN_OR_RETURN(Header h, ParseHeader(payload, source_name));
  const std::string what = source_name + ": Draco payload";
  if (verify_checksum && PayloadCrc(payload) != h.crc)
    return Status(StatusCode::kCorrupt, what + " fails its CRC-32 check (damaged bytes)");
  if (h.position_bits > kMaxQuantizationBits || h.color_bits > kMaxQuantizationBits)
    return Status(StatusCode::kLimitExceeded,
                  what + " says " + std::to_string(h.position_bits) + " position and " +
                      std::to_string(h.color_bits) + " colour bits; at most " +
                      std::to_string(kMaxQuantizationBits) + " are read");
  if (h.vertex_count > max_vertices || h.triangle_count > 4 * max_vertices)
    return Status(StatusCode::kLimitExceeded,
                  what + " has " + std::to_string(h.vertex_count) + " vertices and " +
                      std::to_string(h.triangle_count) + " triangles; the limit is " +
                      std::to_string(max_vertices) + " vertices");
  if (h.vertex_count == 0 || h.triangle_count == 0)
    return Status(StatusCode::kCorrupt, what + " header counts no vertices or no triangles");
  const bool has_ids = (h.flags & kFlagVertexIds) != 0;
  const uint32_t n = h.vertex_count;
  Image out;
  try {
    const bool stream_colors = (h.flags2 & kFlag2Colors) != 0;
    SDVI_RETURN_IF_ERROR(
        CheckDracoFaceCount(payload.subspan(kHeaderSize, h.draco_size), h.triangle_count, source_name + ": Draco mesh"));
    SDVI_ASSIGN_OR_RETURN(DecodedMesh mesh,
                          DecodeDracoMesh(payload.subspan(kHeaderSize, h.draco_size), source_name,
                                          (h.flags & kFlagDecorrelated) && !stream_colors,
                                          (h.flags & kFlagMeanColors) && !stream_colors,
                                          (h.flags2 & kFlag2Positions) != 0, stream_colors));
    if (!stream_colors && mesh.grey != ((h.flags & kFlagGrey) != 0))
      return Status(StatusCode::kCorrupt, what + ": the Draco COLOR attribute has " +
                                              (mesh.grey ? "1 component" : "3 components") +
                                              ", the header's grey flag says otherwise");
    if (has_ids != !mesh.ids.empty())
      return Status(StatusCode::kCorrupt, what + (has_ids ? ": header flags vertex ids, the Draco mesh has none"
                                                          : ": the Draco mesh has vertex ids the header does not flag"));
    std::vector<uint32_t> index_of_point(mesh.points.size());
    out.vertices.resize(n);
    if (has_ids) {
      std::vector<char> seen(n, 0);
      for (size_t p = 0; p < mesh.points.size(); ++p) {
        const uint32_t id = mesh.ids[p];
        if (id >= n)
          return Status(StatusCode::kCorrupt, what + ": point " + std::to_string(p) + " has vertex id " +
                                                  std::to_string(id) + ", the header counts " +
                                                  std::to_string(n) + " vertices");
        if (seen[id] && !(out.vertices[id] == mesh.points[p]))
          return Status(StatusCode::kCorrupt, what + ": two points with vertex id " +
                                                  std::to_string(id) + " differ");
        seen[id] = 1;
        out.vertices[id] = mesh.points[p];
        index_of_point[p] = id;
      }
      const auto missing = std::find(seen.begin(), seen.end(), 0);
      if (missing != seen.end())
        return Status(StatusCode::kCorrupt, what + ": no point has vertex id " +
                                                std::to_string(missing - seen.begin()));
    } else {
      if (mesh.points.size() != n)
        return Status(StatusCode::kCorrupt, what + ": the Draco mesh has " +
                                                std::to_string(mesh.points.size()) +
                                                " points, the header counts " + std::to_string(n));
      out.vertices = std::move(mesh.points);
      std::iota(index_of_point.begin(), index_of_point.end(), 0u);
    }
    for (size_t i = 0; i < out.vertices.size(); ++i) {
      const Vertex& v = out.vertices[i];
      for (float c : {v.x, v.y, v.r, v.g, v.b})
        if (!std::isfinite(c))
          return Status(StatusCode::kNonFinite, what + ": vertex " + std::to_string(i) + " is not finite");
    }
    if (mesh.faces.size() != h.triangle_count)
      return Status(StatusCode::kCorrupt, what + ": the Draco mesh has " + std::to_string(mesh.faces.size()) +
                                              " faces, the header counts " +
                                              std::to_string(h.triangle_count) + " triangles");
    out.triangles.resize(mesh.faces.size());
    for (size_t f = 0; f < mesh.faces.size(); ++f)
      for (int k = 0; k < 3; ++k) out.triangles[f].v[k] = index_of_point[mesh.faces[f][k]];
    CanonicalizeTriangles(&out.triangles);
    codec_internal::Tags tags;
    codec_internal::ColorStream colors;
    colors.components = (h.flags & kFlagGrey) ? 1 : 3;
    SDVI_RETURN_IF_ERROR(codec_internal::DecodeTags(
        payload.subspan(kHeaderSize + h.draco_size, h.tags_size), n,
        codec_internal::CollectMeshEdges(out.triangles), h.crease_edge_count, h.corner_count,
        (h.flags & kFlagFeatureLayer) != 0, (h.flags & kFlagCompactPairs) != 0,
        (h.flags & kFlagRankedStarts) != 0, source_name, &tags, (h.flags & kFlagFeaturesFirst) != 0,
        out.vertices, h.position_bits, (h.flags2 & kFlag2Positions) ? &out.vertices : nullptr,
        stream_colors ? &colors : nullptr));
    if (stream_colors) {
      for (size_t i = 0; i < n; ++i)
        if (!ColorFromStream(colors, i, &out.vertices[i]))
          return Status(StatusCode::kCorrupt, what + ": vertex " + std::to_string(i) + "'s colour lies off its grid");
    }
    if (h.flags2 & kFlag2Positions)
      for (size_t i = 0; i < out.vertices.size(); ++i) {
        const Vertex& v = out.vertices[i];
        for (float c : {v.x, v.y, v.r, v.g, v.b})
          if (!std::isfinite(c))
            return Status(StatusCode::kNonFinite, what + ": vertex " + std::to_string(i) + " is not finite");
      }
    out.crease_edges = std::move(tags.crease_edges);
    out.corners = std::move(tags.corners);
    out.polylines = std::move(tags.polylines);
    out.pairs = std::move(tags.pairs);
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::kLimitExceeded, what + ": out of memory while decoding");
  }
  image->vertices = std::move(out.vertices);
  image->triangles = std::move(out.triangles);
  image->crease_edges = std::move(out.crease_edges);
  image->corners = std::move(out.corners);
  if (h.flags & kFlagFeatureLayer) {
    image->polylines = std::move(out.polylines);
    image->pairs = std::move(out.pairs);
  }
  return Status::Ok();
}

StatusOr<DracoPayloadInfo> InspectDracoPayload(std::span<const uint8_t> payload,
                                               const std::string& source_name) {
  SDVI_ASSIGN_OR_RETURN(Header h, ParseHeader(payload, source_name));
  DracoPayloadInfo info;
  info.version_major = h.major;
  info.version_minor = h.minor;
  info.vertex_count = h.vertex_count;
  info.triangle_count = h.triangle_count;
  info.crease_edge_count = h.crease_edge_count;
  info.corner_count = h.corner_count;
  info.draco_bytes = h.draco_size;
  info.tag_bytes = h.tags_size;
  info.payload_bytes = payload.size();
  info.position_bits = h.position_bits;
  info.color_bits = h.color_bits;
  info.speed = h.speed;
  info.has_vertex_ids = (h.flags & kFlagVertexIds) != 0;
  info.has_feature_layer = (h.flags & kFlagFeatureLayer) != 0;
  info.grey = (h.flags & kFlagGrey) != 0;
  info.decorrelated = (h.flags & kFlagDecorrelated) != 0;
  info.neighbour_mean = (h.flags & kFlagMeanColors) != 0;
  info.stream_positions = (h.flags2 & kFlag2Positions) != 0;
  info.stream_colors = (h.flags2 & kFlag2Colors) != 0;
  return info;
}

StatusOr<PartBytes> codec_internal::MeasureDracoParts(std::span<const uint8_t> payload,
                                                      const std::string& source_name) {
  SDVI_ASSIGN_OR_RETURN(Header h, ParseHeader(payload, source_name));
  Image image;
  SDVI_RETURN_IF_ERROR(DecodeDracoPayload(payload, source_name, &image));
  PartBytes parts;
  uint64_t in_stream = 0;  // the bytes of the positions and colours that open the tag stream
  try {
    auto positions_only = BuildDracoMesh(image, false, ColorLayout::kNone);
    SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> topology,
                          EncodeDracoMesh(*positions_only, draco::MESH_EDGEBREAKER_ENCODING, 1, 1, h.speed));
    SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> with_positions,
                          EncodeDracoMesh(*positions_only, draco::MESH_EDGEBREAKER_ENCODING,
                                          h.position_bits, h.color_bits, h.speed));
    parts.connectivity = std::min<uint64_t>(topology.size(), h.draco_size);
    uint64_t colors_in_stream = 0;
    if (h.flags2 & kFlag2Positions) {
      // The positions open the tag stream, the colours may follow: their bytes where they end.
      codec_internal::RangeDecoder rc(payload.subspan(kHeaderSize + h.draco_size, h.tags_size));
      std::vector<Vertex> scratch(h.vertex_count);
      const auto edges = codec_internal::CollectMeshEdges(image.triangles);
      SDVI_RETURN_IF_ERROR(codec_internal::DecodePositions(rc, h.position_bits, edges, source_name, &scratch));
      parts.positions = std::min<uint64_t>(rc.position(), h.tags_size);
      if (h.flags2 & kFlag2Colors) {
        codec_internal::ColorStream colors;
        colors.components = (h.flags & kFlagGrey) ? 1 : 3;
        SDVI_RETURN_IF_ERROR(codec_internal::DecodeColors(rc, h.vertex_count, edges, source_name, &colors));
        colors_in_stream = std::min<uint64_t>(rc.position(), h.tags_size) - parts.positions;
      }
    } else {
      parts.positions = std::min<uint64_t>(with_positions.size(), h.draco_size) - parts.connectivity;
    }
    parts.colors = h.draco_size - parts.connectivity - ((h.flags2 & kFlag2Positions) ? 0 : parts.positions) +
                   colors_in_stream;
    if (h.flags2 & kFlag2Positions) in_stream = parts.positions + colors_in_stream;
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::kLimitExceeded, source_name + ": out of memory while measuring the payload");
  }
  codec_internal::Tags tags;
  tags.crease_edges = image.crease_edges;
  tags.corners = image.corners;
  const auto edges = codec_internal::CollectMeshEdges(image.triangles);
  if (h.flags & kFlagFeaturesFirst) {
    // The feature layer is the stream's first part: its bytes where it ends.
    tags.has_feature_layer = tags.features_first = true;
    tags.polylines = image.polylines;
    tags.pairs = image.pairs;
    size_t feature_bytes = 0;
    codec_internal::EncodeTags(h.vertex_count, edges, tags, image.vertices, &feature_bytes);
    parts.feature_layer = std::min<uint64_t>(feature_bytes, h.tags_size - in_stream);
    parts.tags = h.tags_size - in_stream - parts.feature_layer;
  } else {
    const std::vector<uint8_t> without_features = codec_internal::EncodeTags(h.vertex_count, edges, tags);
    parts.tags = std::min<uint64_t>(without_features.size(), h.tags_size - in_stream);
    parts.feature_layer = h.tags_size - in_stream - parts.tags;
  }
  parts.container = kHeaderSize;
  return parts;
}

}  // namespace sdvi
