// SPDX-License-Identifier: GPL-3.0-or-later
// Mesh JSON <-> sdvi::Image (spec/MESH_JSON.md).
#include "sdvi/mesh_json.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>

#include "sdvi/file_util.h"
#include "sdvi/format.h"

namespace sdvi {
namespace {

// A JSON document whose floating-point numbers are float32, parsed with strtof: a float
// printed as its shortest round-trip decimal reads back to the same bits.
using Json = nlohmann::basic_json<nlohmann::ordered_map, std::vector, std::string, bool,
                                  std::int64_t, std::uint64_t, float>;

constexpr const char* kFormatName = "sdvi-mesh";
constexpr int kMeshJsonVersion = 1;

class Parser {
 public:
  explicit Parser(std::string source) : source_(std::move(source)) {}

  Status Shape(const std::string& where, const std::string& expected) const {
    return Status(StatusCode::kCorrupt, source_ + ": " + where + " must be " + expected);
  }

  StatusOr<const Json*> Array(const Json& j, const std::string& where, size_t size = 0) const {
    if (!j.is_array() || (size > 0 && j.size() != size))
      return Shape(where, size > 0 ? "an array of " + std::to_string(size) + " elements"
                                   : std::string("an array"));
    return &j;
  }

  StatusOr<float> Number(const Json& j, const std::string& where) const {
    if (!j.is_number()) return Shape(where, "a number");
    return j.get<float>();
  }

  StatusOr<uint32_t> Index(const Json& j, const std::string& where) const {
    if (j.is_number_unsigned()) {
      const uint64_t v = j.get<uint64_t>();
      if (v > std::numeric_limits<uint32_t>::max())
        return Status(StatusCode::kIndexOutOfRange,
                      source_ + ": " + where + " = " + std::to_string(v) + " is beyond 2^32 - 1");
      return static_cast<uint32_t>(v);
    }
    if (j.is_number_integer())
      return Status(StatusCode::kIndexOutOfRange, source_ + ": " + where + " is negative");
    return Shape(where, "a non-negative integer");
  }

  StatusOr<std::vector<uint32_t>> Indices(const Json& j, const std::string& where) const {
    SDVI_ASSIGN_OR_RETURN(const Json* arr, Array(j, where));
    std::vector<uint32_t> out;
    out.reserve(arr->size());
    for (size_t i = 0; i < arr->size(); ++i) {
      SDVI_ASSIGN_OR_RETURN(uint32_t v, Index((*arr)[i], where + "[" + std::to_string(i) + "]"));
      out.push_back(v);
    }
    return out;
  }

  StatusOr<std::string> String(const Json& j, const std::string& where) const {
    if (!j.is_string()) return Shape(where, "a string");
    return j.get<std::string>();
  }

