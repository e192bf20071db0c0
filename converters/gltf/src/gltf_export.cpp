// SPDX-License-Identifier: GPL-3.0-or-later
// glTF 2.0 export: limit surface -> tinygltf model (+ Draco buffer view) -> .glb / .gltf.
// The mapping (units, orientation, colour space, extras) is specified in spec/GLTF.md.
#include "sdvi/gltf.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <new>
#include <sstream>
#include <stdexcept>
#include <utility>

// tinygltf is a compiled library here: declarations only (no TINYGLTF_IMPLEMENTATION).
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

#include "sdvi/export_levels.h"
#include "sdvi/file_util.h"
#include "sdvi/progress.h"
#include "sdvi/subdiv.h"

#ifndef SDVI_VERSION
#define SDVI_VERSION "unknown"
#endif

namespace sdvi {
namespace {

constexpr int kArrayBuffer = TINYGLTF_TARGET_ARRAY_BUFFER;
constexpr int kElementArrayBuffer = TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;

// Twice the signed area of control triangle t in source coordinates (y down); 0 when an
// index is out of range (the engine reports those when it builds the surface).
double SignedArea2(const Image& image, const Triangle& t) {
  for (uint32_t v : t.v) {
    if (v >= image.vertices.size()) return 0;
  }
  const Vertex& a = image.vertices[t.v[0]];
  const Vertex& b = image.vertices[t.v[1]];
  const Vertex& c = image.vertices[t.v[2]];
  return (double(b.x) - a.x) * (double(c.y) - a.y) - (double(b.y) - a.y) * (double(c.x) - a.x);
}

// A flat mesh in glTF coordinates, ready for buffers.
struct GltfMesh {
  std::vector<float> positions;  // xyz per vertex
  std::vector<float> colors;     // linear rgb per vertex
  std::vector<uint32_t> indices; // 3 per triangle, counter-clockwise seen from +Z
};

void AppendGltfVertex(const Vertex& v, uint32_t height, GltfMesh* mesh) {
  mesh->positions.insert(mesh->positions.end(), {v.x, float(height) - v.y, 0.0f});
  for (float c : {v.r, v.g, v.b}) mesh->colors.push_back(SrgbToLinear(c / 255.0f));
}

// Whether control triangle t must have its vertex order reversed to be counter-clockwise
// seen from +Z after the y flip. Source-space counter-clockwise (y down) is clockwise
// after the flip. Degenerate triangles follow the mesh's overall orientation.
std::vector<bool> ControlTrianglesToReverse(const Image& image) {
  double total = 0;
  std::vector<double> area(image.triangles.size());
  for (size_t t = 0; t < image.triangles.size(); ++t) {
    area[t] = SignedArea2(image, image.triangles[t]);
    total += area[t];
  }
  std::vector<bool> reverse(image.triangles.size());
  // In glTF coordinates the signed area is -area (y flipped): reverse when -area < 0.
  for (size_t t = 0; t < area.size(); ++t) reverse[t] = (area[t] != 0 ? area[t] : total) > 0;
  return reverse;
}

void MinMax(const std::vector<float>& values, int components, std::vector<double>* min,
            std::vector<double>* max) {
  min->assign(components, std::numeric_limits<double>::infinity());
  max->assign(components, -std::numeric_limits<double>::infinity());
  for (size_t i = 0; i < values.size(); ++i) {
    const int c = int(i % components);
    (*min)[c] = std::min((*min)[c], double(values[i]));
    (*max)[c] = std::max((*max)[c], double(values[i]));
  }
}

// Appends bytes to buffer 0 as a new buffer view (4-byte aligned); returns its index.
int AddBufferView(tinygltf::Model* model, const void* data, size_t size, int target,
                  const std::string& name) {
  std::vector<unsigned char>& buffer = model->buffers[0].data;
  buffer.resize((buffer.size() + 3) & ~size_t(3), 0);
  tinygltf::BufferView view;
  view.name = name;
  view.buffer = 0;
  view.byteOffset = buffer.size();
  view.byteLength = size;
  view.target = target;
  const auto* bytes = static_cast<const unsigned char*>(data);
  buffer.insert(buffer.end(), bytes, bytes + size);
  model->bufferViews.push_back(std::move(view));
  return int(model->bufferViews.size() - 1);
}

int AddAccessor(tinygltf::Model* model, int buffer_view, int component_type, int type,
                size_t count, std::vector<double> min, std::vector<double> max,
                const std::string& name) {
  tinygltf::Accessor accessor;
  accessor.name = name;
  accessor.bufferView = buffer_view;
  accessor.componentType = component_type;
  accessor.type = type;
  accessor.count = count;
  accessor.minValues = std::move(min);
  accessor.maxValues = std::move(max);
  model->accessors.push_back(std::move(accessor));
  return int(model->accessors.size() - 1);
}

// Float VEC3 attribute accessor with min/max (required for POSITION, useful for COLOR_0).
int AddVec3Accessor(tinygltf::Model* model, const std::vector<float>& values,
                    const std::string& name) {
  std::vector<double> min, max;
  MinMax(values, 3, &min, &max);
  const int view = AddBufferView(model, values.data(), values.size() * sizeof(float),
                                 kArrayBuffer, name);
  return AddAccessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
                     values.size() / 3, std::move(min), std::move(max), name);
}

// Index accessor: unsigned short when every index fits below the restart value 65535.
int AddIndexAccessor(tinygltf::Model* model, const std::vector<uint32_t>& indices,
                     uint32_t vertex_count, const std::string& name) {
  if (vertex_count < 65535) {
    std::vector<uint16_t> narrow(indices.begin(), indices.end());
    const int view = AddBufferView(model, narrow.data(), narrow.size() * sizeof(uint16_t),
                                   kElementArrayBuffer, name);
    return AddAccessor(model, view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                       TINYGLTF_TYPE_SCALAR, indices.size(), {}, {}, name);
  }
  const int view = AddBufferView(model, indices.data(), indices.size() * sizeof(uint32_t),
                                 kElementArrayBuffer, name);
  return AddAccessor(model, view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                     indices.size(), {}, {}, name);
}

// An unlit material: base colour factor times the vertex colour (when present).
int AddUnlitMaterial(tinygltf::Model* model, const std::string& name,
                     std::vector<double> base_color) {
  tinygltf::Material material;
  material.name = name;
  material.doubleSided = true;  // folded fine triangles and back views still fill
  material.pbrMetallicRoughness.baseColorFactor = std::move(base_color);
  material.pbrMetallicRoughness.metallicFactor = 0.0;  // fallback for viewers without unlit
  material.pbrMetallicRoughness.roughnessFactor = 1.0;
  material.extensions["KHR_materials_unlit"] = tinygltf::Value(tinygltf::Value::Object());
  model->materials.push_back(std::move(material));
  return int(model->materials.size() - 1);
}

void UseExtension(tinygltf::Model* model, const std::string& name, bool required) {
  auto add = [&name](std::vector<std::string>* list) {
    if (std::find(list->begin(), list->end(), name) == list->end()) list->push_back(name);
  };
  add(&model->extensionsUsed);
  if (required) add(&model->extensionsRequired);
}

// Compresses mesh with Draco and adds the buffer view and the KHR_draco_mesh_compression
// primitive (accessors without buffer views, counts and min/max of the decoded data).
StatusOr<tinygltf::Primitive> AddDracoPrimitive(tinygltf::Model* model, const GltfMesh& mesh,
                                                const GltfExportOptions& options,
                                                uint64_t* draco_bytes, uint32_t* vertices) {
  const uint32_t n = uint32_t(mesh.positions.size() / 3);
  draco::Mesh dmesh;
  dmesh.set_num_points(n);
  auto add_vec3 = [&](draco::GeometryAttribute::Type type, const std::vector<float>& values) {
    draco::GeometryAttribute att;
    att.Init(type, nullptr, 3, draco::DT_FLOAT32, false, sizeof(float) * 3, 0);
    const int id = dmesh.AddAttribute(att, /*identity_mapping=*/true, n);
    for (uint32_t i = 0; i < n; ++i) {
      dmesh.attribute(id)->SetAttributeValue(draco::AttributeValueIndex(i), &values[3 * i]);
    }
    return id;
  };
  const int pos_id = add_vec3(draco::GeometryAttribute::POSITION, mesh.positions);
  const int col_id = add_vec3(draco::GeometryAttribute::COLOR, mesh.colors);
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    dmesh.AddFace({draco::PointIndex(mesh.indices[t]), draco::PointIndex(mesh.indices[t + 1]),
                   draco::PointIndex(mesh.indices[t + 2])});
  }

  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, options.position_bits);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::COLOR, options.color_bits);
  encoder.SetSpeedOptions(options.draco_speed, options.draco_speed);
  encoder.SetEncodingMethod(draco::MESH_EDGEBREAKER_ENCODING);
  draco::EncoderBuffer encoded;
  const draco::Status encode_status = encoder.EncodeMeshToBuffer(dmesh, &encoded);
  if (!encode_status.ok()) {
    return Status(StatusCode::kEncodeFailed,
                  "glTF export: Draco could not encode the surface mesh (" +
                      std::to_string(n) + " vertices): " + encode_status.error_msg_string());
  }

  // Decode once: the accessors must describe what a loader will get back (edgebreaker
  // reorders points and faces, quantization moves positions).
  draco::DecoderBuffer decode_buffer;
  decode_buffer.Init(encoded.data(), encoded.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&decode_buffer);
  if (!decoded.ok()) {
    return Status(StatusCode::kEncodeFailed,
                  "glTF export: Draco cannot decode its own surface encoding: " +
                      decoded.status().error_msg_string());
  }
  const draco::Mesh& back = *decoded.value();
  const draco::PointAttribute* back_pos = back.GetAttributeByUniqueId(dmesh.attribute(pos_id)->unique_id());
  const draco::PointAttribute* back_col = back.GetAttributeByUniqueId(dmesh.attribute(col_id)->unique_id());
  if (back_pos == nullptr || back_col == nullptr || back.num_faces() != mesh.indices.size() / 3) {
    return Status(StatusCode::kEncodeFailed,
                  "glTF export: the Draco round trip lost attributes or faces");
  }
  std::vector<float> pos(size_t(back.num_points()) * 3), col(size_t(back.num_points()) * 3);
  for (draco::PointIndex p(0); p < back.num_points(); ++p) {
    back_pos->GetMappedValue(p, &pos[3 * p.value()]);
    back_col->GetMappedValue(p, &col[3 * p.value()]);
  }

  *draco_bytes = encoded.size();
  *vertices = back.num_points();
  const int view = AddBufferView(model, encoded.data(), encoded.size(), /*target=*/0,
                                 "surface (Draco)");
  std::vector<double> min, max;
  tinygltf::Primitive primitive;
  MinMax(pos, 3, &min, &max);
  primitive.attributes["POSITION"] =
      AddAccessor(model, -1, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
                  back.num_points(), min, max, "surface POSITION");
  MinMax(col, 3, &min, &max);
  primitive.attributes["COLOR_0"] =
      AddAccessor(model, -1, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
                  back.num_points(), min, max, "surface COLOR_0");
  primitive.indices = AddAccessor(
      model, -1,
      back.num_points() < 65535 ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT
                                : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
      TINYGLTF_TYPE_SCALAR, size_t(back.num_faces()) * 3, {}, {}, "surface indices");

  tinygltf::Value::Object attributes;
  attributes["POSITION"] = tinygltf::Value(int(dmesh.attribute(pos_id)->unique_id()));
  attributes["COLOR_0"] = tinygltf::Value(int(dmesh.attribute(col_id)->unique_id()));
  tinygltf::Value::Object extension;
  extension["bufferView"] = tinygltf::Value(view);
  extension["attributes"] = tinygltf::Value(std::move(attributes));
  primitive.extensions["KHR_draco_mesh_compression"] = tinygltf::Value(std::move(extension));
  UseExtension(model, "KHR_draco_mesh_compression", /*required=*/true);
  return primitive;
}

