// SPDX-License-Identifier: GPL-3.0-or-later
// What the edit phases share: the invalid-argument status, edge facts of a control mesh, the
// deformation.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sdvi/edit.h"
#include "sdvi/image.h"
#include "sdvi/status.h"

namespace sdvi::edit_internal {

// An operation's invalid argument, in its own words.
inline Status Bad(const std::string& what) { return Status(StatusCode::kInvalidArgument, what); }

// Edges that lie in exactly one triangle, sorted.
std::vector<Edge> BoundaryEdges(const Image& image);

// Crease edges as the subdivision sees them: the listed ones and the boundary, sorted, unique.
std::vector<Edge> AllCreaseEdges(const Image& image);

// Twice the signed area of triangle t.
double SignedArea2(const Image& image, const Triangle& t);

// The orientation of most triangles: +1 (counter-clockwise in x right, y down) or -1.
int MeshOrientation(const Image& image);

// Repairs folds by edge flips: while a triangle has the wrong orientation (not `orientation`),
// one of its non-crease edges whose flip gives two triangles of the right orientation (and
// height >= kMinTriangleHeight) is flipped; sweeps in triangle order, at most 64. Vertices,
// creases and the triangle count stay. Returns the number of flips.
int RepairFolds(int orientation, Image* image);

// DeformOp (moving least squares, rigid) on image's positions; kInvalidArgument for bad
// parameters.
Status ApplyDeform(const DeformOp& op, Image* image);

}  // namespace sdvi::edit_internal