  StatusOr<Image> ParseImage(const Json& root) const {
    if (!root.is_object()) return Shape("the document", "a JSON object");
    static const std::set<std::string> kKeys = {
        "format", "version", "width", "height", "vertices", "triangles", "crease_edges",
        "corners", "polylines", "pairs", "metadata"};
    for (const auto& item : root.items())
      if (!kKeys.count(item.key()))
        return Status(StatusCode::kInvalidArgument,
                      source_ + ": unknown key '" + item.key() + "' in the mesh JSON");
    if (root.contains("format")) {
      SDVI_ASSIGN_OR_RETURN(std::string name, String(root["format"], "format"));
      if (name != kFormatName)
        return Status(StatusCode::kInvalidArgument,
                      source_ + ": format is '" + name + "', expected '" + kFormatName + "'");
    }
    if (root.contains("version")) {
      const Json& v = root["version"];
      if (!v.is_number_integer()) return Shape("version", "an integer");
      if (v.get<int64_t>() != kMeshJsonVersion)
        return Status(StatusCode::kUnsupportedVersion,
                      source_ + ": mesh JSON version " + std::to_string(v.get<int64_t>()) +
                          "; this build reads version " + std::to_string(kMeshJsonVersion));
    }
    Image image;
    for (const char* key : {"width", "height", "vertices", "triangles"})
      if (!root.contains(key))
        return Status(StatusCode::kCorrupt, source_ + ": missing required key '" + key + "'");
    SDVI_ASSIGN_OR_RETURN(image.width, Index(root["width"], "width"));
    SDVI_ASSIGN_OR_RETURN(image.height, Index(root["height"], "height"));

    SDVI_ASSIGN_OR_RETURN(const Json* vertices, Array(root["vertices"], "vertices"));
    image.vertices.reserve(vertices->size());
    for (size_t i = 0; i < vertices->size(); ++i) {
      const std::string where = "vertices[" + std::to_string(i) + "]";
      SDVI_ASSIGN_OR_RETURN(const Json* v, Array((*vertices)[i], where + " ([x, y, R, G, B])", 5));
      float c[5];
      for (size_t k = 0; k < 5; ++k) {
        SDVI_ASSIGN_OR_RETURN(c[k], Number((*v)[k], where + "[" + std::to_string(k) + "]"));
      }
      image.vertices.push_back(Vertex{c[0], c[1], c[2], c[3], c[4]});
    }

    SDVI_ASSIGN_OR_RETURN(const Json* triangles, Array(root["triangles"], "triangles"));
    image.triangles.reserve(triangles->size());
    for (size_t i = 0; i < triangles->size(); ++i) {
      const std::string where = "triangles[" + std::to_string(i) + "]";
      SDVI_ASSIGN_OR_RETURN(const Json* t, Array((*triangles)[i], where, 3));
      Triangle tri;
      for (size_t k = 0; k < 3; ++k) {
        SDVI_ASSIGN_OR_RETURN(tri.v[k], Index((*t)[k], where + "[" + std::to_string(k) + "]"));
      }
      image.triangles.push_back(tri);
    }

    if (root.contains("crease_edges")) {
      SDVI_ASSIGN_OR_RETURN(const Json* edges, Array(root["crease_edges"], "crease_edges"));
      for (size_t i = 0; i < edges->size(); ++i) {
        const std::string where = "crease_edges[" + std::to_string(i) + "]";
        SDVI_ASSIGN_OR_RETURN(const Json* e, Array((*edges)[i], where, 2));
        SDVI_ASSIGN_OR_RETURN(uint32_t a, Index((*e)[0], where + "[0]"));
        SDVI_ASSIGN_OR_RETURN(uint32_t b, Index((*e)[1], where + "[1]"));
        if (a == b)
          return Status(StatusCode::kInvalidArgument,
                        source_ + ": " + where + " joins vertex " + std::to_string(a) + " to itself");
        image.crease_edges.push_back(Edge::Of(a, b));
      }
      std::sort(image.crease_edges.begin(), image.crease_edges.end());
      image.crease_edges.erase(std::unique(image.crease_edges.begin(), image.crease_edges.end()),
                               image.crease_edges.end());
    }
    if (root.contains("corners")) {
      SDVI_ASSIGN_OR_RETURN(image.corners, Indices(root["corners"], "corners"));
      std::sort(image.corners.begin(), image.corners.end());
      image.corners.erase(std::unique(image.corners.begin(), image.corners.end()),
                          image.corners.end());
    }
    if (root.contains("polylines")) {
      SDVI_ASSIGN_OR_RETURN(const Json* polylines, Array(root["polylines"], "polylines"));
      for (size_t i = 0; i < polylines->size(); ++i) {
        const std::string where = "polylines[" + std::to_string(i) + "]";
        const Json& p = (*polylines)[i];
        if (!p.is_object() || !p.contains("vertices"))
          return Shape(where, "an object {\"vertices\": [...], \"closed\": bool}");
        for (const auto& item : p.items())
          if (item.key() != "vertices" && item.key() != "closed")
            return Status(StatusCode::kInvalidArgument,
                          source_ + ": unknown key '" + item.key() + "' in " + where);
        FeaturePolyline poly;
        SDVI_ASSIGN_OR_RETURN(poly.vertices, Indices(p["vertices"], where + ".vertices"));
        if (p.contains("closed")) {
          if (!p["closed"].is_boolean()) return Shape(where + ".closed", "true or false");
          poly.closed = p["closed"].get<bool>();
        }
        image.polylines.push_back(std::move(poly));
      }
    }
    if (root.contains("pairs")) {
      SDVI_ASSIGN_OR_RETURN(const Json* pairs, Array(root["pairs"], "pairs"));
      for (size_t i = 0; i < pairs->size(); ++i) {
        const std::string where = "pairs[" + std::to_string(i) + "]";
        const Json& p = (*pairs)[i];
        if (!p.is_object() || !p.contains("first") || !p.contains("second"))
          return Shape(where, "an object {\"first\": i, \"second\": j, \"sharpness\": s}");
        for (const auto& item : p.items())
          if (item.key() != "first" && item.key() != "second" && item.key() != "sharpness")
            return Status(StatusCode::kInvalidArgument,
                          source_ + ": unknown key '" + item.key() + "' in " + where);
        FeaturePair pair;
        SDVI_ASSIGN_OR_RETURN(pair.first, Index(p["first"], where + ".first"));
        SDVI_ASSIGN_OR_RETURN(pair.second, Index(p["second"], where + ".second"));
        if (p.contains("sharpness")) {
          SDVI_ASSIGN_OR_RETURN(pair.sharpness, Number(p["sharpness"], where + ".sharpness"));
        }
        image.pairs.push_back(pair);
      }
    }
    if (root.contains("metadata")) {
      SDVI_ASSIGN_OR_RETURN(const Json* entries, Array(root["metadata"], "metadata"));
      for (size_t i = 0; i < entries->size(); ++i) {
        const std::string where = "metadata[" + std::to_string(i) + "]";
        SDVI_ASSIGN_OR_RETURN(const Json* kv, Array((*entries)[i], where + " ([key, value])", 2));
        SDVI_ASSIGN_OR_RETURN(std::string key, String((*kv)[0], where + "[0]"));
        SDVI_ASSIGN_OR_RETURN(std::string value, String((*kv)[1], where + "[1]"));
        image.metadata.emplace_back(std::move(key), std::move(value));
      }
    }
    return image;
  }