Status CheckOptions(const GltfExportOptions& options) {
  if (options.levels < -1 || options.levels > kMaxGltfLevels) {
    return Status(StatusCode::kInvalidArgument,
                  "glTF export: levels " + std::to_string(options.levels) +
                      " is outside 0.." + std::to_string(kMaxGltfLevels) + " (or -1 for auto)");
  }
  for (auto [name, bits] : {std::pair{"position", options.position_bits},
                            std::pair{"color", options.color_bits}}) {
    if (bits < 1 || bits > kMaxGltfDracoBits) {
      return Status(StatusCode::kInvalidArgument,
                    std::string("glTF export: Draco ") + name + " quantization bits " +
                        std::to_string(bits) + " is outside 1.." + std::to_string(kMaxGltfDracoBits));
    }
  }
  if (options.draco_speed < 0 || options.draco_speed > 10) {
    return Status(StatusCode::kInvalidArgument,
                  "glTF export: Draco speed " + std::to_string(options.draco_speed) +
                      " is outside 0..10");
  }
  return Status::Ok();
}

// The control mesh: triangles with control colours and the crease edges (listed ones plus
// the mesh boundary) as lines, in glTF coordinates.
void AddControlMeshNode(tinygltf::Model* model, const Image& image,
                        const std::vector<bool>& reverse) {
  GltfMesh control;
  for (const Vertex& v : image.vertices) AppendGltfVertex(v, image.height, &control);
  std::map<Edge, int> edge_use;
  for (size_t t = 0; t < image.triangles.size(); ++t) {
    const auto& v = image.triangles[t].v;
    if (reverse[t]) {
      control.indices.insert(control.indices.end(), {v[0], v[2], v[1]});
    } else {
      control.indices.insert(control.indices.end(), {v[0], v[1], v[2]});
    }
    for (int k = 0; k < 3; ++k) ++edge_use[Edge::Of(v[k], v[(k + 1) % 3])];
  }
  std::vector<Edge> creases = image.crease_edges;
  for (const auto& [edge, uses] : edge_use) {
    if (uses == 1) creases.push_back(edge);
  }
  std::sort(creases.begin(), creases.end());
  creases.erase(std::unique(creases.begin(), creases.end()), creases.end());
  std::vector<uint32_t> lines;
  for (const Edge& e : creases) lines.insert(lines.end(), {e.a, e.b});

  const uint32_t n = uint32_t(image.vertices.size());
  tinygltf::Mesh mesh;
  mesh.name = "sdvi control mesh";
  tinygltf::Primitive triangles;
  triangles.attributes["POSITION"] = AddVec3Accessor(model, control.positions, "control POSITION");
  triangles.attributes["COLOR_0"] = AddVec3Accessor(model, control.colors, "control COLOR_0");
  triangles.indices = AddIndexAccessor(model, control.indices, n, "control triangles");
  triangles.material = AddUnlitMaterial(model, "sdvi control colours", {1.0, 1.0, 1.0, 1.0});
  triangles.mode = TINYGLTF_MODE_TRIANGLES;
  mesh.primitives.push_back(triangles);
  if (!lines.empty()) {
    tinygltf::Primitive crease_lines;
    crease_lines.attributes["POSITION"] = triangles.attributes["POSITION"];
    crease_lines.indices = AddIndexAccessor(model, lines, n, "crease edges");
    crease_lines.material = AddUnlitMaterial(model, "sdvi crease edges", {1.0, 0.0, 0.0, 1.0});
    crease_lines.mode = TINYGLTF_MODE_LINE;
    mesh.primitives.push_back(crease_lines);
  }
  model->meshes.push_back(std::move(mesh));

  tinygltf::Node node;
  node.name = "sdvi control mesh";
  node.mesh = int(model->meshes.size() - 1);
  // Beside the surface, to the right, with a gap of 5% of the width.
  node.translation = {std::ceil(image.width * 1.05), 0.0, 0.0};
  model->nodes.push_back(std::move(node));
  model->scenes[0].nodes.push_back(int(model->nodes.size() - 1));
}

