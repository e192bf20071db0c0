// SPDX-License-Identifier: GPL-3.0-or-later
// Feature placement for the control mesh (paper section IV step 3): the domain boundary,
// feature pairs offset from each fitted control polygon, and the rule that no two
// feature polylines cross or come closer than a clearance.
#pragma once

#include <cstdint>
#include <vector>

#include "sdvi/features.h"
#include "sdvi/image.h"
#include "sdvi/status.h"

namespace sdvi {

// A polyline that becomes crease edges of the control mesh.
struct PlacedPolyline {
  std::vector<Point2> points;
  bool closed = false;
  std::vector<uint32_t> corners;  // explicit corners (indices into points)
  bool boundary = false;          // bounds the domain (image rectangle or object contour)
};

struct PlacedFeatures {
  std::vector<PlacedPolyline> polylines;  // boundary polylines first
  std::vector<FeaturePair> pairs;         // indices into polylines
  std::vector<Point2> samples;            // interior samples kept (inside, clear of features)
  bool object_mode = false;               // the boundary comes from boundary curves
  double max_edge = 0;                    // resolved CDT size bound, px
};

// Places the boundary and the features:
//  - boundary: the image rectangle (4 tagged corners) unless some curve is a boundary
//    curve; boundary curves are kept whole or dropped (when they cross a kept one);
//  - control-polygon segments longer than 0.7 * max_edge are split evenly (inserting
//    points on a segment changes the spline slightly; the detector's max_spacing keeps
//    this rare);
//  - each feature, longest first: its polygon offset along averaged (mitred) normals by
//    +-d/2, d = max(min_distance, rho (1 - sharpness)) (use_sharpness = false: d = rho;
//    pairs = false: the polygon itself, once); segments that would cross or come within
//    the clearance of an already placed polyline, or leave the domain (the bad ones on
//    straight parts split into pieces of at most 2 x clearance and tested again: fine
//    cuts, unless options.fine_cuts is false; the split points stay only where they end
//    a run, inside a run they are left out again), are cut out and
//    the remaining runs (>= 2 segments) become features of their own; a polyline may not
//    come within min(0.25, 0.4 d) of itself except between segments joined by less than
//    twice that much polygon (a short segment at a corner); a segment shorter than 0.01 px
//    is cut out with its neighbours;
//  - spikes: before each test, a polygon point where one of the feature's offset polylines
//    turns back along itself (its two segments overlap: a sharp corner followed by steps
//    shorter than the offset's shift along them) is removed from the polygon, so from
//    every polyline of the feature: they keep corresponding vertex by vertex;
//  - a thin structure (FeatureCurve::width w > 0, its curve the centreline): its polylines
//    at +-(w/2 + d/2) and +-(w/2 - d/2), pairs (0, 1) and (2, 3), when w - d >= min_distance
//    / 2; else at +-(w/2 + d/2) and 0, pairs (0, 1) and (1, 2) sharing the centre; cut as one
//    unit, then, where cut, its two outlines (+-w/2) are placed as ordinary features where
//    they fit (pairs = false: the outlines +-w/2, or the centre alone when w < clearance);
//  - junctions (options.junctions): a segment crossing a placed feature polyline (not the
//    boundary) at 30 degrees or more gets the crossing as a vertex, inserted into both
//    polylines as a corner (BuildControlMesh makes equal points one vertex); within 0.25 px
//    of a vertex the crossing is that vertex (a placed one kept, a candidate's moved onto
//    the placed segment; a candidate's open end ends on it), when the two pass through each
//    other there at 30 degrees or more; a junction keeps 0.25 px from other vertices and
//    junctions. A contact closer than the clearance is no conflict when a junction of the
//    same two polylines explains it: outside the disc of 1.5 clearance / sin(angle) around
//    it they are the clearance apart and they touch (< 0.01 px) only at the junction's
//    vertex; a segment explained only by junctions on cut segments is cut (to a fixpoint,
//    with runs of one segment);
//  - interior samples inside the domain and clear of every polyline, deduplicated.
StatusOr<PlacedFeatures> PlaceFeatures(int width, int height, const std::vector<FeatureCurve>& curves,
                                       const std::vector<Point2>& interior_samples,
                                       const ControlMeshOptions& options);

}  // namespace sdvi
