// SPDX-License-Identifier: GPL-3.0-or-later
// Software prefetch for the fit's passes over the coverage (pixel order): each sample reads
// its fine triangle and that triangle's three fine vertices, which lie anywhere in their
// arrays (fine triangles are numbered by control triangle, not by position), so a pass
// waits on memory at nearly every new triangle. Asking for them some samples ahead hides
// the wait; what is computed does not change.
#ifndef SDVI_FIT_PREFETCH_H_
#define SDVI_FIT_PREFETCH_H_

#include <cstddef>
#include <vector>

#include "sdvi/image.h"
#include "sdvi/render.h"

namespace sdvi::fit_internal {

// How many samples ahead of the current one a pass asks for the first level of what it
// will read (here the fine triangle), and the second (the fine vertices, found through
// the first: nearer, so that the first has arrived).
constexpr size_t kPrefetchFar = 32, kPrefetchNear = 16;

// Called at sample q of a pass over samples [.., end): asks for the fine triangle of sample
// q + kPrefetchFar and the fine vertices of sample q + kPrefetchNear.
inline void PrefetchSampleData(const std::vector<PixelSample>& samples, size_t q, size_t end,
                               const std::vector<Triangle>& triangles, const std::vector<Vertex>& fine) {
  if (q + kPrefetchFar < end) {
    const uint32_t t = samples[q + kPrefetchFar].triangle;
    if (t < triangles.size()) __builtin_prefetch(&triangles[t]);
  }
  if (q + kPrefetchNear < end) {
    const uint32_t t = samples[q + kPrefetchNear].triangle;
    if (t < triangles.size()) {
      for (uint32_t v : triangles[t].v) {
        if (v < fine.size()) __builtin_prefetch(&fine[v]);
      }
    }
  }
}

}  // namespace sdvi::fit_internal

#endif  // SDVI_FIT_PREFETCH_H_