// text with every byte that does not start a well-formed UTF-8 sequence (RFC 3629: no
// overlong forms, no surrogates, at most U+10FFFF) replaced by U+FFFD: JSON needs UTF-8.
std::string ValidUtf8(const std::string& text) {
  std::string out;
  const auto* p = reinterpret_cast<const unsigned char*>(text.data());
  const size_t n = text.size();
  auto cont = [&](size_t i, unsigned char lo = 0x80, unsigned char hi = 0xBF) {
    return i < n && p[i] >= lo && p[i] <= hi;
  };
  for (size_t i = 0; i < n;) {
    const unsigned char c = p[i];
    size_t len = 0;
    if (c < 0x80) len = 1;
    else if (c >= 0xC2 && c <= 0xDF && cont(i + 1)) len = 2;
    else if (c == 0xE0 && cont(i + 1, 0xA0) && cont(i + 2)) len = 3;
    else if (((c >= 0xE1 && c <= 0xEC) || c == 0xEE || c == 0xEF) && cont(i + 1) && cont(i + 2)) len = 3;
    else if (c == 0xED && cont(i + 1, 0x80, 0x9F) && cont(i + 2)) len = 3;
    else if (c == 0xF0 && cont(i + 1, 0x90) && cont(i + 2) && cont(i + 3)) len = 4;
    else if (c >= 0xF1 && c <= 0xF3 && cont(i + 1) && cont(i + 2) && cont(i + 3)) len = 4;
    else if (c == 0xF4 && cont(i + 1, 0x80, 0x8F) && cont(i + 2) && cont(i + 3)) len = 4;
    if (len == 0) {
      out += "\xEF\xBF\xBD";
      ++i;
    } else {
      out.append(text, i, len);
      i += len;
    }
  }
  return out;
}

