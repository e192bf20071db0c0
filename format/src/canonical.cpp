// SPDX-License-Identifier: GPL-3.0-or-later
// Canonical form, semantic validation and CRC-32 (format.h).
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "format_internal.h"
#include "sdvi/format.h"

namespace sdvi {
namespace {

constexpr std::array<uint32_t, 256> MakeCrcTable() {
  std::array<uint32_t, 256> table{};
  for (uint32_t i = 0; i < 256; ++i) {
    uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? (0xEDB88320u ^ (c >> 1)) : (c >> 1);
    table[i] = c;
  }
  return table;
}
constexpr std::array<uint32_t, 256> kCrcTable = MakeCrcTable();

bool IsCrease(const std::vector<Edge>& sorted_creases, uint32_t p, uint32_t q) {
  return std::binary_search(sorted_creases.begin(), sorted_creases.end(), Edge::Of(p, q));
}

bool Finite(const Vertex& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.r) && std::isfinite(v.g) &&
         std::isfinite(v.b);
}

}  // namespace

uint32_t Crc32(std::span<const uint8_t> bytes, uint32_t crc) {
  uint32_t c = crc ^ 0xFFFFFFFFu;
  for (uint8_t byte : bytes) c = kCrcTable[(c ^ byte) & 0xFFu] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

namespace format_internal {

std::string EdgeText(const Edge& e) {
  std::string text = "(";
  text += std::to_string(e.a);
  text += ", ";
  text += std::to_string(e.b);
  text += ")";
  return text;
}

int TaggedEdgeMask(const std::vector<Edge>& sorted_creases, const Triangle& t) {
  int mask = 0;
  for (int e = 0; e < 3; ++e)
    if (IsCrease(sorted_creases, t.v[e], t.v[(e + 1) % 3])) mask |= 1 << e;
  return mask;
}

CanonicalTriangles CanonicalizeTriangles(const std::vector<Triangle>& triangles,
                                         const std::vector<Edge>& sorted_creases) {
  std::array<std::vector<Triangle>, 4> groups;  // index = 3 - tagged count
  for (const Triangle& t : triangles) {
    const int mask = TaggedEdgeMask(sorted_creases, t);
    const int count = std::popcount(static_cast<unsigned>(mask));
    int rotate = 0;  // new (a,b,c) = old (v[rotate], v[rotate+1], v[rotate+2])
    if (count == 1) {
      rotate = mask == 1 ? 0 : mask == 2 ? 1 : 2;  // the tagged edge becomes (a,b)
    } else if (count == 2) {
      const int untagged = 7 & ~mask;              // the untagged edge becomes (c,a)
      rotate = untagged == 4 ? 0 : untagged == 1 ? 1 : 2;
    }
    Triangle r;
    for (int i = 0; i < 3; ++i) r.v[i] = t.v[(i + rotate) % 3];
    groups[3 - count].push_back(r);
  }
  CanonicalTriangles out;
  out.tagged3 = static_cast<uint32_t>(groups[0].size());
  out.tagged2 = static_cast<uint32_t>(groups[1].size());
  out.tagged1 = static_cast<uint32_t>(groups[2].size());
  out.triangles.reserve(triangles.size());
  for (const auto& g : groups) out.triangles.insert(out.triangles.end(), g.begin(), g.end());
  return out;
}

std::vector<Edge> CreaseEdgesFromGroups(const std::vector<Triangle>& triangles, uint32_t tagged3,
                                        uint32_t tagged2, uint32_t tagged1) {
  std::vector<Edge> edges;
  edges.reserve(3 * size_t{tagged3} + 2 * size_t{tagged2} + tagged1);
  const size_t end3 = tagged3, end2 = end3 + tagged2, end1 = end2 + tagged1;
  for (size_t i = 0; i < end1 && i < triangles.size(); ++i) {
    const auto& v = triangles[i].v;
    const int count = i < end3 ? 3 : i < end2 ? 2 : 1;
    for (int e = 0; e < count; ++e) edges.push_back(Edge::Of(v[e], v[(e + 1) % 3]));
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

bool SetsAreNormalized(const Image& image) {
  for (size_t i = 0; i < image.crease_edges.size(); ++i) {
    const Edge& e = image.crease_edges[i];
    if (e.a >= e.b || (i > 0 && !(image.crease_edges[i - 1] < e))) return false;
  }
  for (size_t i = 1; i < image.corners.size(); ++i)
    if (image.corners[i - 1] >= image.corners[i]) return false;
  return true;
}

void NormalizeSets(Image& image) {
  for (Edge& e : image.crease_edges) e = Edge::Of(e.a, e.b);
  std::sort(image.crease_edges.begin(), image.crease_edges.end());
  image.crease_edges.erase(std::unique(image.crease_edges.begin(), image.crease_edges.end()),
                           image.crease_edges.end());
  std::sort(image.corners.begin(), image.corners.end());
  image.corners.erase(std::unique(image.corners.begin(), image.corners.end()),
                      image.corners.end());
}

Status ValidateImageParts(const Image& image, const std::string& source, bool has_mesh) {
  if (image.width == 0 || image.height == 0)
    return Status(StatusCode::kEmptyInput, source + ": image size is " + std::to_string(image.width) +
                                               " x " + std::to_string(image.height) +
                                               "; width and height must be positive");
  const uint64_t nv = image.vertices.size();
  for (size_t i = 0; i < image.vertices.size(); ++i) {
    if (!Finite(image.vertices[i]))
      return Status(StatusCode::kNonFinite,
                    source + ": vertex " + std::to_string(i) +
                        " has a NaN or infinite coordinate or colour");
  }
  for (size_t i = 0; i < image.triangles.size(); ++i) {
    const auto& v = image.triangles[i].v;
    for (uint32_t idx : v) {
      if (idx >= nv)
        return Status(StatusCode::kIndexOutOfRange,
                      source + ": triangle " + std::to_string(i) + " names vertex " +
                          std::to_string(idx) + " but there are " + std::to_string(nv) +
                          " vertices");
    }
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0])
      return Status(StatusCode::kDegenerateTriangle,
                    source + ": triangle " + std::to_string(i) + " (" + std::to_string(v[0]) +
                        ", " + std::to_string(v[1]) + ", " + std::to_string(v[2]) +
                        ") repeats a vertex");
  }
  SDVI_RETURN_IF_ERROR(CheckImageValues(image, source));
  SDVI_RETURN_IF_ERROR(ValidateTopology(image, source));
  if (!image.crease_edges.empty()) {
    for (size_t i = 0; i < image.crease_edges.size(); ++i) {
      const Edge& e = image.crease_edges[i];
      if (e.a >= nv || e.b >= nv)
        return Status(StatusCode::kIndexOutOfRange,
                      source + ": crease edge " + EdgeText(e) + " names a vertex >= the " +
                          std::to_string(nv) + " vertices");
      if (e.a >= e.b)
        return Status(StatusCode::kInvalidArgument,
                      source + ": crease edge " + EdgeText(e) + " must list its smaller vertex first");
      if (i > 0 && !(image.crease_edges[i - 1] < e))
        return Status(StatusCode::kInvalidArgument,
                      source + ": crease edges must be sorted and unique; " + EdgeText(e) +
                          " follows " + EdgeText(image.crease_edges[i - 1]));
    }
    // Every crease edge must be an edge of some triangle: mark the ones triangles have.
    std::vector<bool> seen(image.crease_edges.size(), false);
    for (const Triangle& t : image.triangles)
      for (int k = 0; k < 3; ++k) {
        const Edge e = Edge::Of(t.v[k], t.v[(k + 1) % 3]);
        auto it = std::lower_bound(image.crease_edges.begin(), image.crease_edges.end(), e);
        if (it != image.crease_edges.end() && *it == e) seen[it - image.crease_edges.begin()] = true;
      }
    for (size_t i = 0; i < seen.size(); ++i)
      if (!seen[i])
        return Status(StatusCode::kCreaseNotAnEdge,
                      source + ": crease edge " + EdgeText(image.crease_edges[i]) +
                          " is not an edge of any triangle");
  }
  for (size_t i = 0; i < image.corners.size(); ++i) {
    const uint32_t c = image.corners[i];
    if (c >= nv)
      return Status(StatusCode::kIndexOutOfRange, source + ": corner vertex " + std::to_string(c) +
                                                      " but there are " + std::to_string(nv) +
                                                      " vertices");
    if (i > 0 && image.corners[i - 1] >= c)
      return Status(StatusCode::kInvalidArgument,
                    source + ": corners must be sorted and unique; " + std::to_string(c) +
                        " follows " + std::to_string(image.corners[i - 1]));
  }
  for (size_t p = 0; p < image.polylines.size(); ++p) {
    if (!has_mesh) break;  // indices refer to the compressed payload's vertices
    for (uint32_t idx : image.polylines[p].vertices) {
      if (idx >= nv)
        return Status(StatusCode::kIndexOutOfRange,
                      source + ": feature polyline " + std::to_string(p) + " names vertex " +
                          std::to_string(idx) + " but there are " + std::to_string(nv) +
                          " vertices");
    }
  }
  for (size_t i = 0; i < image.pairs.size(); ++i) {
    const FeaturePair& pair = image.pairs[i];
    if (pair.first >= image.polylines.size() || pair.second >= image.polylines.size())
      return Status(StatusCode::kIndexOutOfRange,
                    source + ": feature pair " + std::to_string(i) + " names polylines " +
                        std::to_string(pair.first) + " and " + std::to_string(pair.second) +
                        " but there are " + std::to_string(image.polylines.size()));
    if (!std::isfinite(pair.sharpness))
      return Status(StatusCode::kNonFinite,
                    source + ": feature pair " + std::to_string(i) + " has a non-finite sharpness");
    if (pair.sharpness < 0.f || pair.sharpness > 1.f) {
      char value[32];
      std::snprintf(value, sizeof value, "%g", double(pair.sharpness));
      return Status(StatusCode::kValueOutOfRange,
                    source + ": feature pair " + std::to_string(i) + " has sharpness " + value +
                        ", expected a value in [0, 1]");
    }
  }
  return Status::Ok();
}

}  // namespace format_internal

Status ValidateImage(const Image& image, const std::string& source_name) {
  return format_internal::ValidateImageParts(image, source_name, /*has_mesh=*/true);
}

Image CanonicalizeImage(const Image& image) {
  Image out = image;
  format_internal::NormalizeSets(out);
  out.triangles = format_internal::CanonicalizeTriangles(image.triangles, out.crease_edges).triangles;
  return out;
}

}  // namespace sdvi
