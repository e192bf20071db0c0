// SPDX-License-Identifier: GPL-3.0-or-later
// Freeform deformation by moving least squares, rigid variant (rules in sdvi/edit.h,
// derivation in spec/EDIT.md).
#include <algorithm>
#include <cmath>
#include <string>

#include "edit_internal.h"

namespace sdvi::edit_internal {
namespace {

struct HandlePoint {
  Point2 p, q;  // source, target
};

// f(v) for the rigid MLS of handles (weights 1 / |p - v|^(2 alpha)); w is scratch space.
Point2 RigidMls(const std::vector<HandlePoint>& handles, double alpha, Point2 v, std::vector<double>& w) {
  double sw = 0, px = 0, py = 0, qx = 0, qy = 0;
  w.resize(handles.size());
  for (size_t i = 0; i < handles.size(); ++i) {
    const double d2 = (handles[i].p.x - v.x) * (handles[i].p.x - v.x) + (handles[i].p.y - v.y) * (handles[i].p.y - v.y);
    if (d2 < 1e-18) return handles[i].q;  // at a source: its target
    w[i] = alpha == 1 ? 1 / d2 : std::pow(d2, -alpha);
    sw += w[i];
    px += w[i] * handles[i].p.x;
    py += w[i] * handles[i].p.y;
    qx += w[i] * handles[i].q.x;
    qy += w[i] * handles[i].q.y;
  }
  px /= sw;
  py /= sw;
  qx /= sw;
  qy /= sw;
  // The rotation angle maximising sum w_i q^_i . R p^_i: atan2(sum w p^ x q^, sum w p^ . q^).
  double c = 0, s = 0;
  for (size_t i = 0; i < handles.size(); ++i) {
    const double ax = handles[i].p.x - px, ay = handles[i].p.y - py;
    const double bx = handles[i].q.x - qx, by = handles[i].q.y - qy;
    c += w[i] * (ax * bx + ay * by);
    s += w[i] * (ax * by - ay * bx);
  }
  double cos_t = 1, sin_t = 0;
  if (const double len = std::hypot(c, s); len > 0) {
    cos_t = c / len;
    sin_t = s / len;
  }
  const double dx = v.x - px, dy = v.y - py;
  return {cos_t * dx - sin_t * dy + qx, sin_t * dx + cos_t * dy + qy};
}

}  // namespace

Status ApplyDeform(const DeformOp& op, Image* image) {
  auto bad = [](const std::string& what) { return Status(StatusCode::kInvalidArgument, what); };
  if (op.handles.empty()) return bad("a deformation needs at least one handle");
  if (!(op.alpha > 0 && op.alpha <= 8)) return bad("alpha must be in (0, 8]");
  std::vector<HandlePoint> handles;
  for (size_t i = 0; i < op.handles.size(); ++i) {
    const DeformHandle& h = op.handles[i];
    HandlePoint hp{h.from, h.to};
    if (h.vertex) {
      if (*h.vertex >= image->vertices.size())
        return bad("handles[" + std::to_string(i) + "]: vertex " + std::to_string(*h.vertex) +
                   " does not exist (the image has " + std::to_string(image->vertices.size()) + " vertices)");
      hp.p = {image->vertices[*h.vertex].x, image->vertices[*h.vertex].y};
    }
    if (!std::isfinite(hp.p.x) || !std::isfinite(hp.p.y) || !std::isfinite(hp.q.x) || !std::isfinite(hp.q.y))
      return bad("handles[" + std::to_string(i) + "] is not finite");
    handles.push_back(hp);
  }
  SDVI_ASSIGN_OR_RETURN(std::vector<uint32_t> selected, ResolveSelection(*image, op.select));
  std::vector<uint8_t> pinned(image->vertices.size(), 0);
  if (op.pin_boundary) {
    for (const Edge& e : BoundaryEdges(*image)) pinned[e.a] = pinned[e.b] = 1;
    for (size_t i = 0; i < pinned.size(); ++i)
      if (pinned[i]) {
        const Point2 p{image->vertices[i].x, image->vertices[i].y};
        handles.push_back({p, p});
      }
  }
  std::vector<Point2> moved(selected.size());
  std::vector<double> scratch;
  for (size_t k = 0; k < selected.size(); ++k) {
    const Vertex& v = image->vertices[selected[k]];
    moved[k] = pinned[selected[k]] ? Point2{v.x, v.y} : RigidMls(handles, op.alpha, {v.x, v.y}, scratch);
  }
  for (size_t k = 0; k < selected.size(); ++k) {
    if (pinned[selected[k]]) continue;
    image->vertices[selected[k]].x = float(moved[k].x);
    image->vertices[selected[k]].y = float(moved[k].y);
  }
  return Status::Ok();
}

}  // namespace sdvi::edit_internal
