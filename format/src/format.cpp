// SPDX-License-Identifier: GPL-3.0-or-later
// The .sdvi container: encoder and validating decoder (spec/FORMAT.md).
#include "sdvi/format.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>

#include "format_internal.h"
#include "sdvi/file_util.h"
#include "sdvi_generated.h"

namespace sdvi {
namespace {

namespace fb = sdvi::fb;
using format_internal::CanonicalizeTriangles;
using format_internal::CanonicalTriangles;

constexpr char kIdentifier[] = "SDVI";
constexpr size_t kHeaderBytes = 28;
constexpr size_t kCrcOffsetInHeader = 24;
// The smallest buffer the schema allows: root offset, identifier, a one-field vtable
// (6 bytes + 2 padding), the root table (4-byte vtable offset + 28-byte header).
constexpr size_t kSmallestFileBytes = 48;
// FlatBuffers addresses at most 2^31 - 1 bytes.
constexpr uint64_t kMaxBufferBytes = (uint64_t{1} << 31) - 1;

static_assert(sizeof(fb::Vertex) == sizeof(Vertex));
static_assert(sizeof(fb::Header) == kHeaderBytes);
static_assert(sizeof(fb::Triangle16) == 6);

// Field ids of the root table (schema/sdvi.fbs); vtable slot = 4 + 2 * id.
enum RootField : int {
  kHeader = 0, kVertices, kTriangles, kTrianglesWide, kCorners, kFeatures, kMetadata, kPayload
};

std::string Hex32(uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%08x", v);
  return buf;
}

// Bounds-checked little-endian reads of an unverified buffer.
class RawView {
 public:
  explicit RawView(std::span<const uint8_t> bytes) : bytes_(bytes) {}
  size_t size() const { return bytes_.size(); }

  std::optional<uint32_t> U32(size_t pos) const {
    if (pos > size() || size() - pos < 4) return std::nullopt;
    const uint8_t* p = bytes_.data() + pos;
    return uint32_t{p[0]} | uint32_t{p[1]} << 8 | uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24;
  }
  std::optional<uint16_t> U16(size_t pos) const {
    if (pos > size() || size() - pos < 2) return std::nullopt;
    const uint8_t* p = bytes_.data() + pos;
    return static_cast<uint16_t>(p[0] | p[1] << 8);
  }
  // Position of field `id` of the table at `table`, or nullopt when absent or unreadable.
  std::optional<size_t> FieldPos(size_t table, int id) const {
    auto soff = U32(table);
    if (!soff) return std::nullopt;
    const int64_t vt = static_cast<int64_t>(table) - static_cast<int32_t>(*soff);
    if (vt < 0) return std::nullopt;
    auto vt_size = U16(static_cast<size_t>(vt));
    const size_t slot = 4 + 2 * static_cast<size_t>(id);
    if (!vt_size || *vt_size < slot + 2) return std::nullopt;
    auto off = U16(static_cast<size_t>(vt) + slot);
    if (!off || *off == 0) return std::nullopt;
    return table + *off;
  }
  // Target of the uoffset stored at pos.
  std::optional<size_t> Deref(size_t pos) const {
    auto off = U32(pos);
    if (!off) return std::nullopt;
    return pos + *off;
  }