 private:
  std::string source_;
};

// Shortest decimal that strtof reads back to exactly f; "-0.0" keeps the sign of zero
// (a bare "-0" would parse as the integer 0).
void AppendFloat(std::string& out, float f) {
  if (f == 0.f && std::signbit(f)) {
    out += "-0.0";
    return;
  }
  char buf[32];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, f);
  out.append(buf, ec == std::errc() ? end : buf);
}

void AppendString(std::string& out, const std::string& s) {
  out += Json(s).dump(-1, ' ', false, nlohmann::detail::error_handler_t::replace);
}

template <typename Range, typename Fn>
void AppendLines(std::string& out, const char* key, const Range& items, Fn append_item,
                 bool last) {
  out += "  \"";
  out += key;
  out += "\": [";
  bool first = true;
  for (const auto& item : items) {
    out += first ? "\n    " : ",\n    ";
    append_item(out, item);
    first = false;
  }
  out += first ? "]" : "\n  ]";
  out += last ? "\n" : ",\n";
}

}  // namespace

StatusOr<Image> ParseMeshJson(std::string_view text, const std::string& source_name) {
  Json root;
  try {
    root = Json::parse(text.begin(), text.end());
  } catch (const Json::parse_error& e) {
    return Status(StatusCode::kDecodeFailed,
                  source_name + ": not valid JSON at byte " + std::to_string(e.byte) + ": " +
                      e.what());
  } catch (const std::exception& e) {
    return Status(StatusCode::kDecodeFailed, source_name + ": cannot parse JSON: " + e.what());
  }
  StatusOr<Image> image = [&]() -> StatusOr<Image> {
    try {
      return Parser(source_name).ParseImage(root);
    } catch (const std::exception& e) {
      return Status(StatusCode::kCorrupt, source_name + ": unexpected mesh JSON: " + e.what());
    }
  }();
  if (!image.ok()) return image;
  SDVI_RETURN_IF_ERROR(ValidateImage(*image, source_name));
  return image;
}

