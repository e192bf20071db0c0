// SPDX-License-Identifier: GPL-3.0-or-later
// Writes the seed corpora of the fuzz targets (committed as fuzz/corpus/NAME):
//   decode, compress: one .sdvi file per container feature (every tag group, corners,
//     feature layer, metadata, a real Draco payload, a placeholder payload);
//   draco_payload: Draco payloads (with and without vertex ids and feature layer, grey);
//   mesh_json: the mesh JSON of those images, plus huge sizes and NaN/Inf/huge numbers;
//   raster: tiny PNG (8/16-bit, grey, RGBA), JPEG, TIFF, BMP, WebP and PNM images.
// Usage: make_seeds DIR [--wide] (DIR/NAME/ for every target).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <filesystem>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "sdvi/codec.h"
#include "sdvi/file_util.h"
#include "sdvi/format.h"
#include "sdvi/mesh_json.h"

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
  std::sort(image.crease_edges.begin(), image.crease_edges.end());
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

int WriteText(const std::string& path, const std::string& text) {
  return Write(path, std::vector<uint8_t>(text.begin(), text.end()));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: make_seeds DIR [--wide]\n");
    return 1;
  }
  const std::string root = argv[1];
  for (const char* name : {"decode", "compress", "draco_payload", "mesh_json", "raster"})
    std::filesystem::create_directories(root + "/" + name);
  const std::string dir = root + "/decode", json = root + "/mesh_json";
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
  // Real Draco payloads, in containers and alone.
  sdvi::Image grey = Grid(3);
  for (sdvi::Vertex& v : grey.vertices) v.g = v.b = v.r;
  struct Variant {
    const char* name;
    const sdvi::Image* image;
    bool keep_order, features;
  };
  for (const Variant& v : {Variant{"rich", &rich, false, true}, Variant{"rich_ids", &rich, true, true},
                           Variant{"rich_nofeatures", &rich, false, false}, Variant{"grey", &grey, false, true}}) {
    sdvi::CompressOptions options;
    options.keep_vertex_order = v.keep_order;
    options.feature_layer = v.features;
    options.position_bits = 10;
    options.color_bits = 8;
    auto container = sdvi::EncodeImage(*v.image, &options, v.name);
    failures += Write(dir + "/draco_" + v.name + ".sdvi", container);
    auto payload = sdvi::EncodeDracoPayload(*v.image, options);
    failures += Write(root + "/draco_payload/" + v.name + ".sdrc", payload);
  }
  for (const char* name : {"tiny.sdvi", "rich.sdvi", "draco_rich.sdvi", "draco_grey.sdvi"})
    std::filesystem::copy_file(dir + "/" + name, root + "/compress/" + name,
                               std::filesystem::copy_options::overwrite_existing);
  // Mesh JSON: real documents, then values no image has.
  failures += WriteText(json + "/tiny.json", sdvi::FormatMeshJson(tiny));
  failures += WriteText(json + "/rich.json", sdvi::FormatMeshJson(rich));
  const std::string head = R"({"format": "sdvi-mesh", "version": 1, )";
  const std::string tri = R"("vertices": [[0,0,0,0,0],[8,0,1,2,3],[0,8,4,5,6]], "triangles": [[0,1,2]]})";
  failures += WriteText(json + "/huge_size.json", head + R"("width": 4294967295, "height": 4294967295, )" + tri);
  failures += WriteText(json + "/huge_counts.json",
                        head + R"("width": 8, "height": 8, "vertices": [[0,0,0,0,0]], "triangles": [[0,1,4294967295]]})");
  failures += WriteText(json + "/nan.json", head + R"("width": 8, "height": 8, "vertices": [[NaN,0,0,0,0],[8,0,1,2,3],[0,8,4,5,6]], "triangles": [[0,1,2]]})");
  failures += WriteText(json + "/huge_number.json", head + R"("width": 8, "height": 8, "vertices": [[1e39,0,0,0,0],[8,0,-1.7e38,2,3],[0,8,4,5,6]], "triangles": [[0,1,2]]})");
  // Rasters.
  cv::Mat rgb(6, 5, CV_8UC3), rgba(4, 3, CV_8UC4), grey16(4, 4, CV_16UC1);
  cv::randu(rgb, 0, 256);
  cv::randu(rgba, 0, 256);
  cv::randu(grey16, 0, 65536);
  struct RasterSeed {
    const char* name;
    const cv::Mat* mat;
  };
  for (const RasterSeed& r : {RasterSeed{"rgb.png", &rgb}, RasterSeed{"rgba.png", &rgba},
                              RasterSeed{"grey16.png", &grey16}, RasterSeed{"rgb.jpg", &rgb},
                              RasterSeed{"rgb.tif", &rgb}, RasterSeed{"grey16.tif", &grey16},
                              RasterSeed{"rgb.bmp", &rgb}, RasterSeed{"rgb.webp", &rgb},
                              RasterSeed{"rgb.ppm", &rgb}}) {
    std::vector<uint8_t> bytes;
    const std::string name = r.name;
    if (!cv::imencode(name.substr(name.rfind('.')), *r.mat, bytes)) {
      ++failures;
      continue;
    }
    failures += Write(root + "/raster/" + name, bytes);
  }
  return failures == 0 ? 0 : 1;
}
