// SPDX-License-Identifier: GPL-3.0-or-later
// Images in .sdvi files whatever their payload: the container (sdvi_format) outside,
// the Draco payload (draco_payload.cpp) inside.
#include <string>

#include "sdvi/codec.h"
#include "sdvi/file_util.h"
#include "tag_stream.h"

namespace sdvi {
namespace {

PayloadSummary SummaryOf(std::span<const uint8_t> payload, bool with_params) {
  PayloadSummary summary;
  auto info = InspectDracoPayload(payload, "");
  if (!info.ok()) return summary;
  summary.codec_version_major = static_cast<uint8_t>(info->version_major);
  summary.codec_version_minor = static_cast<uint8_t>(info->version_minor);
  summary.vertex_count = info->vertex_count;
  summary.triangle_count = info->triangle_count;
  if (!with_params) return summary;
  summary.params = {{"position_bits", std::to_string(info->position_bits)},
                    {"color_bits", std::to_string(info->color_bits)},
                    {"speed", std::to_string(info->speed)},
                    {"vertex_ids", info->has_vertex_ids ? "1" : "0"},
                    {"feature_layer", info->has_feature_layer ? "1" : "0"}};
  return summary;
}

}  // namespace

StatusOr<Image> DecodeImage(std::span<const uint8_t> bytes, const std::string& source_name,
                            const ReadOptions& options) {
  SDVI_ASSIGN_OR_RETURN(SdviFile file, DecodeSdvi(bytes, source_name, options));
  if (file.payload == PayloadKind::kRaw) return std::move(file.image);
  Image image = std::move(file.image);
  SDVI_ASSIGN_OR_RETURN(DracoPayloadInfo info, InspectDracoPayload(file.compressed_payload, source_name));
  if (info.has_feature_layer && (!image.polylines.empty() || !image.pairs.empty()))
    return Status(StatusCode::kCorrupt, source_name + ": the feature layer is both in the container "
                                                      "and in the compressed payload");
  SDVI_RETURN_IF_ERROR(DecodeDracoPayload(file.compressed_payload, source_name, &image,
                                          std::min<uint64_t>(options.max_vertices,
                                                             options.max_triangles),
                                          options.verify_checksums));
  const PayloadSummary& summary = file.payload_summary;
  if (summary.vertex_count != image.vertices.size() ||
      summary.triangle_count != image.triangles.size())
    return Status(StatusCode::kCountMismatch,
                  source_name + ": the container says the compressed mesh has " +
                      std::to_string(summary.vertex_count) + " vertices and " +
                      std::to_string(summary.triangle_count) + " triangles, the payload holds " +
                      std::to_string(image.vertices.size()) + " and " +
                      std::to_string(image.triangles.size()));
  if (image.triangles.size() > options.max_triangles)
    return Status(StatusCode::kLimitExceeded,
                  source_name + ": the compressed mesh has " + std::to_string(image.triangles.size()) +
                      " triangles, more than the read limit " + std::to_string(options.max_triangles));
  SDVI_RETURN_IF_ERROR(ValidateImage(image, source_name));
  return CanonicalizeImage(image);
}

StatusOr<Image> ReadImage(const std::string& path, const ReadOptions& options) {
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, ReadFileBytes(path, options.max_file_bytes));
  return DecodeImage(bytes, path, options);
}

namespace {

// The container for image with a Draco payload at the given options (no read-back check).
StatusOr<std::vector<uint8_t>> EncodeCompressed(const Image& image, const CompressOptions& compress) {
  std::vector<uint32_t> new_index;
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> payload, EncodeDracoPayload(image, compress, &new_index));
  Image rest = image;
  SDVI_RETURN_IF_ERROR(RenumberVertices(new_index, &rest));
  rest.vertices.clear();
  rest.triangles.clear();
  rest.crease_edges.clear();
  rest.corners.clear();
  if (compress.feature_layer) {
    rest.polylines.clear();
    rest.pairs.clear();
  }
  return EncodeSdviCompressed(rest, payload, SummaryOf(payload, compress.container_params));
}

}  // namespace