 private:
  std::span<const uint8_t> bytes_;
};

// kTruncated when a list the root table points to starts inside the buffer but runs past
// its end. Called only when the checksum fails; the writer lays the largest lists out
// last, so a file cut short fails here.
Status CheckExtent(const RawView& raw, size_t root, const std::string& source) {
  struct VectorField {
    int id;
    size_t element_bytes;
    const char* name;
  };
  static constexpr VectorField kVectors[] = {
      {kVertices, 20, "vertex list"},    {kTriangles, 6, "triangle list"},
      {kTrianglesWide, 12, "wide triangle list"}, {kCorners, 4, "corner list"},
      {kMetadata, 4, "metadata list"}};
  auto check_vector = [&](std::optional<size_t> field, size_t element_bytes,
                          const char* name) -> Status {
    if (!field) return Status::Ok();
    // A list that starts past the end of the file: lists are laid out after the root
    // table, so a file cut short before a list loses its start. (A flipped offset byte
    // can look the same; the message says both.)
    if (auto offset = raw.U32(*field); offset && *field + uint64_t{*offset} + 4 > raw.size()) {
      return Status(StatusCode::kTruncated,
                    source + ": the " + name + " starts at byte " +
                        std::to_string(*field + uint64_t{*offset}) + " but the file has " +
                        std::to_string(raw.size()) + " bytes (the file is truncated, or damaged)");
    }
    auto target = raw.Deref(*field);
    // Unreadable or misaligned offsets are damage, not truncation: the verifier reports them.
    if (!target || *target % 4 != 0) return Status::Ok();
    auto length = raw.U32(*target);
    if (!length) return Status::Ok();
    const uint64_t end = *target + 4 + uint64_t{*length} * element_bytes;
    if (end > raw.size())
      return Status(StatusCode::kTruncated,
                    source + ": the " + name + " needs bytes up to " + std::to_string(end) +
                        " but the file has " + std::to_string(raw.size()) +
                        " bytes (the file is truncated)");
    return Status::Ok();
  };
  for (const VectorField& v : kVectors)
    SDVI_RETURN_IF_ERROR(check_vector(raw.FieldPos(root, v.id), v.element_bytes, v.name));
  for (auto [id, name] : {std::pair{int{kFeatures}, "feature layer"},
                          std::pair{int{kPayload}, "compressed payload table"}}) {
    auto field = raw.FieldPos(root, id);
    if (!field) continue;
    if (auto offset = raw.U32(*field); offset && *field + uint64_t{*offset} + 4 > raw.size()) {
      return Status(StatusCode::kTruncated,
                    source + ": the " + name + " starts at byte " +
                        std::to_string(*field + uint64_t{*offset}) + " but the file has " +
                        std::to_string(raw.size()) + " bytes (the file is truncated, or damaged)");
    }
  }
  if (auto payload_field = raw.FieldPos(root, kPayload)) {
    if (auto payload = raw.Deref(*payload_field); payload && *payload + 4 <= raw.size()) {
      SDVI_RETURN_IF_ERROR(check_vector(raw.FieldPos(*payload, 6), 1, "compressed payload"));
    }
  }
  return Status::Ok();
}

std::vector<std::pair<std::string, std::string>> ReadKeyValues(
    const flatbuffers::Vector<flatbuffers::Offset<fb::MetadataEntry>>* entries) {
  std::vector<std::pair<std::string, std::string>> out;
  if (!entries) return out;
  out.reserve(entries->size());
  for (const fb::MetadataEntry* e : *entries)
    out.emplace_back(e->key()->str(), e->value() ? e->value()->str() : std::string());
  return out;
}

flatbuffers::Offset<flatbuffers::Vector<flatbuffers::Offset<fb::MetadataEntry>>> WriteKeyValues(
    flatbuffers::FlatBufferBuilder& fbb,
    const std::vector<std::pair<std::string, std::string>>& entries) {
  std::vector<flatbuffers::Offset<fb::MetadataEntry>> offsets;
  offsets.reserve(entries.size());
  for (const auto& [key, value] : entries) {
    auto k = fbb.CreateString(key);
    auto v = fbb.CreateString(value);
    offsets.push_back(fb::CreateMetadataEntry(fbb, k, v));
  }
  return fbb.CreateVector(offsets);
}

// Everything after the mesh: corners, feature layer, metadata.
struct OptionalParts {
  flatbuffers::Offset<flatbuffers::Vector<uint32_t>> corners;
  flatbuffers::Offset<fb::FeatureLayer> features;
  flatbuffers::Offset<flatbuffers::Vector<flatbuffers::Offset<fb::MetadataEntry>>> metadata;
};

OptionalParts WriteOptionalParts(flatbuffers::FlatBufferBuilder& fbb, const Image& image) {
  OptionalParts parts;
  if (!image.corners.empty()) parts.corners = fbb.CreateVector(image.corners);
  if (!image.polylines.empty() || !image.pairs.empty()) {
    flatbuffers::Offset<flatbuffers::Vector<flatbuffers::Offset<fb::Polyline>>> polylines;
    if (!image.polylines.empty()) {
      std::vector<flatbuffers::Offset<fb::Polyline>> offsets;
      offsets.reserve(image.polylines.size());
      for (const FeaturePolyline& p : image.polylines)
        offsets.push_back(fb::CreatePolyline(fbb, fbb.CreateVector(p.vertices), p.closed));
      polylines = fbb.CreateVector(offsets);
    }
    flatbuffers::Offset<flatbuffers::Vector<const fb::FeaturePair*>> pairs;
    if (!image.pairs.empty()) {
      std::vector<fb::FeaturePair> structs;
      structs.reserve(image.pairs.size());
      for (const FeaturePair& p : image.pairs) structs.emplace_back(p.first, p.second, p.sharpness);
      pairs = fbb.CreateVectorOfStructs(structs);
    }
    parts.features = fb::CreateFeatureLayer(fbb, polylines, pairs);
  }
  if (!image.metadata.empty()) parts.metadata = WriteKeyValues(fbb, image.metadata);
  return parts;
}

// Finishes the buffer with identifier "SDVI" and stores its CRC-32 in the header.
std::vector<uint8_t> FinishWithCrc(flatbuffers::FlatBufferBuilder& fbb,
                                   flatbuffers::Offset<fb::Image> root) {
  fbb.Finish(root, kIdentifier);
  std::vector<uint8_t> bytes(fbb.GetBufferPointer(), fbb.GetBufferPointer() + fbb.GetSize());
  const fb::Image* image = fb::GetImage(bytes.data());
  const size_t crc_pos =
      reinterpret_cast<const uint8_t*>(image->header()) - bytes.data() + kCrcOffsetInHeader;
  const uint32_t crc = Crc32(bytes);  // the crc field is still zero here
  for (int i = 0; i < 4; ++i) bytes[crc_pos + i] = static_cast<uint8_t>(crc >> (8 * i));
  return bytes;
}

Status CheckEncodable(uint64_t estimated_bytes, const std::string& what) {
  if (estimated_bytes > kMaxBufferBytes - 4096)
    return Status(StatusCode::kLimitExceeded,
                  what + ": about " + std::to_string(estimated_bytes) +
                      " bytes, more than a .sdvi container can hold (2 GiB)");
  return Status::Ok();
}

uint64_t EstimateOptionalBytes(const Image& image) {
  uint64_t bytes = 4 * uint64_t{image.corners.size()} + 12 * uint64_t{image.pairs.size()} + 64;
  for (const auto& p : image.polylines) bytes += 4 * uint64_t{p.vertices.size()} + 24;
  for (const auto& [k, v] : image.metadata) bytes += k.size() + v.size() + 24;
  return bytes;
}

}  // namespace

StatusOr<std::vector<uint8_t>> EncodeSdvi(const Image& input) {
  // Crease edges and corners are sets: normalise a copy only when the caller's are not.
  std::optional<Image> normalized;
  if (!format_internal::SetsAreNormalized(input)) {
    normalized = input;
    format_internal::NormalizeSets(*normalized);
  }
  const Image& image = normalized ? *normalized : input;
  SDVI_RETURN_IF_ERROR(ValidateImage(image, "encoding .sdvi"));
  const uint64_t nv = image.vertices.size(), nt = image.triangles.size();
  const bool wide = nv > kNarrowProfileMaxVertices;
  const uint64_t estimate = 20 * nv + (wide ? 12 : 6) * nt + EstimateOptionalBytes(image) + 128;
  SDVI_RETURN_IF_ERROR(CheckEncodable(estimate, "encoding .sdvi"));
  const CanonicalTriangles canon = CanonicalizeTriangles(image.triangles, image.crease_edges);

  flatbuffers::FlatBufferBuilder fbb(static_cast<size_t>(estimate));
  // Built back to front: the first object created ends the file. Vertices come last in
  // the file, then (before them) the triangles, then the optional parts.
  auto vertices = fbb.CreateVectorOfStructs(
      reinterpret_cast<const fb::Vertex*>(image.vertices.data()), image.vertices.size());
  flatbuffers::Offset<flatbuffers::Vector<const fb::Triangle16*>> narrow;
  flatbuffers::Offset<flatbuffers::Vector<const fb::Triangle32*>> wide_triangles;
  if (wide) {
    std::vector<fb::Triangle32> tris;
    tris.reserve(canon.triangles.size());
    for (const Triangle& t : canon.triangles) tris.emplace_back(t.v[0], t.v[1], t.v[2]);
    wide_triangles = fbb.CreateVectorOfStructs(tris);
  } else {
    std::vector<fb::Triangle16> tris;
    tris.reserve(canon.triangles.size());
    for (const Triangle& t : canon.triangles)
      tris.emplace_back(static_cast<uint16_t>(t.v[0]), static_cast<uint16_t>(t.v[1]),
                        static_cast<uint16_t>(t.v[2]));
    narrow = fbb.CreateVectorOfStructs(tris);
  }
  const OptionalParts parts = WriteOptionalParts(fbb, image);
  const fb::Header header(kSdviVersionMajor, kSdviVersionMinor, image.width, image.height,
                          canon.tagged3, canon.tagged2, canon.tagged1, /*crc32=*/0);
  auto root = fb::CreateImage(fbb, &header, vertices, narrow, wide_triangles, parts.corners,
                              parts.features, parts.metadata, /*payload=*/0);
  return FinishWithCrc(fbb, root);
}

StatusOr<std::vector<uint8_t>> EncodeSdviCompressed(const Image& image_without_mesh,
                                                    const std::vector<uint8_t>& draco_payload,
                                                    const PayloadSummary& summary) {
  const Image& image = image_without_mesh;
  const std::string what = "encoding compressed .sdvi";
  if (!image.vertices.empty() || !image.triangles.empty() || !image.crease_edges.empty() ||
      !image.corners.empty())
    return Status(StatusCode::kInvalidArgument,
                  what + ": the image must not hold vertices, triangles, crease edges or corners "
                         "(they travel inside the compressed payload)");
  if (draco_payload.empty())
    return Status(StatusCode::kEmptyInput, what + ": the compressed payload is empty");
  SDVI_RETURN_IF_ERROR(format_internal::ValidateImageParts(image, what, /*has_mesh=*/false));
  const uint64_t estimate = draco_payload.size() + EstimateOptionalBytes(image) + 256;
  SDVI_RETURN_IF_ERROR(CheckEncodable(estimate, what));

  flatbuffers::FlatBufferBuilder fbb(static_cast<size_t>(estimate));
  auto data = fbb.CreateVector(draco_payload);  // created first: ends the file
  auto params = summary.params.empty() ? 0 : WriteKeyValues(fbb, summary.params);
  auto payload = fb::CreateCompressedPayload(fbb, fb::PayloadCodec::Draco,
                                             summary.codec_version_major,
                                             summary.codec_version_minor, summary.vertex_count,
                                             summary.triangle_count, params, data);
  const OptionalParts parts = WriteOptionalParts(fbb, image);
  const fb::Header header(kSdviVersionMajor, kSdviVersionMinor, image.width, image.height, 0, 0, 0,
                          0);
  auto root = fb::CreateImage(fbb, &header, 0, 0, 0, 0, parts.features, parts.metadata, payload);
  return FinishWithCrc(fbb, root);
}

StatusOr<SdviFile> DecodeSdvi(std::span<const uint8_t> input, const std::string& source,
                              const ReadOptions& options) {
  const size_t size = input.size();
  if (size == 0) return Status(StatusCode::kEmptyInput, source + ": the file is empty");
  if (size > options.max_file_bytes || size > kMaxBufferBytes)
    return Status(StatusCode::kLimitExceeded,
                  source + ": " + std::to_string(size) + " bytes exceed the limit of " +
                      std::to_string(std::min<uint64_t>(options.max_file_bytes, kMaxBufferBytes)));
  // Identifier first: it says whether this is an sdvi file at all.
  const size_t id_bytes = size > 4 ? std::min<size_t>(size - 4, 4) : 0;
  if (id_bytes > 0 && std::memcmp(input.data() + 4, kIdentifier, id_bytes) != 0) {
    std::string found;
    for (size_t i = 0; i < id_bytes; ++i) {
      const char c = static_cast<char>(input[4 + i]);
      found += (c >= 32 && c < 127) ? c : '?';
    }
    std::string hint;
    if (input[0] == '{' || input[0] == '[') hint = " (this looks like JSON: use `sdvi convert`)";
    if (size >= 4 && std::memcmp(input.data(), "\x89PNG", 4) == 0) hint = " (this is a PNG image)";
    return Status(StatusCode::kWrongIdentifier,
                  source + ": not an .sdvi file: expected identifier 'SDVI' at byte 4, found '" +
                      found + "'" + hint);
  }
  if (size < kSmallestFileBytes)
    return Status(StatusCode::kTruncated,
                  source + ": the file has " + std::to_string(size) +
                      " bytes, fewer than the smallest .sdvi container (" +
                      std::to_string(kSmallestFileBytes) + " bytes)");

  // FlatBuffers reads scalars in place: work on an aligned copy when the input is not.
  std::vector<uint8_t> aligned_copy;
  std::span<const uint8_t> bytes = input;
  if (reinterpret_cast<uintptr_t>(input.data()) % 8 != 0) {
    aligned_copy.assign(input.begin(), input.end());
    bytes = aligned_copy;
  }
  const RawView raw(bytes);

  // The version before anything else: root-table field 0 starts with major, minor.
  const size_t root = *raw.U32(0);
  auto header_pos = raw.FieldPos(root, kHeader);
  if (!header_pos || *header_pos >= size)
    return Status(StatusCode::kCorrupt,
                  source + ": cannot locate the header (root table at byte " +
                      std::to_string(root) + " of " + std::to_string(size) + ")");
  if (*header_pos + kHeaderBytes > size)
    return Status(StatusCode::kTruncated,
                  source + ": the file ends inside the header (" + std::to_string(size) +
                      " bytes, the header ends at byte " +
                      std::to_string(*header_pos + kHeaderBytes) + ")");
  const uint16_t major = *raw.U16(*header_pos), minor = *raw.U16(*header_pos + 2);
  if (major != kSdviVersionMajor)
    return Status(StatusCode::kUnsupportedVersion,
                  source + ": the file has format version " + std::to_string(major) + "." +
                      std::to_string(minor) + "; this build reads version " +
                      std::to_string(kSdviVersionMajor) + ".x (writes " +
                      std::to_string(kSdviVersionMajor) + "." + std::to_string(kSdviVersionMinor) +
                      ")");

  // CRC-32 over the whole file with the crc field as zero.
  const size_t crc_pos = *header_pos + kCrcOffsetInHeader;
  const uint32_t stored_crc = *raw.U32(crc_pos);
  static constexpr uint8_t kZero[4] = {0, 0, 0, 0};
  uint32_t crc = Crc32(bytes.subspan(0, crc_pos));
  crc = Crc32(kZero, crc);
  crc = Crc32(bytes.subspan(crc_pos + 4), crc);
  if (crc != stored_crc) {
    // A file cut short fails the checksum too: say which it is.
    SDVI_RETURN_IF_ERROR(CheckExtent(raw, root, source));
  }
  if (crc != stored_crc && options.verify_checksums)
    return Status(StatusCode::kCorrupt, source + ": checksum mismatch: the header says " +
                                            Hex32(stored_crc) + ", the content gives " +
                                            Hex32(crc) + " (bytes were changed or damaged)");

  flatbuffers::Verifier::Options verifier_options;
  verifier_options.max_tables = std::max<uint32_t>(1'000'000, options.max_vertices);
  flatbuffers::Verifier verifier(bytes.data(), size, verifier_options);
  if (!fb::VerifyImageBuffer(verifier))
    return Status(StatusCode::kCorrupt,
                  source + ": the FlatBuffers structure is invalid (offsets, sizes or alignment)");
  const fb::Image* file = fb::GetImage(bytes.data());
  const fb::Header& h = *file->header();

  SdviFile out;
  out.version_major = major;
  out.version_minor = minor;
  out.file_bytes = size;
  if (h.width() > options.max_width || h.height() > options.max_height)
    return Status(StatusCode::kLimitExceeded,
                  source + ": image size " + std::to_string(h.width()) + " x " +
                      std::to_string(h.height()) + " exceeds the limit of " +
                      std::to_string(options.max_width) + " x " + std::to_string(options.max_height));
  Image& image = out.image;
  image.width = h.width();
  image.height = h.height();

  const auto* vertices = file->vertices();
  const auto* narrow = file->triangles();
  const auto* wide = file->triangles_wide();
  const auto* corners = file->corners();
  const uint64_t nv = vertices ? vertices->size() : 0;
  const uint64_t nt = (narrow ? narrow->size() : 0) + (wide ? wide->size() : 0);
  if (narrow && wide && narrow->size() > 0 && wide->size() > 0)
    return Status(StatusCode::kCorrupt,
                  source + ": the file holds both narrow and wide triangle lists");
  if (nv > options.max_vertices)
    return Status(StatusCode::kLimitExceeded, source + ": " + std::to_string(nv) +
                                                  " vertices exceed the limit of " +
                                                  std::to_string(options.max_vertices));
  if (nt > options.max_triangles)
    return Status(StatusCode::kLimitExceeded, source + ": " + std::to_string(nt) +
                                                  " triangles exceed the limit of " +
                                                  std::to_string(options.max_triangles));
  out.tagged3 = h.tagged3();
  out.tagged2 = h.tagged2();
  out.tagged1 = h.tagged1();
  const uint64_t tagged = uint64_t{h.tagged3()} + h.tagged2() + h.tagged1();

  if (const fb::CompressedPayload* payload = file->payload()) {
    if (nv > 0 || nt > 0 || (corners && corners->size() > 0))
      return Status(StatusCode::kCorrupt,
                    source + ": the file holds both a compressed payload and a raw mesh");
    if (tagged > 0)
      return Status(StatusCode::kCountMismatch,
                    source + ": tagged-triangle counts must be zero when the mesh is compressed, "
                             "found " + std::to_string(tagged));
    if (payload->codec() != fb::PayloadCodec::Draco)
      return Status(StatusCode::kUnsupportedFormat,
                    source + ": compressed payload codec " +
                        std::to_string(static_cast<int>(payload->codec())) +
                        " is not one this build reads (1 = Draco)");
    if (!payload->data() || payload->data()->size() == 0)
      return Status(StatusCode::kEmptyInput, source + ": the compressed payload is empty");
    out.payload = PayloadKind::kDraco;
    out.compressed_payload.assign(payload->data()->begin(), payload->data()->end());
    out.payload_summary.codec_version_major = payload->codec_version_major();
    out.payload_summary.codec_version_minor = payload->codec_version_minor();
    out.payload_summary.vertex_count = payload->vertex_count();
    out.payload_summary.triangle_count = payload->triangle_count();
    out.payload_summary.params = ReadKeyValues(payload->params());
    if (out.payload_summary.vertex_count > options.max_vertices ||
        out.payload_summary.triangle_count > options.max_triangles)
      return Status(StatusCode::kLimitExceeded,
                    source + ": the compressed mesh (" +
                        std::to_string(out.payload_summary.vertex_count) + " vertices, " +
                        std::to_string(out.payload_summary.triangle_count) +
                        " triangles) exceeds the read limits");
  } else {
    if (tagged > nt)
      return Status(StatusCode::kCountMismatch,
                    source + ": the header counts " + std::to_string(h.tagged3()) + " + " +
                        std::to_string(h.tagged2()) + " + " + std::to_string(h.tagged1()) +
                        " tagged triangles but the file holds " + std::to_string(nt) +
                        " triangles");
    if (vertices) {
      image.vertices.resize(vertices->size());
      if (!image.vertices.empty())
        std::memcpy(image.vertices.data(), vertices->Data(), image.vertices.size() * sizeof(Vertex));
    }
    image.triangles.reserve(nt);
    if (narrow)
      for (const fb::Triangle16* t : *narrow) image.triangles.push_back(Triangle{{t->a(), t->b(), t->c()}});
    if (wide)
      for (const fb::Triangle32* t : *wide) image.triangles.push_back(Triangle{{t->a(), t->b(), t->c()}});
    if (corners) {
      image.corners.assign(corners->begin(), corners->end());
      for (size_t i = 1; i < image.corners.size(); ++i)
        if (image.corners[i - 1] >= image.corners[i])
          return Status(StatusCode::kCorrupt, source + ": corner " +
                                                  std::to_string(image.corners[i]) +
                                                  " breaks the ascending order of the corner list");
    }
    // Indices first: tags derived from out-of-range triangles would be meaningless.
    for (size_t i = 0; i < image.triangles.size(); ++i)
      for (uint32_t idx : image.triangles[i].v)
        if (idx >= nv)
          return Status(StatusCode::kIndexOutOfRange,
                        source + ": triangle " + std::to_string(i) + " names vertex " +
                            std::to_string(idx) + " but the file has " + std::to_string(nv) +
                            " vertices");
    image.crease_edges = format_internal::CreaseEdgesFromGroups(image.triangles, h.tagged3(),
                                                                h.tagged2(), h.tagged1());
  }

  if (const fb::FeatureLayer* features = file->features()) {
    if (const auto* polylines = features->polylines()) {
      image.polylines.reserve(polylines->size());
      for (const fb::Polyline* p : *polylines) {
        FeaturePolyline poly;
        if (p->vertices()) poly.vertices.assign(p->vertices()->begin(), p->vertices()->end());
        poly.closed = p->closed();
        image.polylines.push_back(std::move(poly));
      }
    }
    if (const auto* pairs = features->pairs()) {
      image.pairs.reserve(pairs->size());
      for (const fb::FeaturePair* p : *pairs)
        image.pairs.push_back(FeaturePair{p->first(), p->second(), p->sharpness()});
    }
  }
  image.metadata = ReadKeyValues(file->metadata());

  SDVI_RETURN_IF_ERROR(format_internal::ValidateImageParts(
      image, source, /*has_mesh=*/out.payload == PayloadKind::kRaw));
  return out;
}

StatusOr<SdviFile> ReadSdviFile(const std::string& path, const ReadOptions& options) {
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, ReadFileBytes(path, options.max_file_bytes));
  return DecodeSdvi(bytes, path, options);
}

Status WriteSdvi(const std::string& path, const Image& image) {
  auto bytes = EncodeSdvi(image);
  if (!bytes.ok()) return Status(bytes.status().code(), path + ": " + bytes.status().message());
  return WriteFileAtomic(path, *bytes);
}

}  // namespace sdvi
