// Public contract between curvilinear feature extraction / control-mesh construction
// (paper section IV steps 1-4) and the colour fit / refinement loop (steps 5-6).
#pragma once

#include <cstdint>
#include <vector>

#include "sdvi/image.h"
#include "sdvi/raster.h"
#include "sdvi/status.h"

namespace sdvi {

struct Point2 {
  double x = 0, y = 0;
};

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
};

struct FeatureOptions {
  bool detect_edges = true;  // false: no interior features (domain boundary only)
  // Detector thresholds etc. are added by the features module with documented defaults.
};

// Detects curvilinear features of image (RGB or grey, 0..255; alpha or mask gives the
// object domain, whose contours come back as boundary curves) and fits their B-splines.
StatusOr<std::vector<FeatureCurve>> DetectFeatures(const Raster& image, const Raster* mask,
                                                   const FeatureOptions& options);

struct ControlMeshOptions {
  float rho = 5.0f;          // pair distance rho * (1 - sharpness), paper value 5 px
  float min_distance = 0.5f; // floor on the pair distance, keeps triangles non-degenerate
  bool pairs = true;         // false: one polyline per feature (ablation, paper Fig. 9)
  bool use_sharpness = true; // false: every pair at distance rho (ablation, paper Fig. 14)
  float min_angle_deg = 20;  // CDT quality bound
  float max_edge = 0;        // CDT size bound in px; 0 = from the image size
};

// Builds the control mesh (colours zero): the domain boundary (image rectangle with its
// four corners tagged, or the boundary curves), feature pairs offset along averaged
// normals, the given interior samples, a constrained Delaunay triangulation (CGAL) with
// no Steiner point on a feature polyline. Fills crease_edges, corners, polylines, pairs.
StatusOr<Image> BuildControlMesh(int width, int height, const std::vector<FeatureCurve>& curves,
                                 const std::vector<Point2>& interior_samples,
                                 const ControlMeshOptions& options);

}  // namespace sdvi