std::string FormatMeshJson(const Image& image) {
  std::string out;
  out.reserve(64 + image.vertices.size() * 48 + image.triangles.size() * 24);
  out += "{\n  \"format\": \"";
  out += kFormatName;
  out += "\",\n  \"version\": " + std::to_string(kMeshJsonVersion) + ",\n";
  out += "  \"width\": " + std::to_string(image.width) + ",\n";
  out += "  \"height\": " + std::to_string(image.height) + ",\n";
  const bool has_features = !image.polylines.empty() || !image.pairs.empty();
  const bool has_metadata = !image.metadata.empty();
  AppendLines(out, "vertices", image.vertices, [](std::string& o, const Vertex& v) {
    o += '[';
    const float c[5] = {v.x, v.y, v.r, v.g, v.b};
    for (int k = 0; k < 5; ++k) {
      if (k) o += ", ";
      AppendFloat(o, c[k]);
    }
    o += ']';
  }, false);
  AppendLines(out, "triangles", image.triangles, [](std::string& o, const Triangle& t) {
    o += '[' + std::to_string(t.v[0]) + ", " + std::to_string(t.v[1]) + ", " +
         std::to_string(t.v[2]) + ']';
  }, false);
  AppendLines(out, "crease_edges", image.crease_edges, [](std::string& o, const Edge& e) {
    o += '[' + std::to_string(e.a) + ", " + std::to_string(e.b) + ']';
  }, false);
  out += "  \"corners\": [";
  for (size_t i = 0; i < image.corners.size(); ++i) {
    if (i) out += ", ";
    out += std::to_string(image.corners[i]);
  }
  out += (has_features || has_metadata) ? "],\n" : "]\n";
  if (has_features) {
    AppendLines(out, "polylines", image.polylines, [](std::string& o, const FeaturePolyline& p) {
      o += "{\"vertices\": [";
      for (size_t i = 0; i < p.vertices.size(); ++i) {
        if (i) o += ", ";
        o += std::to_string(p.vertices[i]);
      }
      o += "], \"closed\": ";
      o += p.closed ? "true}" : "false}";
    }, false);
    AppendLines(out, "pairs", image.pairs, [](std::string& o, const FeaturePair& p) {
      o += "{\"first\": " + std::to_string(p.first) + ", \"second\": " + std::to_string(p.second) +
           ", \"sharpness\": ";
      AppendFloat(o, p.sharpness);
      o += '}';
    }, !has_metadata);
  }
  if (has_metadata) {
    AppendLines(out, "metadata", image.metadata,
                [](std::string& o, const std::pair<std::string, std::string>& kv) {
                  o += '[';
                  AppendString(o, kv.first);
                  o += ", ";
                  AppendString(o, kv.second);
                  o += ']';
                }, true);
  }
  out += "}\n";
  return out;
}

StatusOr<Image> ReadMeshJsonFile(const std::string& path) {
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, ReadFileBytes(path));
  if (bytes.empty()) return Status(StatusCode::kEmptyInput, path + ": the file is empty");
  return ParseMeshJson(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
                       path);
}

Status WriteMeshJsonFile(const std::string& path, const Image& image) {
  SDVI_RETURN_IF_ERROR(ValidateImage(image, path));
  const std::string text = FormatMeshJson(image);
  return WriteFileAtomic(path, text.data(), text.size());
}

}  // namespace sdvi