std::string Copyright(const Image& image, const GltfExportOptions& options) {
  if (!options.copyright.empty()) return ValidUtf8(options.copyright);
  for (const auto& [key, value] : image.metadata) {
    if (key == "copyright" && !value.empty()) return ValidUtf8(value);
  }
  return "unspecified";
}

}  // namespace

float SrgbToLinear(float srgb) {
  const float s = std::clamp(std::isfinite(srgb) ? srgb : 0.0f, 0.0f, 1.0f);
  return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
}

int DefaultGltfLevels(const Image& image) { return DefaultExportLevels(image); }

StatusOr<GltfContainer> GltfContainerForPath(const std::string& path) {
  const std::string ext = FileExtension(path);
  if (ext == "glb") return GltfContainer::kBinary;
  if (ext == "gltf") return GltfContainer::kText;
  return Status(StatusCode::kInvalidArgument,
                path + ": a glTF output must end in .glb (binary) or .gltf (text)");
}

namespace {

// The .gltf JSON text with buffer 0 given as uri and byte_length (key order kept).
std::string PointBufferAtFile(const std::string& gltf, const std::string& uri, size_t byte_length) {
  nlohmann::ordered_json doc = nlohmann::ordered_json::parse(gltf);
  doc["buffers"][0]["byteLength"] = byte_length;
  doc["buffers"][0]["uri"] = uri;
  return doc.dump(2);
}

StatusOr<GltfExport> EncodeGltfOrThrow(const Image& image, const GltfExportOptions& options) {
  SDVI_RETURN_IF_ERROR(CheckOptions(options));
  SDVI_RETURN_IF_ERROR(CheckExportInput(image, "glTF export"));
  GltfExport result;
  result.levels = options.levels >= 0 ? options.levels : DefaultGltfLevels(image);
  const uint64_t fine_triangles = uint64_t(image.triangles.size()) << (2 * result.levels);
  if (fine_triangles > kMaxGltfFineTriangles) {
    return Status(StatusCode::kLimitExceeded,
                  "glTF export: level " + std::to_string(result.levels) + " gives " +
                      std::to_string(fine_triangles) + " triangles, over the limit of " +
                      std::to_string(kMaxGltfFineTriangles));
  }

  LimitSurfaceOptions surface_options;
  surface_options.levels = result.levels;
  surface_options.to_limit = true;
  if (options.progress) options.progress->Phase("limit surface (level " + std::to_string(result.levels) + ")");
  SDVI_ASSIGN_OR_RETURN(LimitSurface surface, BuildLimitSurface(image, surface_options));
  const std::vector<Vertex> fine = EvaluateSurface(surface, image.vertices);
  const std::vector<bool> reverse = ControlTrianglesToReverse(image);

  GltfMesh mesh;
  mesh.positions.reserve(fine.size() * 3);
  mesh.colors.reserve(fine.size() * 3);
  for (const Vertex& v : fine) AppendGltfVertex(v, image.height, &mesh);
  mesh.indices.reserve(surface.triangles.size() * 3);
  for (size_t t = 0; t < surface.triangles.size(); ++t) {
    const auto& v = surface.triangles[t].v;
    const uint32_t parent = t < surface.parent_triangle.size() ? surface.parent_triangle[t] : 0;
    if (parent < reverse.size() && reverse[parent]) {
      mesh.indices.insert(mesh.indices.end(), {v[0], v[2], v[1]});
    } else {
      mesh.indices.insert(mesh.indices.end(), {v[0], v[1], v[2]});
    }
  }
  for (uint32_t i : mesh.indices) {
    if (i >= fine.size()) {
      return Status(StatusCode::kInternal, "glTF export: a fine triangle refers to vertex " +
                                               std::to_string(i) + " of " +
                                               std::to_string(fine.size()));
    }
  }
  result.vertices = uint32_t(fine.size());
  result.triangles = uint32_t(surface.triangles.size());

  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = std::string("sdvi ") + SDVI_VERSION;
  model.asset.copyright = Copyright(image, options);
  tinygltf::Value::Object sdvi_extras;
  sdvi_extras["source_width"] = tinygltf::Value(int(image.width));
  sdvi_extras["source_height"] = tinygltf::Value(int(image.height));
  sdvi_extras["levels"] = tinygltf::Value(result.levels);
  sdvi_extras["unit"] = tinygltf::Value(std::string("source pixel"));
  sdvi_extras["origin"] = tinygltf::Value(std::string("bottom-left corner of the image"));
  tinygltf::Value::Object asset_extras;
  asset_extras["sdvi"] = tinygltf::Value(std::move(sdvi_extras));
  model.asset.extras = tinygltf::Value(std::move(asset_extras));
  model.buffers.emplace_back();
  // Room for the surface's attributes and indices (and the control mesh): no regrowth.
  size_t reserve = mesh.positions.size() * 8 + mesh.indices.size() * 4 + 64;
  if (options.control_mesh) reserve += image.vertices.size() * 24 + image.triangles.size() * 20 + 64;
  model.buffers[0].data.reserve(reserve);
  model.scenes.emplace_back();
  model.scenes[0].name = "sdvi image";
  model.defaultScene = 0;
  UseExtension(&model, "KHR_materials_unlit", /*required=*/false);

  if (options.progress) options.progress->Phase(options.draco ? "Draco encoding" : "glTF encoding");
  tinygltf::Primitive primitive;
  if (options.draco) {
    SDVI_ASSIGN_OR_RETURN(primitive, AddDracoPrimitive(&model, mesh, options, &result.draco_bytes,
                                                       &result.vertices));
  } else {
    primitive.attributes["POSITION"] = AddVec3Accessor(&model, mesh.positions, "surface POSITION");
    primitive.attributes["COLOR_0"] = AddVec3Accessor(&model, mesh.colors, "surface COLOR_0");
    primitive.indices = AddIndexAccessor(&model, mesh.indices, result.vertices, "surface indices");
  }
  primitive.material = AddUnlitMaterial(&model, "sdvi unlit vertex colour", {1.0, 1.0, 1.0, 1.0});
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  tinygltf::Mesh surface_mesh;
  surface_mesh.name = "sdvi limit surface";
  surface_mesh.primitives.push_back(std::move(primitive));
  model.meshes.push_back(std::move(surface_mesh));
  tinygltf::Node node;
  node.name = "sdvi surface";
  node.mesh = 0;
  model.nodes.push_back(std::move(node));
  model.scenes[0].nodes.push_back(0);

  if (options.control_mesh) AddControlMeshNode(&model, image, reverse);

  // The BIN chunk / data: URI holds exactly byteLength bytes: pad the buffer to 4.
  model.buffers[0].data.resize((model.buffers[0].data.size() + 3) & ~size_t(3), 0);
  if (model.buffers[0].data.size() > std::numeric_limits<uint32_t>::max() - 4096) {
    return Status(StatusCode::kLimitExceeded, "glTF export: the buffer (" +
                                                  std::to_string(model.buffers[0].data.size()) +
                                                  " bytes) exceeds what a .glb can hold");
  }

  std::ostringstream out(std::ios::binary);
  tinygltf::TinyGLTF writer;
  const bool binary = options.container == GltfContainer::kBinary;
  // tinygltf's stream writer embeds every buffer of a .gltf: for a .bin beside it, take
  // the data out first and point the buffer at the file afterwards.
  const bool external = !binary && !options.embed && !options.bin_uri.empty();
  if (external) result.bin = std::move(model.buffers[0].data);
  if (!writer.WriteGltfSceneToStream(&model, out, /*prettyPrint=*/!binary, binary)) {
    return Status(StatusCode::kEncodeFailed, "glTF export: tinygltf could not serialize the model");
  }
  std::string bytes = std::move(out).str();  // C++20: moves the stream's buffer out
  if (external) bytes = PointBufferAtFile(bytes, options.bin_uri, result.bin.size());
  result.bytes.assign(bytes.begin(), bytes.end());
  if (options.progress) options.progress->Done();
  return result;
}

}  // namespace

