// SPDX-License-Identifier: GPL-3.0-or-later
// Internals of sdvi_format shared by its translation units (not installed, not public).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sdvi/image.h"
#include "sdvi/status.h"

namespace sdvi::format_internal {

// Triangles in the paper's order: tagged3 triangles with 3 crease edges, then tagged2 with
// 2 (rotated so (c,a) is the smooth edge), then tagged1 with 1 (rotated so (a,b) is the
// crease edge), then the untagged ones. Stable inside each group.
struct CanonicalTriangles {
  std::vector<Triangle> triangles;
  uint32_t tagged3 = 0, tagged2 = 0, tagged1 = 0;
};

// Bit e set when edge (v[e], v[e+1 mod 3]) of t is in sorted_creases.
int TaggedEdgeMask(const std::vector<Edge>& sorted_creases, const Triangle& t);

CanonicalTriangles CanonicalizeTriangles(const std::vector<Triangle>& triangles,
                                         const std::vector<Edge>& sorted_creases);

// The crease edges the paper's groups tag, sorted and unique.
std::vector<Edge> CreaseEdgesFromGroups(const std::vector<Triangle>& triangles, uint32_t tagged3,
                                        uint32_t tagged2, uint32_t tagged1);

// True when crease_edges hold (a < b) edges sorted and unique, and corners are sorted
// and unique.
bool SetsAreNormalized(const Image& image);
// Makes crease_edges and corners so (Edge::Of, sort, unique).
void NormalizeSets(Image& image);

// An edge as messages name it: "(a, b)".
std::string EdgeText(const Edge& e);

// A vertex opposite an edge counts as across it when farther than this (pixels; plus
// float rounding at the image's scale): spec/FORMAT.md section 9, check 24.
inline constexpr double kFoldTolerance = 1.0 / 1024;

// Checks 19-21 of spec/FORMAT.md section 9 (size, coordinate and colour ranges) are
// CheckImageValues of sdvi/mesh_rules.h.
// Checks 22-24: duplicate triangles, non-manifold edges, orientation, folds. Expects
// indices in range and no degenerate triangle.
Status ValidateTopology(const Image& image, const std::string& source);

// ValidateImage; with has_mesh false (a compressed payload holds the mesh) the feature
// layer's vertex indices are not checked against the (absent) vertices.
Status ValidateImageParts(const Image& image, const std::string& source, bool has_mesh);

}  // namespace sdvi::format_internal
