// SPDX-License-Identifier: GPL-3.0-or-later
// Public contract between curvilinear feature extraction / control-mesh construction
// (paper section IV steps 1-4) and the colour fit / refinement loop (steps 5-6).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "sdvi/image.h"
#include "sdvi/raster.h"
#include "sdvi/status.h"

namespace sdvi {

struct Point2 {
  double x = 0, y = 0;
};

// Euclidean distance between two points.
inline double Distance(Point2 a, Point2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

// One curvilinear feature after B-spline fitting: its deBoor points (the control polygon
// that becomes a feature polyline of the mesh), in source pixels.
struct FeatureCurve {
  std::vector<Point2> points;     // deBoor points
  bool closed = false;            // periodic (closed) or end-interpolating (open)
  std::vector<uint32_t> corners;  // indices into points that keep a kink (open ends are
                                  // corners implicitly)
  float sharpness = 1.0f;         // 1 - blur, in [0, 1]
  bool boundary = false;          // a domain contour of an object image (outer or hole):
                                  // bounds the domain, is not paired
  float contrast = 0;             // median colour step across the edge (0..255 units, RMS
                                  // over channels); 0 for boundary curves
  float width = 0;                // > 0: a thin structure (a hairline): `points` is its
                                  // centreline and it has two colour discontinuities, the
                                  // outlines width px apart, placed as one unit (src/pairs.h)
};

// The length of the curve's control polygon (closing segment included when closed), px.
double PolygonLength(const FeatureCurve& c);

// Edge detection (paper step 1): the image (RGB or grey) is smoothed with a Gaussian of
// smoothing_sigma; the colour gradient is the principal direction / magnitude of the
// structure tensor summed over channels (sqrt(lambda1 / channels), 0..255 units per px;
// grey = the plain gradient magnitude); non-maximum suppression across the edge with a
// sub-pixel peak; hysteresis between low_ratio * high and high; thinning; linking into
// chains at endpoints (1 neighbour) and junctions (>= 3 neighbours); at each junction the
// two chain ends that continue each other best (>= ~143 degrees apart) are joined, so a
// curve touched or crossed by another stays one chain (the other ends at the junction).
// Blur (per edge pixel): the edge profile is taken as a Gaussian-blurred step of contrast
// C (colour distance between the smoothed image at +-5 px across the edge): its total
// width is sigma_t = C / (sqrt(2 pi) |gradient|); the blur width of the image itself is
// sigma_b = sqrt(sigma_t^2 - sigma_0^2), sigma_0 = the width a perfect step gets from
// our own smoothing. Per chain: the median sigma_b, normalised blur =
// min(1, sigma_b / blur_scale). With quantize_sharpness the chains are split by Otsu's
// threshold (weighted by length) into a sharp and a soft class and every chain gets its
// class mean; sharpness = 1 - blur.
// Corners: chain ends (endpoints, junctions) and points where the chain turns by more
// than corner_angle_deg over corner_window px on each side (local maxima).
// Defaults (here and in ControlMeshOptions) were picked by reconstruction PSNR at an equal
// vertex budget (pixels / 50, one colour fit, no refinement) averaged over 10 photos and
// graphics of ../shared/data: smoothing 0.8 px (1.0: -0.2 dB, 1.5: -1.9 dB), corner angle
// 70 deg (35: -0.8 dB), fit tolerance 1.5 px, pair floor 1 px (0.5: -0.3 dB, 2: -2.3 dB),
// rho 5 (3: -0.6 dB, 8: -1.3 dB), blur_scale 2 (1.3: -1.0 dB, 3: -0.5 dB). Ablations
// there: no pairs -6.6 dB, no sharpness -5.6 dB, no interior features -7.3 dB.
struct FeatureOptions {
  bool detect_edges = true;       // false: no interior features (domain boundary only)
  double smoothing_sigma = 0.8;   // Gaussian smoothing before the gradient, px
  double high_threshold = 0;      // hysteresis high threshold (gradient units); 0 = auto:
                                  // max(min_high_threshold, high_quantile of the gradient)
  double min_high_threshold = 8;  // ~ contrast 22 for a crisp step
  double high_quantile = 0.9;     // of the gradient magnitude over the domain
  double low_ratio = 0.4;         // low threshold = low_ratio * high
  double min_chain_length = 12;   // chains shorter than this (px) are dropped
  double corner_angle_deg = 70;   // turning angle that makes a corner
  double corner_window = 4;       // px on each side for the turning angle
  double blur_scale = 2.0;        // blur width sigma_b (px) that counts as blur 1
  bool quantize_sharpness = true; // Otsu two-level sharpness (paper); false: per chain
  double fit_tolerance = 1.5;     // B-spline fit: max distance to the chain, px
  double max_spacing = 12;        // B-spline fit: max arc length per polygon segment, px
  double min_domain_area = 16;    // object mode: smaller components / holes are dropped, px^2
  int threads = 1;                // worker threads for the per-pixel passes and the per-chain
                                  // fits; the curves do not depend on it (spec/METHOD.md
                                  // section 6 step 1, "Threads")
};

// Detects curvilinear features of image (RGB or grey, 0..255; alpha or mask gives the
// object domain, whose contours come back as boundary curves) and fits their B-splines.
StatusOr<std::vector<FeatureCurve>> DetectFeatures(const Raster& image, const Raster* mask,
                                                   const FeatureOptions& options);

// Where the image varies (spec/METHOD.md section 6, the quality stop): the image cut into
// square blocks, a block busy when some colour channel of its domain pixels varies by more
// than a tolerance (FindContentBlocks, vectorize.h). The mesher applies its size bound only
// to triangles touching a busy block, and the image rectangle's sides are split only there:
// a flat region is represented by any triangle covering it, so it costs few vertices.
struct ContentBlocks {
  int block = 0;                   // px; 0: no blocks (everything counts as busy)
  int columns = 0, rows = 0;
  std::vector<uint32_t> busy_sum;  // (rows + 1) x (columns + 1) summed-area table of busy flags
  uint32_t domain_blocks = 0;      // blocks holding a domain pixel
  // True when a block meeting the box [x0, x1] x [y0, y1] (px, clamped to the image) is
  // busy, or when there are no blocks.
  bool AnyBusy(double x0, double y0, double x1, double y1) const;
  // Busy blocks / domain blocks (1 when there are no blocks).
  double BusyShare() const;
};

struct ControlMeshOptions {
  float rho = 5.0f;          // pair distance rho * (1 - sharpness), paper value 5 px
  float min_distance = 1.0f; // floor on the pair distance, keeps triangles non-degenerate
  bool pairs = true;         // false: one polyline per feature (ablation, paper Fig. 9)
  bool use_sharpness = true; // false: every pair at distance rho (ablation, paper Fig. 14)
  float min_angle_deg = 10;  // CDT quality bound, deg (paper: 20; spec/METHOD.md 6 step 4)
  float max_edge = 0;        // CDT size bound in px; 0 = max(8, sqrt(width * height) / 12)
  float clearance = 1.0f;    // min distance between different feature polylines (and
                             // from features to the boundary and to interior samples), px
  // Where the size bound applies (not owned); null: everywhere.
  const ContentBlocks* content = nullptr;
  bool fine_cuts = true;     // split straight segments cut for a conflict into pieces of
                             // 2 x clearance and test again (src/pairs.h); false: every
                             // placed vertex is a point of the given curves (or a split of
                             // a segment longer than 0.7 max_edge)
  bool junctions = true;     // features that cross at 30 degrees or more share a junction
                             // vertex (a corner) instead of being cut (src/pairs.h); false:
                             // every crossing is cut out with its neighbourhood
};

// Distance between the two polylines of a feature pair (paper section IV step 3):
// max(min_distance, rho (1 - sharpness)); max(min_distance, rho) when use_sharpness is false.
double PairDistance(float sharpness, const ControlMeshOptions& options);

// The two sides of a feature pair around its centre polygon (deBoor points, >= 2; a closed
// one does not repeat its first point): every point moved by +-distance / 2 along the
// averaged normal of its two segments, mitred (divided by the cosine of the half turn,
// at most 2x) so that each side stays distance / 2 from the centre's segments. [0] is the
// side along +n, n = (-dy, dx) / |(dx, dy)| for a segment direction (dx, dy); [1] along -n. The only
// placement of pair sides: BuildControlMesh and the editor's sharpness change use it.
std::array<std::vector<Point2>, 2> OffsetPairSides(const std::vector<Point2>& centre, bool closed,
                                                   double distance);

// Builds the control mesh (colours zero): the domain boundary (image rectangle with its
// four corners tagged, or the boundary curves), feature pairs offset along averaged
// normals, the given interior samples, a constrained Delaunay triangulation (CGAL) with
// no Steiner point on a feature polyline. Fills crease_edges, corners, polylines, pairs.
// Placement rules (trimming of crossing features etc.) are documented in src/pairs.h.
// A junction (options.junctions) is one vertex listed in each polyline meeting there.
// Vertex order: polyline vertices (boundary first, then features in placement order),
// then the kept interior samples, then Steiner points of the mesher. polylines holds the
// boundary too (closed); every pair is (side +normal, side -normal) with the curve's
// sharpness (0 when use_sharpness is false). Mesher (CGAL, no edge refinement): angle bound
// sin^2(min_angle_deg) capped at CGAL's 0.125, size bound max_edge (only on triangles whose
// bounding box meets a busy block when options.content is set), and triangles with an
// edge shorter than min(clearance, min_distance) / 2 are left alone (no refinement
// cascades at small input angles); triangles touching feature polylines may stay thinner
// than the bound. Samples on an exact square lattice give right triangles whose
// circumcentre lies on an edge, which this mesher cannot insert: jitter lattices.
// Errors: kInvalidArgument for bad options,
// sizes or curves (non-finite, too few points, corner out of range), kInvalidMesh when
// no domain boundary survives, kInternal when the triangulation breaks an invariant.
StatusOr<Image> BuildControlMesh(int width, int height, const std::vector<FeatureCurve>& curves,
                                 const std::vector<Point2>& interior_samples,
                                 const ControlMeshOptions& options);

// Debug picture (for --debug-dir): image (grey or RGB[A], 0..255) as RGB, each curve's
// spline drawn over it (sharp >= 0.5 red, soft green, boundary blue), its deBoor points
// as dots and its corners (explicit ones and open ends) as small yellow squares.
Raster DrawFeatures(const Raster& image, const std::vector<FeatureCurve>& curves);

// Debug picture: the control mesh's edges over image (smooth edges grey, crease edges
// red, corner vertices yellow).
Raster DrawControlMesh(const Raster& image, const Image& mesh);

}  // namespace sdvi
