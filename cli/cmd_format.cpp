// SPDX-License-Identifier: GPL-3.0-or-later
// sdvi convert (mesh JSON <-> .sdvi) and sdvi info (what a .sdvi file holds).
#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "args.h"
#include "commands.h"
#include "io.h"
#include "sdvi/file_util.h"
#include "sdvi/format.h"
#include "sdvi/mesh_json.h"
#include "sdvi/tagged_mesh.h"
#if __has_include("sdvi/codec.h")
#include "sdvi/codec.h"
#define SDVI_CLI_HAS_CODEC 1
#endif

namespace sdvi::cli {
namespace {

enum class FileKind { kSdvi, kMeshJson };

StatusOr<FileKind> KindOfOutput(const std::string& path) {
  const std::string ext = FileExtension(path);
  if (ext == "sdvi") return FileKind::kSdvi;
  if (ext == "json") return FileKind::kMeshJson;
  return Status(StatusCode::kInvalidArgument,
                path + ": cannot tell the output format from the extension '" + ext +
                    "' (expected .sdvi or .json)");
}

// An input is .sdvi when it carries the identifier (any payload, through LoadSdvi), mesh
// JSON when it has that extension.
StatusOr<Image> LoadAny(const std::string& path) {
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, ReadFileBytes(path));
  const bool sdvi_identifier = bytes.size() >= 8 && std::equal(bytes.begin() + 4, bytes.begin() + 8,
                                                               "SDVI");
  if (!sdvi_identifier && FileExtension(path) == "json") {
    if (bytes.empty()) return Status(StatusCode::kEmptyInput, path + ": the file is empty");
    return ParseMeshJson(
        std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path);
  }
  return LoadSdvi(path);
}

// Vertices that are corners, by the subdivision engine's own rule (spec/SUBDIVISION.md
// section 1): tagged explicitly, with crease degree 1 or >= 3 counting the listed crease
// edges and the mesh boundary, or on no triangle. A mesh without triangles has its explicit
// corners only (the engine refuses it).
StatusOr<size_t> CountCorners(const Image& image, const std::string& path) {
  if (image.triangles.empty()) return image.corners.size();
  auto mesh = TaggedMesh::FromImage(image);
  if (!mesh.ok()) return Status(mesh.status().code(), path + ": " + mesh.status().message());
  const std::vector<VertexTag>& tags = mesh->vertex_tags();
  return size_t(std::count(tags.begin(), tags.end(), VertexTag::kCorner));
}

// The options of `sdvi convert`.
struct ConvertArgs {
  std::string input, output;
};

int Convert(const ConvertArgs& a) {
  auto kind = KindOfOutput(a.output);
  if (!kind.ok()) return ReportUsage("convert", kind.status().message());
  auto image = LoadAny(a.input);
  if (!image.ok()) return ReportError("convert", image.status());
  // Outputs are always in canonical form (sdvi/format.h).
  const Image canonical = CanonicalizeImage(*image);
  const Status written = *kind == FileKind::kSdvi ? WriteSdvi(a.output, canonical)
                                                  : WriteMeshJsonFile(a.output, canonical);
  if (!written.ok()) return ReportError("convert", written);
  return kExitOk;
}

// The options of `sdvi info`.
struct InfoArgs {
  std::string input;
  bool json = false, features = false;
};

int Info(const InfoArgs& args) {
  if (args.features) return PrintFeatures(args.input, args.json);
  const std::string& path = args.input;
  // Read once: the input may be standard input.
  auto file_bytes = ReadFileBytes(path);
  if (!file_bytes.ok()) return ReportError("info", file_bytes.status());
  auto file = DecodeSdvi(*file_bytes, path);
  if (!file.ok()) return ReportError("info", file.status());
  const Image& image = file->image;
  const bool raw = file->payload == PayloadKind::kRaw;
  const uint64_t vertices = raw ? image.vertices.size() : file->payload_summary.vertex_count;
  const uint64_t triangles = raw ? image.triangles.size() : file->payload_summary.triangle_count;
  const uint64_t pixels = uint64_t{image.width} * image.height;
  const uint64_t paper = PaperSizeBytes(vertices, triangles);
  const bool optional_data = !image.corners.empty() || !image.polylines.empty() ||
                             !image.pairs.empty() || !image.metadata.empty();
  const bool narrow = vertices <= kNarrowProfileMaxVertices;
  size_t corners = 0;
  if (raw) {
    auto counted = CountCorners(image, path);
    if (!counted.ok()) return ReportError("info", counted.status());
    corners = *counted;
  }

  nlohmann::ordered_json j;
  j["file"] = path;
  j["version"] = std::to_string(file->version_major) + "." + std::to_string(file->version_minor);
  j["payload"] = raw ? "raw" : "draco";
  j["profile"] = narrow ? "narrow" : "wide";
  j["width"] = image.width;
  j["height"] = image.height;
  j["vertices"] = vertices;
  j["triangles"] = triangles;
  if (raw) {
    j["tagged_triangles"] = {{"3", file->tagged3}, {"2", file->tagged2}, {"1", file->tagged1},
                             {"0", triangles - file->tagged3 - file->tagged2 - file->tagged1}};
    j["crease_edges"] = image.crease_edges.size();
    j["corners_explicit"] = image.corners.size();
    j["corners"] = corners;
  }
  j["polylines"] = image.polylines.size();
  j["pairs"] = image.pairs.size();
  j["metadata_entries"] = image.metadata.size();
  j["paper_size_bytes"] = paper;
  j["file_bytes"] = file->file_bytes;
  if (raw) {
    j["container_overhead_bytes"] = static_cast<int64_t>(file->file_bytes) - static_cast<int64_t>(paper);
    // spec/FORMAT.md: a raw narrow file with no optional data is at most paper + 64 bytes.
    if (narrow && !optional_data) j["within_paper_bound"] = file->file_bytes <= paper + 64;
  } else {
    j["compressed_payload_bytes"] = file->compressed_payload.size();
#ifdef SDVI_CLI_HAS_CODEC
    auto draco = InspectDracoPayload(file->compressed_payload, path);
    if (!draco.ok()) return ReportError("info", draco.status());
    j["crease_edges"] = draco->crease_edge_count;
    j["corners_explicit"] = draco->corner_count;
    j["draco"] = {{"payload_version", std::to_string(draco->version_major) + "." +
                                          std::to_string(draco->version_minor)},
                  {"position_bits", draco->position_bits},
                  {"color_bits", draco->color_bits},
                  {"colors", draco->grey && draco->stream_colors ? "grey, neighbour mean, tag stream"
                             : draco->grey                ? "grey"
                             : draco->stream_colors  ? "decorrelated, neighbour mean, tag stream"
                             : draco->neighbour_mean ? "decorrelated, neighbour mean"
                             : draco->decorrelated   ? "decorrelated"
                                                     : "rgb"},
                  {"positions", draco->stream_positions ? "tag stream, neighbour mean" : "draco"},
                  {"speed", draco->speed},
                  {"draco_bytes", draco->draco_bytes},
                  {"tag_bytes", draco->tag_bytes}};
    j["feature_layer_in_payload"] = draco->has_feature_layer;
#endif
    j["ratio_to_paper"] = paper ? static_cast<double>(file->file_bytes) / paper : 0.0;
  }
#ifdef SDVI_CLI_HAS_CODEC
  {  // Where the bytes go (PartBytes in sdvi/codec.h).
    auto parts = MeasureParts(*file_bytes, path);
    if (!parts.ok()) return ReportError("info", parts.status());
    j["bytes_by_part"] = {{"connectivity", parts->connectivity}, {"positions", parts->positions},
                          {"colors", parts->colors},             {"tags", parts->tags},
                          {"feature_layer", parts->feature_layer}, {"container", parts->container}};
  }
#endif
  j["compression_ratio"] = vertices ? static_cast<double>(pixels) / vertices : 0.0;
  j["bits_per_pixel"] = pixels ? 8.0 * file->file_bytes / pixels : 0.0;

  if (args.json) {
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("file               %s\n", path.c_str());
  std::printf("format version     %s (%s payload, %s profile)\n",
              j["version"].get<std::string>().c_str(), raw ? "raw" : "Draco",
              narrow ? "narrow uint16" : "wide uint32");
  std::printf("image size         %u x %u pixels\n", image.width, image.height);
  std::printf("vertices           %llu\n", static_cast<unsigned long long>(vertices));
  std::printf("triangles          %llu\n", static_cast<unsigned long long>(triangles));
  if (raw) {
    std::printf("tagged triangles   3: %u  2: %u  1: %u  untagged: %llu\n", file->tagged3,
                file->tagged2, file->tagged1,
                static_cast<unsigned long long>(triangles - file->tagged3 - file->tagged2 -
                                                file->tagged1));
    std::printf("crease edges       %zu\n", image.crease_edges.size());
    std::printf("corners            %zu (%zu explicit)\n", corners,
                image.corners.size());
  }
  if (!raw && j.contains("draco")) {
    const auto& d = j["draco"];
    std::printf("crease edges       %llu\n", j["crease_edges"].get<unsigned long long>());
    std::printf("corners            %llu explicit\n", j["corners_explicit"].get<unsigned long long>());
    std::printf("Draco payload      version %s, %d position bits%s, %d colour bits (%s), speed %d "
                "(%llu Draco + %llu tag bytes)\n",
                d["payload_version"].get<std::string>().c_str(), d["position_bits"].get<int>(),
                d.value("positions", "draco") == "draco" ? "" : " (in the tag stream, neighbour mean)",
                d["color_bits"].get<int>(), d["colors"].get<std::string>().c_str(), d["speed"].get<int>(),
                d["draco_bytes"].get<unsigned long long>(), d["tag_bytes"].get<unsigned long long>());
  }
  if (j.value("feature_layer_in_payload", false))
    std::printf("feature layer      inside the Draco payload\n");
  else
    std::printf("feature layer      %zu polylines, %zu pairs\n", image.polylines.size(),
                image.pairs.size());
  std::printf("metadata entries   %zu\n", image.metadata.size());
  std::printf("paper size         %llu bytes (20 V + 6 T + 8)\n",
              static_cast<unsigned long long>(paper));
  std::printf("file size          %llu bytes", static_cast<unsigned long long>(file->file_bytes));
  if (raw) std::printf(" (container adds %lld)", static_cast<long long>(file->file_bytes) - static_cast<long long>(paper));
  else
    std::printf(" (Draco payload %zu; %.3f x the paper size)", file->compressed_payload.size(),
                j["ratio_to_paper"].get<double>());
  std::printf("\n");
  if (j.contains("bytes_by_part")) {
    std::printf("bytes by part     ");
    for (const auto& [part, n] : j["bytes_by_part"].items())
      std::printf(" %s %llu (%.1f%%)", part.c_str(), n.get<unsigned long long>(),
                  file->file_bytes ? 100.0 * n.get<double>() / double(file->file_bytes) : 0.0);
    std::printf("\n");
  }
  std::printf("compression ratio  %.2f pixels per vertex\n", j["compression_ratio"].get<double>());
  std::printf("bits per pixel     %.3f\n", j["bits_per_pixel"].get<double>());
  return kExitOk;
}

}  // namespace

void RegisterConvert(CLI::App& app, Outcome& outcome) {
  auto a = std::make_shared<ConvertArgs>();
  CLI::App* c = AddCommand(
      app, "convert", "convert between .sdvi and the human-readable mesh JSON (spec/MESH_JSON.md); outputs are canonical",
      {"sdvi convert in.sdvi mesh.json", "sdvi convert mesh.json out.sdvi"});
  MarkInput(c, a->input);
  c->add_option("input", a->input, "a .sdvi (any payload) or a mesh .json; '-' reads standard input")->required()->type_name("IN");
  MarkOutput(c, a->output);
  c->add_option("output", a->output, "OUT.sdvi or OUT.json (the extension chooses the format)")->required()->type_name("OUT");
  SetAction(c, outcome, [a] { return Convert(*a); });
}

void RegisterInfo(CLI::App& app, Outcome& outcome) {
  auto a = std::make_shared<InfoArgs>();
  CLI::App* c = AddCommand(
      app, "info", "what a .sdvi file holds: version, counts, tags, paper size, file size, payload",
      {"sdvi info photo.sdvi", "sdvi info photo.sdvi --json",
       "sdvi info photo.sdvi --features   # feature ids for sdvi edit"});
  MarkInput(c, a->input);
  c->add_option("input", a->input, "the .sdvi file ('-' reads standard input)")->required()->type_name("FILE.sdvi");
  c->add_flag("--features", a->features,
              "list the features instead: id, kind, sharpness, length, bounding box, vertex count (spec/EDIT.md)");
  AddJson(c, a->json);
  SetAction(c, outcome, [a] { return Info(*a); });
}

}  // namespace sdvi::cli
