// SPDX-License-Identifier: GPL-3.0-or-later
// Tests of the SVG export (svg_export.h): the document parsed back with libxml2.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <libxml/parser.h>
#include <libxml/tree.h>

#include "pdf_test_images.h"
#include "sdvi/export_levels.h"
#include "sdvi/svg_export.h"

namespace {

struct Path {
  double x[3], y[3];
  int r, g, b;
};

struct Parsed {
  std::string root, width, height, view_box, rendering;
  std::vector<Path> paths;
  int other_elements = 0;  // besides <desc> and <path>
};

std::string Attribute(xmlNode* node, const char* name) {
  xmlChar* value = xmlGetProp(node, reinterpret_cast<const xmlChar*>(name));
  std::string s = value ? reinterpret_cast<const char*>(value) : "";
  xmlFree(value);
  return s;
}

Parsed Parse(const std::string& bytes) {
  Parsed out;
  std::unique_ptr<xmlDoc, void (*)(xmlDoc*)> doc(
      xmlReadMemory(bytes.data(), int(bytes.size()), "export.svg", nullptr, XML_PARSE_NONET | XML_PARSE_NOERROR),
      xmlFreeDoc);
  REQUIRE(doc);
  xmlNode* root = xmlDocGetRootElement(doc.get());
  REQUIRE(root);
  out.root = reinterpret_cast<const char*>(root->name);
  out.width = Attribute(root, "width");
  out.height = Attribute(root, "height");
  out.view_box = Attribute(root, "viewBox");
  out.rendering = Attribute(root, "shape-rendering");
  for (xmlNode* n = root->children; n; n = n->next) {
    if (n->type != XML_ELEMENT_NODE) continue;
    const std::string name = reinterpret_cast<const char*>(n->name);
    if (name == "desc") continue;
    if (name != "path") {
      ++out.other_elements;
      continue;
    }
    Path p;
    const std::string d = Attribute(n, "d"), fill = Attribute(n, "fill");
    REQUIRE(std::sscanf(d.c_str(), "M%lf %lfL%lf %lf %lf %lfZ", &p.x[0], &p.y[0], &p.x[1], &p.y[1], &p.x[2],
                        &p.y[2]) == 6);
    REQUIRE(std::sscanf(fill.c_str(), "#%02x%02x%02x", &p.r, &p.g, &p.b) == 3);
    out.paths.push_back(p);
  }
  return out;
}

// A full-frame grid whose colours are affine in x and y; Loop subdivision with its crease
// rules on the frame reproduces affine data, so the limit colour anywhere is the same
// affine function and a flat triangle's fill is that function at the centroid.
sdvi::Image AffineGrid(uint32_t width, uint32_t height) {
  sdvi::Image image = sdvi::pdf_test::Gradient(width, height);
  image.crease_edges.clear();
  for (sdvi::Vertex& v : image.vertices) {
    v.r = 20 + 2 * v.x;
    v.g = 200 - 1.5f * v.y;
    v.b = 60 + v.x + v.y;
  }
  return image;
}

}  // namespace

TEST_CASE("export-svg writes one flat path per fine triangle, coloured at its centroid", "[svg_export]") {
  const sdvi::Image image = AffineGrid(96, 64);
  for (int levels : {0, 1, 2}) {
    sdvi::SvgExportOptions options;
    options.levels = levels;
    auto exported = sdvi::EncodeSvg(image, options);
    REQUIRE(exported.ok());
    CHECK(exported->levels == levels);
    const Parsed parsed = Parse(exported->bytes);
    CHECK(parsed.root == "svg");
    CHECK(parsed.width == "96");
    CHECK(parsed.height == "64");
    CHECK(parsed.view_box == "0 0 96 64");
    CHECK(parsed.rendering == "crispEdges");
    CHECK(parsed.other_elements == 0);
    REQUIRE(parsed.paths.size() == image.triangles.size() << (2 * levels));
    CHECK(exported->triangles == parsed.paths.size());
    double area = 0;
    for (const Path& p : parsed.paths) {
      const double cx = (p.x[0] + p.x[1] + p.x[2]) / 3, cy = (p.y[0] + p.y[1] + p.y[2]) / 3;
      for (int k = 0; k < 3; ++k) {
        CHECK(p.x[k] >= -0.05);
        CHECK(p.x[k] <= 96.05);
        CHECK(p.y[k] >= -0.05);
        CHECK(p.y[k] <= 64.05);
      }
      // Coordinates carry one decimal: the centroid is known to 0.05 px.
      CHECK(std::abs(p.r - (20 + 2 * cx)) <= 0.5 + 2 * 0.05 + 1e-9);
      CHECK(std::abs(p.g - (200 - 1.5 * cy)) <= 0.5 + 1.5 * 0.05 + 1e-9);
      CHECK(std::abs(p.b - (60 + cx + cy)) <= 0.5 + 2 * 0.05 + 1e-9);
      area += std::abs((p.x[1] - p.x[0]) * (p.y[2] - p.y[0]) - (p.y[1] - p.y[0]) * (p.x[2] - p.x[0])) / 2;
    }
    // The fine triangles tile the frame (to the rounding of the coordinates).
    CHECK(area == Approx(96.0 * 64.0).epsilon(0.01));
  }
}