StatusOr<std::vector<uint8_t>> EncodeImage(const Image& image, const CompressOptions* compress,
                                           const std::string& source_name) {
  SDVI_RETURN_IF_ERROR(ValidateImage(image, source_name));
  if (!compress) return EncodeSdvi(image);
  // The file is read back before it is returned: the writer never produces a file its
  // reader refuses (spec/FORMAT.md 8.2). Quantised positions can fold a thin triangle;
  // with default position bits the bits are raised until none folds, explicit bits that
  // fold are kFoldedTriangle.
  CompressOptions options = *compress;
  const bool default_bits = options.position_bits == 0;
  if (default_bits) options.position_bits = DefaultPositionBits(image, options.reference_mse);
  for (;;) {
    SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> file, EncodeCompressed(image, options));
    const Status read_back = DecodeImage(file, source_name + " (compressed)").status();
    if (read_back.ok()) return file;
    if (read_back.code() != StatusCode::kFoldedTriangle)
      return Status(StatusCode::kEncodeFailed,
                    source_name + ": the compressed file does not read back: " + read_back.ToString());
    if (!default_bits || options.position_bits >= kMaxQuantizationBits)
      return Status(StatusCode::kFoldedTriangle, read_back.message() + " once positions are quantised to " +
                                                     std::to_string(options.position_bits) +
                                                     " bits; use more position bits");
    ++options.position_bits;
  }
}

Status WriteImage(const std::string& path, const Image& image, const CompressOptions* compress) {
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, EncodeImage(image, compress, path));
  return WriteFileAtomic(path, bytes);
}

StatusOr<CompressionReport> ReportCompression(const SdviFile& file, const std::string& source_name) {
  CompressionReport report;
  report.payload = file.payload;
  report.file_bytes = file.file_bytes;
  if (file.payload == PayloadKind::kDraco) {
    SDVI_ASSIGN_OR_RETURN(report.draco, InspectDracoPayload(file.compressed_payload, source_name));
    report.payload_bytes = file.compressed_payload.size();
    report.vertex_count = report.draco.vertex_count;
    report.triangle_count = report.draco.triangle_count;
  } else {
    report.payload_bytes = file.file_bytes;
    report.vertex_count = static_cast<uint32_t>(file.image.vertices.size());
    report.triangle_count = static_cast<uint32_t>(file.image.triangles.size());
  }
  report.paper_bytes = PaperSizeBytes(report.vertex_count, report.triangle_count);
  const double pixels = double(file.image.width) * double(file.image.height);
  if (pixels > 0) report.bits_per_pixel = 8.0 * double(report.file_bytes) / pixels;
  if (report.vertex_count > 0)
    report.bytes_per_vertex = double(report.file_bytes) / double(report.vertex_count);
  if (report.paper_bytes > 0) report.ratio_to_paper = double(report.file_bytes) / double(report.paper_bytes);
  return report;
}

StatusOr<PartBytes> MeasureParts(std::span<const uint8_t> file_bytes, const std::string& source_name) {
  SDVI_ASSIGN_OR_RETURN(SdviFile file, DecodeSdvi(file_bytes, source_name));
  PartBytes parts;
  if (file.payload == PayloadKind::kDraco) {
    SDVI_ASSIGN_OR_RETURN(parts, codec_internal::MeasureDracoParts(file.compressed_payload, source_name));
    parts.container += file.file_bytes - file.compressed_payload.size();
    return parts;
  }
  const Image& image = file.image;
  const uint64_t v = image.vertices.size(), t = image.triangles.size();
  parts.positions = 8 * v;
  parts.colors = 12 * v;
  parts.connectivity = (v <= kNarrowProfileMaxVertices ? 6 : 12) * t;
  parts.tags = 4 * image.corners.size();
  Image without_features = image;
  without_features.polylines.clear();
  without_features.pairs.clear();
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> smaller, EncodeSdvi(without_features));
  parts.feature_layer = file.file_bytes > smaller.size() ? file.file_bytes - smaller.size() : 0;
  const uint64_t counted = parts.positions + parts.colors + parts.connectivity + parts.tags + parts.feature_layer;
  parts.container = file.file_bytes > counted ? file.file_bytes - counted : 0;
  return parts;
}

}  // namespace sdvi
