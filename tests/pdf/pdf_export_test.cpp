// SPDX-License-Identifier: GPL-3.0-or-later
// PDF export (sdvi_pdf): strips, bit choice, and the document read back with qpdf: the
// type-4 shading's records decoded by the rules of ISO 32000-1 8.7.4.5.5 must give the
// limit surface (computed independently by RefineImage), its colour range and its domain.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <qpdf/QPDF.hh>
#include <qpdf/QPDFObjectHandle.hh>
#include <qpdf/QPDFPageDocumentHelper.hh>

#include "grid_triangles.h"
#include "pdf_test_images.h"
#include "sdvi/export_levels.h"
#include "sdvi/pdf.h"
#include "sdvi/subdiv.h"

namespace sdvi {
namespace {

std::array<uint32_t, 3> Sorted(const Triangle& t) {
  std::array<uint32_t, 3> v = t.v;
  std::sort(v.begin(), v.end());
  return v;
}

std::multiset<std::array<uint32_t, 3>> TriangleSet(const std::vector<Triangle>& triangles) {
  std::multiset<std::array<uint32_t, 3>> set;
  for (const Triangle& t : triangles) set.insert(Sorted(t));
  return set;
}

// A vertex of the shading as a reader decodes it.
struct DecodedVertex {
  int flag = 0;
  double x = 0, y = 0, c[3] = {0, 0, 0};  // source px; colour 0..1
};

// What the test reads back from the document.
struct ReadBack {
  std::map<std::string, double> numbers;  // /ShadingType, /BitsPer*, ...
  std::vector<double> decode;
  std::vector<DecodedVertex> vertices;
  std::string content;
  std::string producer;
  long long source_width = -1, source_height = -1;
  std::vector<double> media_box;
};

uint64_t ReadBits(const std::string& data, size_t* bit, int n) {
  uint64_t value = 0;
  for (int i = 0; i < n; ++i, ++*bit) {
    const uint8_t byte = uint8_t(data.at(*bit / 8));
    value = (value << 1) | ((byte >> (7 - *bit % 8)) & 1);
  }
  return value;
}

ReadBack ReadPdf(const std::vector<uint8_t>& bytes) {
  QPDF pdf;
  pdf.processMemoryFile("export.pdf", reinterpret_cast<const char*>(bytes.data()), bytes.size());
  ReadBack back;
  std::vector<QPDFPageObjectHelper> pages = QPDFPageDocumentHelper(pdf).getAllPages();
  REQUIRE(pages.size() == 1);
  QPDFObjectHandle page = pages[0].getObjectHandle();
  for (auto& item : page.getKey("/MediaBox").aitems()) back.media_box.push_back(item.getNumericValue());
  auto content = page.getKey("/Contents").getStreamData(qpdf_dl_generalized);
  back.content.assign(reinterpret_cast<const char*>(content->getBuffer()), content->getSize());
  QPDFObjectHandle shading = page.getKey("/Resources").getKey("/Shading").getKey("/Sh0");
  REQUIRE(shading.isStream());
  QPDFObjectHandle dict = shading.getDict();
  for (const char* key : {"/ShadingType", "/BitsPerCoordinate", "/BitsPerComponent", "/BitsPerFlag"}) {
    back.numbers[key] = double(dict.getKey(key).getIntValue());
  }
  REQUIRE(dict.getKey("/ColorSpace").getName() == "/DeviceRGB");
  REQUIRE(dict.getKey("/Filter").getName() == "/FlateDecode");
  for (auto& item : dict.getKey("/Decode").aitems()) back.decode.push_back(item.getNumericValue());
  REQUIRE(back.decode.size() == 10);

  auto data = shading.getStreamData(qpdf_dl_generalized);
  const std::string raw(reinterpret_cast<const char*>(data->getBuffer()), data->getSize());
  const int bc = int(back.numbers["/BitsPerCoordinate"]), bk = int(back.numbers["/BitsPerComponent"]),
            bf = int(back.numbers["/BitsPerFlag"]);
  const size_t record_bytes = size_t(bf + 2 * bc + 3 * bk + 7) / 8;
  REQUIRE(raw.size() % record_bytes == 0);
  for (size_t r = 0; r < raw.size() / record_bytes; ++r) {
    size_t bit = r * record_bytes * 8;
    DecodedVertex v;
    v.flag = int(ReadBits(raw, &bit, bf));
    double values[5];
    for (int k = 0; k < 5; ++k) {
      const int bits = k < 2 ? bc : bk;
      const double max_code = std::pow(2.0, bits) - 1;
      values[k] = back.decode[2 * k] +
                  double(ReadBits(raw, &bit, bits)) * (back.decode[2 * k + 1] - back.decode[2 * k]) / max_code;
    }
    v.x = values[0], v.y = values[1];
    for (int k = 0; k < 3; ++k) v.c[k] = values[2 + k];
    back.vertices.push_back(v);
  }

  QPDFObjectHandle info = pdf.getTrailer().getKey("/Info");
  back.producer = info.getKey("/Producer").getUTF8Value();
  back.source_width = info.getKey("/SdviSourceWidth").getIntValue();
  back.source_height = info.getKey("/SdviSourceHeight").getIntValue();
  return back;
}

// Decoded triangles (three vertices each) from the records, by the flag rule.
std::vector<std::array<DecodedVertex, 3>> DecodedTriangles(const std::vector<DecodedVertex>& records) {
  std::vector<std::array<DecodedVertex, 3>> triangles;
  for (size_t i = 0; i < records.size();) {
    if (records[i].flag == 0) {
      REQUIRE(i + 2 < records.size());
      triangles.push_back({records[i], records[i + 1], records[i + 2]});
      i += 3;
    } else {
      REQUIRE(!triangles.empty());
      const auto& p = triangles.back();
      if (records[i].flag == 1) {
        triangles.push_back({p[1], p[2], records[i]});
      } else {
        REQUIRE(records[i].flag == 2);
        triangles.push_back({p[0], p[2], records[i]});
      }
      ++i;
    }
  }
  return triangles;
}

double Area(const DecodedVertex& a, const DecodedVertex& b, const DecodedVertex& c) {
  return std::abs((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)) / 2;
}

TEST_CASE("TriangleStrips covers every triangle once and shares vertices", "[pdf]") {
  const Image image = pdf_test::Gradient(64, 48, 9, 7);
  for (int levels : {0, 1, 3}) {
    LimitSurfaceOptions options;
    options.levels = levels;
    auto surface = BuildLimitSurface(image, options);
    REQUIRE(surface.ok());
    const std::vector<ShadingRecord> records = TriangleStrips(surface->triangles);
    auto back = TrianglesFromRecords(records);
    REQUIRE(back.ok());
    CHECK(TriangleSet(*back) == TriangleSet(surface->triangles));
    // Strips: far fewer records than three per triangle on a connected mesh.
    CHECK(records.size() < 1.6 * surface->triangles.size() + 3);
  }
}

TEST_CASE("TriangleStrips on disconnected and reordered triangles", "[pdf]") {
  // Two separate triangles and a fan of four; listed in a scrambled order.
  const std::vector<Triangle> triangles = {
      {{10, 11, 12}}, {{0, 1, 2}}, {{0, 3, 4}}, {{0, 2, 3}}, {{20, 21, 22}}, {{0, 4, 5}}};
  const std::vector<ShadingRecord> records = TriangleStrips(triangles);
  auto back = TrianglesFromRecords(records);
  REQUIRE(back.ok());
  CHECK(TriangleSet(*back) == TriangleSet(triangles));
  // The fan of 4 is one strip (3 + 3 records), the two loose triangles 3 records each.
  CHECK(records.size() == 12);
}

TEST_CASE("TrianglesFromRecords rejects malformed flag sequences", "[pdf]") {
  CHECK(TrianglesFromRecords({{1, 0}, {0, 1}, {0, 2}}).status().code() == StatusCode::kCorrupt);
  CHECK(TrianglesFromRecords({{0, 0}, {0, 1}}).status().code() == StatusCode::kCorrupt);
  CHECK(TrianglesFromRecords({{0, 0}, {0, 1}, {0, 2}, {3, 4}}).status().code() == StatusCode::kCorrupt);
  CHECK(TrianglesFromRecords({{0, 0}, {1, 1}, {0, 2}}).status().code() == StatusCode::kCorrupt);
  auto ok = TrianglesFromRecords({{0, 0}, {0, 1}, {0, 2}, {1, 3}, {2, 4}});
  REQUIRE(ok.ok());
  REQUIRE(ok->size() == 3);
  CHECK((*ok)[1].v == std::array<uint32_t, 3>{1, 2, 3});
  CHECK((*ok)[2].v == std::array<uint32_t, 3>{1, 3, 4});
}

TEST_CASE("CoordinateBitsFor keeps the step at or below 1/64 pixel", "[pdf]") {
  CHECK(CoordinateBitsFor(1) == 8);
  CHECK(CoordinateBitsFor(255.0 / 64) == 8);
  CHECK(CoordinateBitsFor(4.0) == 12);
  CHECK(CoordinateBitsFor(4095.0 / 64) == 12);
  CHECK(CoordinateBitsFor(64) == 16);
  CHECK(CoordinateBitsFor(512) == 16);
  CHECK(CoordinateBitsFor(65535.0 / 64) == 16);
  CHECK(CoordinateBitsFor(1024) == 24);
  CHECK(CoordinateBitsFor(3840) == 24);
  CHECK(CoordinateBitsFor(1e6) == 32);
}

// The shading read back from the PDF is the limit surface: same triangle count and
// total area, every vertex within half a quantisation step of a fine vertex computed by
// RefineImage (direct refinement in double precision, not the exporter's stencils), and
// the same colour range.
void CheckShadingIsSurface(const Image& image, const PdfExportOptions& options) {
  auto exported = EncodePdf(image, options);
  REQUIRE(exported.ok());
  const ReadBack back = ReadPdf(exported->bytes);
  CHECK(back.numbers.at("/ShadingType") == 4);
  // Records are whole bytes (no padding question between readers): 8 + 2 * 16 + 3 * 8.
  const int record_bits = int(back.numbers.at("/BitsPerFlag") + 2 * back.numbers.at("/BitsPerCoordinate") +
                              3 * back.numbers.at("/BitsPerComponent"));
  CHECK(record_bits % 8 == 0);
  CHECK(back.numbers.at("/BitsPerFlag") == (options.color_bits == 12 ? 4 : 8));
  CHECK(back.numbers.at("/BitsPerComponent") == options.color_bits);
  CHECK(back.vertices.size() == exported->records);

  LimitSurfaceOptions surface_options;
  surface_options.levels = exported->levels;
  auto refined = RefineImage(image, surface_options);
  REQUIRE(refined.ok());
  CHECK(exported->triangles == refined->triangles.size());
  CHECK(exported->vertices == refined->vertices.size());

  // Two zero-area guard triangles first (spec/PDF.md), then the surface.
  const auto triangles = DecodedTriangles(back.vertices);
  REQUIRE(triangles.size() == refined->triangles.size() + 2);
  for (int g = 0; g < 2; ++g) {
    CHECK(Area(triangles[g][0], triangles[g][1], triangles[g][2]) == 0);
  }
  double area = 0, expected_area = 0;
  for (const auto& t : triangles) area += Area(t[0], t[1], t[2]);
  for (const Triangle& t : refined->triangles) {
    DecodedVertex p[3];
    for (int k = 0; k < 3; ++k) p[k].x = refined->vertices[t.v[k]].x, p[k].y = refined->vertices[t.v[k]].y;
    expected_area += Area(p[0], p[1], p[2]);
  }
  // Quantisation moves each vertex by at most one step (a full step on the bounding box's
  // sides, which round outwards), so the area by at most perimeter x step.
  const double max_step = std::max((back.decode[1] - back.decode[0]), (back.decode[3] - back.decode[2])) /
                          (std::pow(2.0, back.numbers.at("/BitsPerCoordinate")) - 1);
  CHECK(std::abs(area - expected_area) <= 2 * (image.width + image.height) * max_step + 1e-6 * expected_area);

  // Decode ranges: the surface's extent (grown by the guard margin on the left, right and
  // bottom) and colour range (clamped to 0..255).
  const int bc = int(back.numbers.at("/BitsPerCoordinate"));
  const double step_x = (back.decode[1] - back.decode[0]) / (std::pow(2.0, bc) - 1);
  const double step_y = (back.decode[3] - back.decode[2]) / (std::pow(2.0, bc) - 1);
  double lo[5], hi[5];
  std::fill(lo, lo + 5, 1e30);
  std::fill(hi, hi + 5, -1e30);
  for (const Vertex& v : refined->vertices) {
    const double values[5] = {v.x, v.y, std::clamp(v.r, 0.0f, 255.0f) / 255.0,
                              std::clamp(v.g, 0.0f, 255.0f) / 255.0, std::clamp(v.b, 0.0f, 255.0f) / 255.0};
    for (int k = 0; k < 5; ++k) lo[k] = std::min(lo[k], values[k]), hi[k] = std::max(hi[k], values[k]);
  }
  const double margin = std::max(2.0, 0.01 * std::max(hi[0] - lo[0], hi[1] - lo[1]));
  CHECK(back.decode[0] == Approx(lo[0] - margin).margin(1e-3));
  CHECK(back.decode[1] == Approx(hi[0] + margin).margin(1e-3));
  CHECK(back.decode[2] == Approx(lo[1]).margin(1e-3));
  CHECK(back.decode[3] == Approx(hi[1] + margin).margin(1e-3));
  for (int k = 2; k < 5; ++k) {
    CHECK(back.decode[2 * k] == Approx(lo[k]).margin(1e-4));
    if (hi[k] > lo[k]) CHECK(back.decode[2 * k + 1] == Approx(hi[k]).margin(1e-4));
  }
  double seen_lo[3] = {1e30, 1e30, 1e30}, seen_hi[3] = {-1e30, -1e30, -1e30};
  for (const DecodedVertex& v : back.vertices) {
    for (int k = 0; k < 3; ++k) seen_lo[k] = std::min(seen_lo[k], v.c[k]), seen_hi[k] = std::max(seen_hi[k], v.c[k]);
  }
  const double color_step = 1.0 / (std::pow(2.0, options.color_bits) - 1);
  for (int k = 0; k < 3; ++k) {
    CHECK(seen_lo[k] == Approx(lo[2 + k]).margin(color_step));
    CHECK(seen_hi[k] == Approx(hi[2 + k]).margin(color_step));
  }

  // Every fine vertex appears in the stream, quantised by at most half a step (a full step
  // on the bounding box's sides, which round outwards; + float noise of the stencil
  // evaluation).
  std::map<std::pair<long, long>, std::vector<const DecodedVertex*>> grid;
  for (const DecodedVertex& v : back.vertices) {
    grid[{std::lround((v.x - back.decode[0]) / step_x), std::lround((v.y - back.decode[2]) / step_y)}].push_back(&v);
  }
  size_t found = 0;
  for (const Vertex& f : refined->vertices) {
    const long gx = std::lround((f.x - back.decode[0]) / step_x), gy = std::lround((f.y - back.decode[2]) / step_y);
    bool match = false;
    for (long dx = -1; dx <= 1 && !match; ++dx) {
      for (long dy = -1; dy <= 1 && !match; ++dy) {
        auto it = grid.find({gx + dx, gy + dy});
        if (it == grid.end()) continue;
        for (const DecodedVertex* v : it->second) {
          const double colour[3] = {std::clamp(f.r, 0.0f, 255.0f) / 255.0, std::clamp(f.g, 0.0f, 255.0f) / 255.0,
                                    std::clamp(f.b, 0.0f, 255.0f) / 255.0};
          const bool side_x = f.x <= lo[0] || f.x >= hi[0], side_y = f.y <= lo[1] || f.y >= hi[1];
          bool same = std::abs(v->x - f.x) <= (side_x ? 1.0 : 0.5) * step_x + 1e-3 &&
                      std::abs(v->y - f.y) <= (side_y ? 1.0 : 0.5) * step_y + 1e-3;
          for (int k = 0; k < 3; ++k) {
            const double span = back.decode[5 + 2 * k] - back.decode[4 + 2 * k];
            same = same && std::abs(v->c[k] - colour[k]) <= 0.5 * span * color_step + 1e-4;
          }
          match = match || same;
        }
      }
    }
    found += match;
  }
  CHECK(found == refined->vertices.size());
}

TEST_CASE("The PDF's shading is the limit surface (full-frame image)", "[pdf]") {
  PdfExportOptions options;
  SECTION("default level and bits") { CheckShadingIsSurface(pdf_test::Gradient(96, 64), options); }
  SECTION("level 1, 12-bit coordinates, 16-bit colours") {
    options.levels = 1;
    options.coordinate_bits = 12;
    options.color_bits = 16;
    CheckShadingIsSurface(pdf_test::Gradient(96, 64), options);
  }
  SECTION("level 2, 24-bit coordinates, 12-bit colours") {
    options.levels = 2;
    options.coordinate_bits = 24;
    options.color_bits = 12;
    CheckShadingIsSurface(pdf_test::Gradient(96, 64), options);
  }
}

TEST_CASE("The PDF's shading is the limit surface (object image with a hole)", "[pdf]") {
  CheckShadingIsSurface(pdf_test::Annulus(80, 60), PdfExportOptions{});
}

TEST_CASE("An object image is clipped to its domain: one subpath per boundary loop", "[pdf]") {
  auto annulus = EncodePdf(pdf_test::Annulus(80, 60), PdfExportOptions{});
  REQUIRE(annulus.ok());
  const std::string content = ReadPdf(annulus->bytes).content;
  auto count = [&content](const std::string& op) {
    size_t n = 0;
    for (size_t p = content.find(op); p != std::string::npos; p = content.find(op, p + 1)) ++n;
    return n;
  };
  CHECK(count(" m\n") == 2);  // outer edge and the hole
  CHECK(count("\nh\n") == 2);
  CHECK(content.find("W* n\n/Sh0 sh") != std::string::npos);
  // A full-frame image: the frame, its collinear boundary points merged into 4 corners,
  // rounded outwards (at most one 16-bit step, 0.0016 px here, outside the frame).
  auto frame = EncodePdf(pdf_test::Gradient(96, 64), PdfExportOptions{});
  REQUIRE(frame.ok());
  const std::string frame_content = ReadPdf(frame->bytes).content;
  std::vector<double> corners;
  {
    std::istringstream in(frame_content.substr(frame_content.find(" cm\n") + 4));
    std::string token;
    while (in >> token && token != "W*") {
      if (token != "m" && token != "l" && token != "h") corners.push_back(std::stod(token));
    }
  }
  REQUIRE(corners.size() == 8);
  for (size_t i = 0; i < 8; i += 2) {
    const double x = corners[i], y = corners[i + 1];
    CHECK(((x <= 0 && x > -0.002) || (x >= 96 && x < 96.002)));
    CHECK(((y <= 0 && y > -0.002) || (y >= 64 && y < 64.002)));
  }
}

TEST_CASE("Page size from dpi or width, background, metadata", "[pdf]") {
  const Image image = pdf_test::Gradient(96, 64);
  PdfExportOptions options;
  auto at72 = EncodePdf(image, options);
  REQUIRE(at72.ok());
  ReadBack back = ReadPdf(at72->bytes);
  CHECK(back.media_box == std::vector<double>{0, 0, 96, 64});
  CHECK(back.producer.rfind("sdvi ", 0) == 0);
  CHECK(back.source_width == 96);
  CHECK(back.source_height == 64);
  CHECK(back.content.find("rg") == std::string::npos);  // no background by default

  options.dpi = 144;
  options.background = PdfBackground::kWhite;
  auto at144 = EncodePdf(image, options);
  REQUIRE(at144.ok());
  back = ReadPdf(at144->bytes);
  CHECK(back.media_box == std::vector<double>{0, 0, 48, 32});
  CHECK(back.content.rfind("q 1 1 1 rg 0 0 48 32 re f Q\n", 0) == 0);

  options.width_mm = 50.8;  // 2 inches = 144 pt, overrides the dpi
  auto wide = EncodePdf(image, options);
  REQUIRE(wide.ok());
  CHECK(wide->page_width_pt == Approx(144));
  CHECK(wide->page_height_pt == Approx(96));
}

TEST_CASE("The same input gives byte-identical PDFs", "[pdf]") {
  auto a = EncodePdf(pdf_test::Annulus(80, 60), PdfExportOptions{});
  auto b = EncodePdf(pdf_test::Annulus(80, 60), PdfExportOptions{});
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  CHECK(a->bytes == b->bytes);
}

TEST_CASE("The sRGB profile colour space: an ICC stream, the same shading, byte-identical files", "[pdf]") {
  const Image image = pdf_test::Gradient(96, 64);
  PdfExportOptions options;
  auto device = EncodePdf(image, options);
  options.color_space = PdfColorSpace::kSrgbIcc;
  auto icc = EncodePdf(image, options);
  auto again = EncodePdf(image, options);
  REQUIRE(device.ok());
  REQUIRE(icc.ok());
  REQUIRE(again.ok());
  CHECK(icc->bytes == again->bytes);  // the profile's creation date is fixed

  auto shading_of = [](QPDF& pdf, const std::vector<uint8_t>& bytes) {
    pdf.processMemoryFile("export.pdf", reinterpret_cast<const char*>(bytes.data()), bytes.size());
    QPDFObjectHandle page = QPDFPageDocumentHelper(pdf).getAllPages().at(0).getObjectHandle();
    return page.getKey("/Resources").getKey("/Shading").getKey("/Sh0");
  };
  auto data_of = [](QPDFObjectHandle stream) {
    auto buffer = stream.getStreamData(qpdf_dl_generalized);
    return std::string(reinterpret_cast<const char*>(buffer->getBuffer()), buffer->getSize());
  };
  QPDF device_pdf, icc_pdf;
  QPDFObjectHandle device_shading = shading_of(device_pdf, device->bytes);
  QPDFObjectHandle icc_shading = shading_of(icc_pdf, icc->bytes);
  CHECK(data_of(icc_shading) == data_of(device_shading));  // the same vertices and colours

  QPDFObjectHandle space = icc_shading.getDict().getKey("/ColorSpace");
  REQUIRE(space.isArray());
  REQUIRE(space.getArrayNItems() == 2);
  CHECK(space.getArrayItem(0).getName() == "/ICCBased");
  QPDFObjectHandle profile = space.getArrayItem(1);
  REQUIRE(profile.isStream());
  CHECK(profile.getDict().getKey("/N").getIntValue() == 3);
  CHECK(profile.getDict().getKey("/Alternate").getName() == "/DeviceRGB");
  // The ICC header: its size, a display ('mntr') RGB profile with PCS XYZ, the signature
  // 'acsp', and the fixed creation date 2000-01-01 00:00:00.
  const std::string icc_bytes = data_of(profile);
  REQUIRE(icc_bytes.size() >= 128);
  auto u32 = [&](size_t at) {
    return uint32_t(uint8_t(icc_bytes[at])) << 24 | uint32_t(uint8_t(icc_bytes[at + 1])) << 16 |
           uint32_t(uint8_t(icc_bytes[at + 2])) << 8 | uint32_t(uint8_t(icc_bytes[at + 3]));
  };
  CHECK(u32(0) == icc_bytes.size());
  CHECK(icc_bytes.substr(12, 4) == "mntr");
  CHECK(icc_bytes.substr(16, 4) == "RGB ");
  CHECK(icc_bytes.substr(20, 4) == "XYZ ");
  CHECK(icc_bytes.substr(36, 4) == "acsp");
  CHECK(icc_bytes.substr(24, 12) == std::string("\x07\xd0\x00\x01\x00\x01\x00\x00\x00\x00\x00\x00", 12));
}

TEST_CASE("Bad options and inputs give specific codes", "[pdf]") {
  const Image image = pdf_test::Gradient(96, 64);
  auto code = [](const Image& im, PdfExportOptions o) { return EncodePdf(im, o).status().code(); };
  PdfExportOptions o;
  o.levels = 7;
  CHECK(code(image, o) == StatusCode::kInvalidArgument);
  o = {};
  o.dpi = 0;
  CHECK(code(image, o) == StatusCode::kInvalidArgument);
  o = {};
  o.width_mm = -3;
  CHECK(code(image, o) == StatusCode::kInvalidArgument);
  o = {};
  o.coordinate_bits = 10;
  CHECK(code(image, o) == StatusCode::kInvalidArgument);
  o = {};
  o.color_bits = 4;
  CHECK(code(image, o) == StatusCode::kInvalidArgument);
  o = {};
  o.dpi = 0.1;  // 69120 pt wide
  CHECK(code(image, o) == StatusCode::kLimitExceeded);
  CHECK(code(Image{}, {}) == StatusCode::kEmptyInput);
  Image bad = image;
  bad.vertices[3].g = NAN;
  CHECK(code(bad, {}) == StatusCode::kNonFinite);
  Image broken = image;
  broken.triangles[0].v[1] = 9999;
  CHECK(code(broken, {}) == StatusCode::kIndexOutOfRange);
}

TEST_CASE("WritePdf leaves nothing behind on failure", "[pdf]") {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "sdvi_pdf_test_missing";
  std::filesystem::remove_all(dir);
  const std::string path = (dir / "out.pdf").string();
  auto written = WritePdf(path, pdf_test::Gradient(96, 64), {});
  CHECK(written.status().code() == StatusCode::kIoError);
  CHECK(!std::filesystem::exists(dir));
  auto empty = WritePdf((std::filesystem::temp_directory_path() / "sdvi_pdf_empty.pdf").string(), Image{}, {});
  CHECK(empty.status().code() == StatusCode::kEmptyInput);
  CHECK(!std::filesystem::exists(std::filesystem::temp_directory_path() / "sdvi_pdf_empty.pdf"));
}

TEST_CASE("The default level is the exporters' rule", "[pdf]") {
  const Image image = pdf_test::Gradient(96, 64);
  auto exported = EncodePdf(image, {});
  REQUIRE(exported.ok());
  CHECK(exported->levels == DefaultExportLevels(image));
  CHECK(exported->triangles == image.triangles.size() << (2 * exported->levels));
}

TEST_CASE("ColorGradient is the steepest channel's plane gradient", "[pdf]") {
  // r rises by 100 over 2 px in x, g by 100 over 4 px in y: |grad r| = 50, |grad g| = 25.
  const Vertex a{0, 0, 0, 0, 7}, b{2, 0, 100, 0, 7}, c{0, 4, 0, 100, 7};
  CHECK(ColorGradient(a, b, c) == Approx(50));
  CHECK(ColorGradient(c, a, b) == Approx(50));  // any vertex order, either orientation
  CHECK(ColorGradient(a, c, b) == Approx(50));
  // A diagonal ramp: b rises by 30 from (0,0) to (3,4), constant across it.
  const Vertex p{0, 0, 0, 0, 0}, q{3, 4, 0, 0, 30}, r{-4, 3, 0, 0, 0};
  CHECK(ColorGradient(p, q, r) == Approx(6));
  // Zero area: flat colour 0, different colours infinitely steep.
  const Vertex d{1, 0, 0, 0, 7};
  CHECK(ColorGradient(a, d, b) == std::numeric_limits<double>::infinity());
  const Vertex e{1, 0, 0, 0, 7}, f{2, 0, 0, 0, 7};
  CHECK(ColorGradient(a, e, f) == 0);
}

// A full-frame image with a one-pixel colour ramp: vertex columns at x = 0, 15, 16, 32, the
// left two dark, the right two light (a 200-level step over 1 px).
Image StepImage() {
  Image image;
  image.width = 32;
  image.height = 24;
  const float xs[4] = {0, 15, 16, 32};
  auto id = [](int i, int j) { return uint32_t(j * 4 + i); };
  for (int j = 0; j <= 2; ++j) {
    for (int i = 0; i < 4; ++i) {
      const bool light = i >= 2;
      image.vertices.push_back({xs[i], 12.0f * j, light ? 220.0f : 20.0f, light ? 200.0f : 40.0f,
                                light ? 180.0f : 60.0f});
    }
  }
  testing::AppendGridTriangles(3, 2, id, &image.triangles);
  return image;
}

TEST_CASE("Steep triangles are painted first, then the others", "[pdf]") {
  const Image image = StepImage();
  PdfExportOptions options;
  options.levels = 2;
  CheckShadingIsSurface(image, options);  // the reordered shading is still the surface

  auto exported = EncodePdf(image, options);
  REQUIRE(exported.ok());
  LimitSurfaceOptions surface_options;
  surface_options.levels = 2;
  auto refined = RefineImage(image, surface_options);
  REQUIRE(refined.ok());
  uint32_t steep = 0;
  for (const Triangle& t : refined->triangles) {
    const auto& v = refined->vertices;
    steep += ColorGradient(v[t.v[0]], v[t.v[1]], v[t.v[2]]) > kSteepColorGradient;
  }
  REQUIRE(steep > 0);
  REQUIRE(steep < refined->triangles.size());
  CHECK(exported->steep_triangles == steep);

  // Read back: after the two guards, the first `steep` triangles are the steep ones. The
  // decoded gradients carry the quantisation of colours (<= 1 level) and positions, so the
  // check allows a factor of two around the threshold.
  const auto triangles = DecodedTriangles(ReadPdf(exported->bytes).vertices);
  REQUIRE(triangles.size() == refined->triangles.size() + 2);
  auto decoded_gradient = [](const std::array<DecodedVertex, 3>& t) {
    Vertex v[3];
    for (int k = 0; k < 3; ++k) {
      v[k] = {float(t[k].x), float(t[k].y), float(t[k].c[0] * 255), float(t[k].c[1] * 255),
              float(t[k].c[2] * 255)};
    }
    return ColorGradient(v[0], v[1], v[2]);
  };
  for (size_t i = 2; i < triangles.size(); ++i) {
    const double g = decoded_gradient(triangles[i]);
    if (i < 2 + steep) {
      CHECK(g > kSteepColorGradient / 2);
    } else {
      CHECK(g < kSteepColorGradient * 2);
    }
  }
}

}  // namespace
}  // namespace sdvi