TEST_CASE("export-svg's default level: one below the PDF's unless flat shading loses 38 dB there; deterministic",
          "[svg_export]") {
  // The gradient: 96 triangles of 64 px^2, the PDF's level 3 (64 / 4^3 <= 2 px^2).
  const sdvi::Image gradient = sdvi::pdf_test::Gradient(96, 64);
  REQUIRE(sdvi::DefaultExportLevels(gradient) == 3);
  auto first = sdvi::EncodeSvg(gradient, {});
  auto second = sdvi::EncodeSvg(gradient, {});
  REQUIRE(first.ok());
  REQUIRE(second.ok());
  CHECK(first->levels == 2);
  CHECK(first->flat_psnr >= sdvi::kSvgFlatPsnr);
  CHECK(first->bytes == second->bytes);
  // The annulus's colours turn fast: one below the PDF's level is under the bar, so the
  // PDF's level is used; the finer level is the better one.
  const sdvi::Image annulus = sdvi::pdf_test::Annulus(80, 60);
  const int pdf_levels = sdvi::DefaultExportLevels(annulus);
  REQUIRE(pdf_levels >= 1);
  sdvi::SvgExportOptions coarser;
  coarser.levels = pdf_levels - 1;
  auto coarse = sdvi::EncodeSvg(annulus, coarser);
  REQUIRE(coarse.ok());
  CHECK(coarse->flat_psnr < sdvi::kSvgFlatPsnr);
  auto chosen = sdvi::EncodeSvg(annulus, {});
  REQUIRE(chosen.ok());
  CHECK(chosen->levels == pdf_levels);
  CHECK(chosen->flat_psnr > coarse->flat_psnr + 5);  // halving the triangles' size: ~6 dB
  // A single-colour image is drawn exactly at any level.
  sdvi::Image flat = gradient;
  for (sdvi::Vertex& v : flat.vertices) v.r = v.g = v.b = 77;
  auto exact = sdvi::EncodeSvg(flat, {});
  REQUIRE(exact.ok());
  CHECK(std::isinf(exact->flat_psnr));
  CHECK(exact->levels == 2);
}

TEST_CASE("export-svg leaves the outside of an object image empty", "[svg_export]") {
  const sdvi::Image image = sdvi::pdf_test::Annulus(80, 60);
  sdvi::SvgExportOptions options;
  options.levels = 2;
  auto exported = sdvi::EncodeSvg(image, options);
  REQUIRE(exported.ok());
  const Parsed parsed = Parse(exported->bytes);
  const double outer = std::min(80, 60) * 0.42, inner = outer * 0.4;
  for (const Path& p : parsed.paths) {
    const double cx = (p.x[0] + p.x[1] + p.x[2]) / 3 - 40, cy = (p.y[0] + p.y[1] + p.y[2]) / 3 - 30;
    const double radius = std::hypot(cx, cy);
    CHECK(radius < outer + 0.1);  // no triangle outside the disc or in the hole
    CHECK(radius > inner - 0.1);
  }
}

TEST_CASE("export-svg rejects bad input with specific codes", "[svg_export][slow]") {
  sdvi::Image image = sdvi::pdf_test::Gradient(96, 64);
  sdvi::SvgExportOptions options;
  options.levels = sdvi::kMaxSvgLevels + 1;
  CHECK(sdvi::EncodeSvg(image, options).status().code() == sdvi::StatusCode::kInvalidArgument);
  options.levels = 6;  // 96 x 4^6 = 393,216 fine triangles: within the limit
  CHECK(sdvi::EncodeSvg(image, options).ok());
  CHECK(sdvi::EncodeSvg(sdvi::Image(), {}).status().code() == sdvi::StatusCode::kEmptyInput);
  sdvi::Image nan = image;
  nan.vertices[3].g = std::nanf("");
  CHECK(sdvi::EncodeSvg(nan, {}).status().code() == sdvi::StatusCode::kNonFinite);
  sdvi::Image huge = image;
  for (int i = 0; i < 12; ++i) huge.triangles.insert(huge.triangles.end(), image.triangles.begin(), image.triangles.end());
  options.levels = 6;  // 1248 x 4096 = 5.1M > 4.2M
  CHECK(sdvi::EncodeSvg(huge, options).status().code() == sdvi::StatusCode::kLimitExceeded);
  CHECK(sdvi::WriteSvg("/nonexistent-dir/out.svg", image, {}).status().code() != sdvi::StatusCode::kOk);
}