StatusOr<GltfExport> EncodeGltf(const Image& image, const GltfExportOptions& options) {
  // tinygltf's JSON writer throws (e.g. on text that is not UTF-8), allocations may fail.
  try {
    return EncodeGltfOrThrow(image, options);
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::kLimitExceeded, "glTF export: out of memory");
  } catch (const std::exception& e) {
    return Status(StatusCode::kEncodeFailed, std::string("glTF export: ") + e.what());
  }
}

std::string GltfBinPath(const std::string& gltf_path) {
  return std::filesystem::path(gltf_path).replace_extension(".bin").string();
}

std::string GltfBinUri(const std::string& gltf_path) {
  const std::string name = std::filesystem::path(GltfBinPath(gltf_path)).filename().string();
  std::string uri;
  for (unsigned char c : name) {
    if (std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~') {
      uri += char(c);
    } else {
      static const char kHex[] = "0123456789ABCDEF";
      uri += '%';
      uri += kHex[c >> 4];
      uri += kHex[c & 15];
    }
  }
  return uri;
}

StatusOr<GltfExport> WriteGltf(const std::string& path, const Image& image,
                               GltfExportOptions options) {
  SDVI_ASSIGN_OR_RETURN(options.container, GltfContainerForPath(path));
  const bool external = options.container == GltfContainer::kText && !options.embed;
  options.bin_uri = external ? GltfBinUri(path) : std::string();
  SDVI_ASSIGN_OR_RETURN(GltfExport result, EncodeGltf(image, options));
  if (external) {
    const std::string bin_path = GltfBinPath(path);
    SDVI_RETURN_IF_ERROR(WriteFileAtomic(bin_path, result.bin));
    if (Status written = WriteFileAtomic(path, result.bytes); !written.ok()) {
      std::error_code ignored;
      std::filesystem::remove(bin_path, ignored);
      return written;
    }
    return result;
  }
  SDVI_RETURN_IF_ERROR(WriteFileAtomic(path, result.bytes));
  return result;
}

}  // namespace sdvi
