// Writes a small seed corpus for fuzz_decode: one file per container feature
// (narrow and wide profiles, every tag group, corners, feature layer, metadata, a
// compressed payload). Usage: make_seeds DIR [--wide]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "sdvi/file_util.h"
#include "sdvi/format.h"

namespace {

// A grid of (n+1) x (n+1) vertices, two triangles a cell, boundary tagged crease.
sdvi::Image Grid(uint32_t n) {
  sdvi::Image image;
  image.width = image.height = n * 4;
  for (uint32_t y = 0; y <= n; ++y)
    for (uint32_t x = 0; x <= n; ++x)
      image.vertices.push_back({4.f * x, 4.f * y, float(x * 7 % 256), float(y * 13 % 256), 100.5f});
  auto id = [n](uint32_t x, uint32_t y) { return y * (n + 1) + x; };
  for (uint32_t y = 0; y < n; ++y)
    for (uint32_t x = 0; x < n; ++x) {
      image.triangles.push_back({{id(x, y), id(x + 1, y), id(x + 1, y + 1)}});
      image.triangles.push_back({{id(x, y), id(x + 1, y + 1), id(x, y + 1)}});
    }
  for (uint32_t i = 0; i < n; ++i) {
    image.crease_edges.push_back(sdvi::Edge::Of(id(i, 0), id(i + 1, 0)));
    image.crease_edges.push_back(sdvi::Edge::Of(id(i, n), id(i + 1, n)));
    image.crease_edges.push_back(sdvi::Edge::Of(id(0, i), id(0, i + 1)));
    image.crease_edges.push_back(sdvi::Edge::Of(id(n, i), id(n, i + 1)));
  }
  return image;
}

int Write(const std::string& path, const sdvi::StatusOr<std::vector<uint8_t>>& bytes) {
  if (!bytes.ok()) {
    std::fprintf(stderr, "%s\n", bytes.status().ToString().c_str());
    return 1;
  }
  sdvi::Status s = sdvi::WriteFileAtomic(path, *bytes);
  if (!s.ok()) std::fprintf(stderr, "%s\n", s.ToString().c_str());
  return s.ok() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: make_seeds DIR [--wide]\n");
    return 1;
  }
  const std::string dir = argv[1];
  int failures = 0;
  sdvi::Image tiny = Grid(1);
  failures += Write(dir + "/tiny.sdvi", sdvi::EncodeSdvi(tiny));
  sdvi::Image rich = Grid(4);
  rich.corners = {0, 6, 12};
  rich.crease_edges.push_back(sdvi::Edge::Of(6, 12));
  rich.crease_edges.push_back(sdvi::Edge::Of(12, 18));
  rich.polylines = {{{0, 1, 2, 3, 4}, false}, {{6, 12, 18}, false}, {{0, 4, 24, 20}, true}};
  rich.pairs = {{0, 1, 0.75f}};
  rich.metadata = {{"source", "make_seeds"}, {"fit.target_psnr", "38"}};
  std::sort(rich.crease_edges.begin(), rich.crease_edges.end());
  failures += Write(dir + "/rich.sdvi", sdvi::EncodeSdvi(rich));
  if (argc > 2 && std::string(argv[2]) == "--wide")  // 66049 vertices, 2.9 MB
    failures += Write(dir + "/wide.sdvi", sdvi::EncodeSdvi(Grid(256)));
  sdvi::Image shell;
  shell.width = shell.height = 64;
  shell.polylines = {{{0, 1, 2}, false}};
  shell.metadata = {{"codec", "draco"}};
  sdvi::PayloadSummary summary;
  summary.vertex_count = 3;
  summary.triangle_count = 1;
  summary.params = {{"position_bits", "14"}};
  failures += Write(dir + "/compressed.sdvi",
                    sdvi::EncodeSdviCompressed(shell, {1, 2, 3, 4, 5, 6, 7, 8}, summary));
  return failures == 0 ? 0 : 1;
}
