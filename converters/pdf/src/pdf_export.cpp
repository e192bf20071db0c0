// SPDX-License-Identifier: GPL-3.0-or-later
// PDF export: limit surface -> type-4 shading strips -> qpdf document. The mapping (page,
// coordinates, quantisation, colour space, clip, metadata) is specified in spec/PDF.md.
#include "sdvi/pdf.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <limits>
#include <new>
#include <stdexcept>
#include <unordered_map>
#include <utility>

#include <lcms2.h>
#include <zlib.h>

#include <qpdf/Buffer.hh>
#include <qpdf/QPDF.hh>
#include <qpdf/QPDFObjectHandle.hh>
#include <qpdf/QPDFPageDocumentHelper.hh>
#include <qpdf/QPDFWriter.hh>

#include "sdvi/export_levels.h"
#include "sdvi/file_util.h"
#include "sdvi/subdiv.h"

#ifndef SDVI_VERSION
#define SDVI_VERSION "unknown"
#endif

namespace sdvi {
namespace {

// Coordinates are quantised to at most this step (source pixels): position errors move
// colour edges, and 1/64 px keeps the error on a 255-level edge below 4 levels.
constexpr double kMaxCoordinateStep = 1.0 / 64;

// BitsPerFlag (2, 4 or 8) that makes a vertex record a whole number of bytes. Readers
// disagree on padding between records (poppler and pdf.js skip to the next byte, MuPDF
// reads on), so records never need any: 2 * coordinate bits is a multiple of 8 for
// every allowed width, and 3 * colour bits leaves 0 (8, 16 bits) or 4 (12 bits).
int FlagBitsFor(int coordinate_bits, int color_bits) {
  const int rest = (2 * coordinate_bits + 3 * color_bits) % 8;
  return rest == 0 ? 8 : 8 - rest;
}

uint64_t EdgeKey(uint32_t a, uint32_t b) {
  if (a > b) std::swap(a, b);
  return (uint64_t(a) << 32) | b;
}

// The (up to two) triangles on each edge, for the strip walk.
class EdgeTriangles {
 public:
  explicit EdgeTriangles(const std::vector<Triangle>& triangles) {
    map_.reserve(triangles.size() * 2);
    for (uint32_t t = 0; t < triangles.size(); ++t) {
      const auto& v = triangles[t].v;
      for (int k = 0; k < 3; ++k) {
        auto [it, inserted] = map_.try_emplace(EdgeKey(v[k], v[(k + 1) % 3]), Pair{t, kNone});
        if (!inserted && it->second.second == kNone) it->second.second = t;
      }
    }
  }
  // The triangle other than t on edge (a, b), or kNone.
  uint32_t Across(uint32_t a, uint32_t b, uint32_t t) const {
    auto it = map_.find(EdgeKey(a, b));
    if (it == map_.end()) return kNone;
    if (it->second.first == t) return it->second.second;
    if (it->second.second == t) return it->second.first;
    return kNone;
  }
  static constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

 private:
  using Pair = std::pair<uint32_t, uint32_t>;
  std::unordered_map<uint64_t, Pair> map_;
};

uint32_t ThirdVertex(const Triangle& t, uint32_t a, uint32_t b) {
  for (uint32_t v : t.v) {
    if (v != a && v != b) return v;
  }
  return t.v[0];
}

// Unvisited triangles across the edges of t (0..3).
int OpenNeighbours(const std::vector<Triangle>& triangles, const EdgeTriangles& edges,
                   const std::vector<bool>& visited, uint32_t t) {
  const auto& v = triangles[t].v;
  int open = 0;
  for (int k = 0; k < 3; ++k) {
    const uint32_t n = edges.Across(v[k], v[(k + 1) % 3], t);
    open += n != EdgeTriangles::kNone && !visited[n];
  }
  return open;
}

}  // namespace

std::vector<ShadingRecord> TriangleStrips(const std::vector<Triangle>& triangles) {
  const EdgeTriangles edges(triangles);
  std::vector<bool> visited(triangles.size(), false);
  std::vector<ShadingRecord> records;
  records.reserve(triangles.size() + triangles.size() / 4 + 3);
  for (uint32_t seed = 0; seed < triangles.size(); ++seed) {
    if (visited[seed]) continue;
    visited[seed] = true;
    // Order the seed (a, b, c) so that edge (b, c) leads to an unvisited neighbour.
    const auto& s = triangles[seed].v;
    uint32_t a = s[0], b = s[1], c = s[2];
    for (int k = 0; k < 3; ++k) {
      const uint32_t p = s[(k + 1) % 3], q = s[(k + 2) % 3];
      const uint32_t n = edges.Across(p, q, seed);
      if (n != EdgeTriangles::kNone && !visited[n]) {
        a = s[k], b = p, c = q;
        break;
      }
    }
    records.push_back({0, a});
    records.push_back({0, b});
    records.push_back({0, c});
    uint32_t current = seed;
    for (;;) {
      // Flag 1 continues across (b, c), flag 2 across (a, c); of two open candidates take
      // the one with fewer open neighbours (the one more likely to be stranded).
      const uint32_t n1 = edges.Across(b, c, current), n2 = edges.Across(a, c, current);
      const bool open1 = n1 != EdgeTriangles::kNone && !visited[n1];
      const bool open2 = n2 != EdgeTriangles::kNone && !visited[n2];
      if (!open1 && !open2) break;
      bool take1 = open1;
      if (open1 && open2) {
        take1 = OpenNeighbours(triangles, edges, visited, n1) <=
                OpenNeighbours(triangles, edges, visited, n2);
      }
      if (take1) {
        const uint32_t d = ThirdVertex(triangles[n1], b, c);
        records.push_back({1, d});
        a = b, b = c, c = d;
        current = n1;
      } else {
        const uint32_t d = ThirdVertex(triangles[n2], a, c);
        records.push_back({2, d});
        b = c, c = d;
        current = n2;
      }
      visited[current] = true;
    }
  }
  return records;
}

StatusOr<std::vector<Triangle>> TrianglesFromRecords(const std::vector<ShadingRecord>& records) {
  std::vector<Triangle> triangles;
  bool have_previous = false;
  uint32_t a = 0, b = 0, c = 0;
  for (size_t i = 0; i < records.size();) {
    const ShadingRecord& r = records[i];
    if (r.flag == 0) {
      if (i + 2 >= records.size() || records[i + 1].flag != 0 || records[i + 2].flag != 0) {
        return Status(StatusCode::kCorrupt, "shading record " + std::to_string(i) +
                                                ": a flag-0 triangle needs three flag-0 records");
      }
      a = r.vertex, b = records[i + 1].vertex, c = records[i + 2].vertex;
      i += 3;
    } else if (r.flag == 1 || r.flag == 2) {
      if (!have_previous) {
        return Status(StatusCode::kCorrupt, "shading record " + std::to_string(i) + ": flag " +
                                                std::to_string(r.flag) +
                                                " without a previous triangle");
      }
      if (r.flag == 1) {
        a = b, b = c, c = r.vertex;
      } else {
        b = c, c = r.vertex;
      }
      ++i;
    } else {
      return Status(StatusCode::kCorrupt, "shading record " + std::to_string(i) + ": flag " +
                                              std::to_string(r.flag) + " is not 0, 1 or 2");
    }
    triangles.push_back(Triangle{{a, b, c}});
    have_previous = true;
  }
  return triangles;
}

double ColorGradient(const Vertex& a, const Vertex& b, const Vertex& c) {
  const double ux = double(b.x) - a.x, uy = double(b.y) - a.y;
  const double wx = double(c.x) - a.x, wy = double(c.y) - a.y;
  const double area2 = ux * wy - uy * wx;  // twice the signed area
  const double ca[3] = {a.r, a.g, a.b}, cb[3] = {b.r, b.g, b.b}, cc[3] = {c.r, c.g, c.b};
  double gradient = 0;
  for (int k = 0; k < 3; ++k) {
    const double d1 = cb[k] - ca[k], d2 = cc[k] - ca[k];
    if (area2 == 0) {
      if (d1 != 0 || d2 != 0) return std::numeric_limits<double>::infinity();
      continue;
    }
    // The plane c(p) = ca + gx (x - ax) + gy (y - ay) through the three colours.
    const double gx = (d1 * wy - d2 * uy) / area2, gy = (d2 * ux - d1 * wx) / area2;
    gradient = std::max(gradient, std::hypot(gx, gy));
  }
  return gradient;
}

int CoordinateBitsFor(double extent) {
  for (int bits : {8, 12, 16, 24}) {
    if (extent / double((uint64_t(1) << bits) - 1) <= kMaxCoordinateStep) return bits;
  }
  return 32;
}

namespace {

// MSB-first bit packing.
class BitWriter {
 public:
  void Put(uint64_t value, int bits) {
    for (int i = bits - 1; i >= 0; --i) {
      acc_ = uint8_t((acc_ << 1) | ((value >> i) & 1));
      if (++fill_ == 8) Flush();
    }
  }
  bool aligned() const { return fill_ == 0; }
  std::string& bytes() { return bytes_; }

 private:
  void Flush() {
    bytes_.push_back(char(acc_));
    acc_ = 0;
    fill_ = 0;
  }
  std::string bytes_;
  uint8_t acc_ = 0;
  int fill_ = 0;
};

// value in [lo, hi] -> 0 .. 2^bits - 1 (the inverse of the Decode mapping).
enum class Rounding { kNearest, kDown, kUp };

uint64_t Quantise(double value, double lo, double hi, int bits, Rounding rounding = Rounding::kNearest) {
  const double max_code = double((uint64_t(1) << bits) - 1);
  if (!(hi > lo)) return 0;
  const double exact = (value - lo) / (hi - lo) * max_code;
  const double q = rounding == Rounding::kDown ? std::floor(exact)
                   : rounding == Rounding::kUp ? std::ceil(exact)
                                               : std::round(exact);
  return uint64_t(std::clamp(q, 0.0, max_code));
}

double Dequantise(uint64_t code, double lo, double hi, int bits) {
  const double max_code = double((uint64_t(1) << bits) - 1);
  return lo + double(code) * (hi - lo) / max_code;
}

// Colours are clamped to 0..255 (what every renderer does), as fractions of 255.
double ColorFraction(float value) { return std::clamp(double(value), 0.0, 255.0) / 255.0; }

// The Decode array: coordinate range of the used vertices (a zero extent widened by one
// pixel) and each colour's range as a fraction of 255.
std::array<double, 10> DecodeRange(const std::vector<Vertex>& fine) {
  std::array<double, 10> d;
  for (int k = 0; k < 5; ++k) {
    d[2 * k] = std::numeric_limits<double>::infinity();
    d[2 * k + 1] = -std::numeric_limits<double>::infinity();
  }
  for (const Vertex& v : fine) {
    const double values[5] = {v.x, v.y, ColorFraction(v.r), ColorFraction(v.g), ColorFraction(v.b)};
    for (int k = 0; k < 5; ++k) {
      d[2 * k] = std::min(d[2 * k], values[k]);
      d[2 * k + 1] = std::max(d[2 * k + 1], values[k]);
    }
  }
  for (int k = 0; k < 2; ++k) {
    if (!(d[2 * k + 1] > d[2 * k])) d[2 * k + 1] = d[2 * k] + 1;
  }
  return d;
}

// The two guard vertices: the bottom corners of the surface's bounding box grown by
// kGuardMargin (at least 2 source pixels, 1% of the larger side), with the colour of fine
// vertex 0. Each is repeated three times as a zero-area triangle painted before the surface
// and outside the clip, so it shows nowhere; it only widens the mesh's bounds, which pdf.js
// rasterises into a canvas of exactly that size and where spans ending on the right bound
// spill into column 0 of the next row (spec/PDF.md, "Guard triangles").
std::array<Vertex, 2> GuardVertices(const std::vector<Vertex>& fine, const std::array<float, 4>& box) {
  const auto [x0, x1, y0, y1] = box;
  const float margin = std::max(2.0f, 0.01f * std::max(x1 - x0, y1 - y0));
  const Vertex& c = fine[0];
  return {Vertex{x0 - margin, y1 + margin, c.r, c.g, c.b}, Vertex{x1 + margin, y1 + margin, c.r, c.g, c.b}};
}

// The surface's bounding box: x0, x1, y0, y1.
std::array<float, 4> BoundingBox(const std::vector<Vertex>& fine) {
  std::array<float, 4> box = {fine[0].x, fine[0].x, fine[0].y, fine[0].y};
  for (const Vertex& v : fine) {
    box[0] = std::min(box[0], v.x), box[1] = std::max(box[1], v.x);
    box[2] = std::min(box[2], v.y), box[3] = std::max(box[3], v.y);
  }
  return box;
}

// A fine vertex as the reader will see it: quantised and decoded.
struct QuantisedVertex {
  uint64_t code[5];
  double x, y;
};

// Coordinates round to the nearest code, except on the sides of the surface's bounding box
// `box` (x0, x1, y0, y1), where they round outwards: a full-frame image then covers its whole
// frame even in viewers that sample pixels half a pixel off (MuPDF) and whose last column
// or row would otherwise fall just outside the mesh.
QuantisedVertex QuantiseVertex(const Vertex& v, const std::array<double, 10>& d,
                               const std::array<float, 4>& box, int coord_bits, int color_bits) {
  QuantisedVertex q;
  const double values[5] = {v.x, v.y, ColorFraction(v.r), ColorFraction(v.g), ColorFraction(v.b)};
  for (int k = 0; k < 5; ++k) {
    Rounding rounding = Rounding::kNearest;
    if (k < 2 && values[k] <= box[2 * k]) rounding = Rounding::kDown;
    if (k < 2 && values[k] >= box[2 * k + 1]) rounding = Rounding::kUp;
    q.code[k] = Quantise(values[k], d[2 * k], d[2 * k + 1], k < 2 ? coord_bits : color_bits, rounding);
  }
  q.x = Dequantise(q.code[0], d[0], d[1], coord_bits);
  q.y = Dequantise(q.code[1], d[2], d[3], coord_bits);
  return q;
}

// The shading stream's data: one record (a whole number of bytes) per ShadingRecord.
std::string PackRecords(const std::vector<ShadingRecord>& records,
                        const std::vector<QuantisedVertex>& vertices, int flag_bits,
                        int coord_bits, int color_bits) {
  BitWriter writer;
  const int record_bits = flag_bits + 2 * coord_bits + 3 * color_bits;
  writer.bytes().reserve(records.size() * size_t(record_bits / 8));
  for (const ShadingRecord& r : records) {
    const QuantisedVertex& q = vertices[r.vertex];
    writer.Put(r.flag, flag_bits);
    for (int k = 0; k < 5; ++k) writer.Put(q.code[k], k < 2 ? coord_bits : color_bits);
  }
  assert(writer.aligned());
  return std::move(writer.bytes());
}

StatusOr<std::string> Deflate(const std::string& raw) {
  uLongf size = compressBound(uLong(raw.size()));
  std::string out(size, '\0');
  const int rc = compress2(reinterpret_cast<Bytef*>(out.data()), &size,
                           reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()),
                           Z_BEST_COMPRESSION);
  if (rc != Z_OK) {
    return Status(StatusCode::kEncodeFailed,
                  "PDF export: zlib could not compress the shading (error " + std::to_string(rc) + ")");
  }
  out.resize(size);
  return out;
}

// A number for a content stream: fixed point, at most `decimals` digits, no trailing zeros.
std::string Number(double value, int decimals = 4) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  std::string s(buffer);
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

// The domain's boundary as closed loops of fine vertices: edges used by one triangle,
// chained; collinear interior points are dropped (a straight side costs two points).
std::vector<std::vector<uint32_t>> BoundaryLoops(const std::vector<Triangle>& triangles,
                                                 const std::vector<QuantisedVertex>& vertices) {
  std::unordered_map<uint64_t, int> use;
  use.reserve(triangles.size() * 2);
  for (const Triangle& t : triangles) {
    for (int k = 0; k < 3; ++k) ++use[EdgeKey(t.v[k], t.v[(k + 1) % 3])];
  }
  std::vector<std::pair<uint32_t, uint32_t>> boundary;
  for (const auto& [key, count] : use) {
    if (count == 1) boundary.push_back({uint32_t(key >> 32), uint32_t(key)});
  }
  std::sort(boundary.begin(), boundary.end());  // deterministic whatever the hash order
  std::unordered_map<uint32_t, std::vector<size_t>> at;
  for (size_t e = 0; e < boundary.size(); ++e) {
    at[boundary[e].first].push_back(e);
    at[boundary[e].second].push_back(e);
  }
  std::vector<bool> used(boundary.size(), false);
  std::vector<std::vector<uint32_t>> loops;
  for (size_t start = 0; start < boundary.size(); ++start) {
    if (used[start]) continue;
    used[start] = true;
    std::vector<uint32_t> loop = {boundary[start].first};
    uint32_t v = boundary[start].second;
    while (v != loop.front()) {
      loop.push_back(v);
      size_t next = boundary.size();
      for (size_t e : at[v]) {
        if (!used[e]) {
          next = e;
          break;
        }
      }
      if (next == boundary.size()) break;  // an open chain (cannot happen on a closed mesh)
      used[next] = true;
      v = boundary[next].first == v ? boundary[next].second : boundary[next].first;
    }
    // Drop points on the straight line through their neighbours (exactly, in quantised
    // coordinates: a zero cross product).
    std::vector<uint32_t> kept;
    const size_t n = loop.size();
    for (size_t i = 0; i < n; ++i) {
      const QuantisedVertex& p = vertices[loop[(i + n - 1) % n]];
      const QuantisedVertex& q = vertices[loop[i]];
      const QuantisedVertex& r = vertices[loop[(i + 1) % n]];
      const double cross = (double(q.code[0]) - double(p.code[0])) * (double(r.code[1]) - double(q.code[1])) -
                           (double(q.code[1]) - double(p.code[1])) * (double(r.code[0]) - double(q.code[0]));
      if (n <= 3 || cross != 0) kept.push_back(loop[i]);
    }
    if (kept.size() >= 3) loops.push_back(std::move(kept));
  }
  return loops;
}

std::string ClipPath(const std::vector<std::vector<uint32_t>>& loops,
                     const std::vector<QuantisedVertex>& vertices) {
  std::string path;
  for (const auto& loop : loops) {
    for (size_t i = 0; i < loop.size(); ++i) {
      const QuantisedVertex& q = vertices[loop[i]];
      path += Number(q.x) + " " + Number(q.y) + (i == 0 ? " m\n" : " l\n");
    }
    path += "h\n";
  }
  return path;
}

Status CheckOptions(const PdfExportOptions& options) {
  if (options.levels < -1 || options.levels > kMaxPdfLevels) {
    return Status(StatusCode::kInvalidArgument,
                  "PDF export: levels " + std::to_string(options.levels) + " is outside 0.." +
                      std::to_string(kMaxPdfLevels) + " (or -1 for auto)");
  }
  if (!(options.dpi > 0) || !std::isfinite(options.dpi)) {
    return Status(StatusCode::kInvalidArgument,
                  "PDF export: dpi " + Number(options.dpi) + " must be a positive number");
  }
  if (options.width_mm < 0 || !std::isfinite(options.width_mm)) {
    return Status(StatusCode::kInvalidArgument, "PDF export: width " + Number(options.width_mm) +
                                                    " mm must be positive (or 0 to use the dpi)");
  }
  const int cb = options.coordinate_bits;
  if (cb != 0 && cb != 8 && cb != 12 && cb != 16 && cb != 24 && cb != 32) {
    return Status(StatusCode::kInvalidArgument, "PDF export: coordinate bits " +
                                                    std::to_string(cb) +
                                                    " is not 0 (auto), 8, 12, 16, 24 or 32");
  }
  const int kb = options.color_bits;
  if (kb != 8 && kb != 12 && kb != 16) {
    return Status(StatusCode::kInvalidArgument,
                  "PDF export: colour bits " + std::to_string(kb) + " is not 8, 12 or 16");
  }
  return Status::Ok();
}

Status CheckImage(const Image& image) {
  SDVI_RETURN_IF_ERROR(CheckExportInput(image, "PDF export"));
  if (image.width == 0 || image.height == 0) {
    return Status(StatusCode::kEmptyInput, "PDF export: the image size is " +
                                               std::to_string(image.width) + " x " +
                                               std::to_string(image.height) + " pixels");
  }
  return Status::Ok();
}

QPDFObjectHandle RealArray(const std::vector<double>& values, int decimals) {
  QPDFObjectHandle array = QPDFObjectHandle::newArray();
  for (double v : values) array.appendItem(QPDFObjectHandle::newReal(Number(v, decimals)));
  return array;
}

// Little CMS's built-in sRGB profile (IEC 61966-2-1), serialised. The header's creation date
// (bytes 24..35, six big-endian 16-bit numbers) is the time the profile object was made; it
// is set to a fixed 2000-01-01 00:00:00 so that an export is byte-identical run to run.
StatusOr<std::string> SrgbIccProfile() {
  cmsHPROFILE profile = cmsCreate_sRGBProfile();
  if (profile == nullptr) {
    return Status(StatusCode::kEncodeFailed, "PDF export: Little CMS could not make the sRGB profile");
  }
  cmsUInt32Number size = 0;
  std::string bytes;
  bool saved = cmsSaveProfileToMem(profile, nullptr, &size) && size >= 128;
  if (saved) {
    bytes.resize(size);
    saved = cmsSaveProfileToMem(profile, bytes.data(), &size) && size == bytes.size();
  }
  cmsCloseProfile(profile);
  if (!saved) {
    return Status(StatusCode::kEncodeFailed, "PDF export: Little CMS could not write the sRGB profile");
  }
  constexpr uint16_t kCreated[6] = {2000, 1, 1, 0, 0, 0};
  for (int i = 0; i < 6; ++i) {
    bytes[24 + 2 * i] = char(kCreated[i] >> 8);
    bytes[25 + 2 * i] = char(kCreated[i] & 0xFF);
  }
  return bytes;
}

std::string MetadataValue(const Image& image, const std::string& key) {
  for (const auto& [k, value] : image.metadata) {
    if (k == key) return value;
  }
  return "";
}

// The document: Info, one page with the clip + shading content, written by QPDFWriter.
StatusOr<std::vector<uint8_t>> BuildDocument(const Image& image, const PdfExport& result,
                                             const PdfExportOptions& options,
                                             const std::string& shading_data,
                                             const std::string& clip_path) {
  QPDF pdf;
  pdf.emptyPDF();

  QPDFObjectHandle shading = pdf.newStream();
  QPDFObjectHandle dict = shading.getDict();
  dict.replaceKey("/ShadingType", QPDFObjectHandle::newInteger(4));
  if (options.color_space == PdfColorSpace::kSrgbIcc) {
    SDVI_ASSIGN_OR_RETURN(std::string icc, SrgbIccProfile());
    QPDFObjectHandle profile = pdf.newStream(icc);
    profile.getDict().replaceKey("/N", QPDFObjectHandle::newInteger(3));
    profile.getDict().replaceKey("/Alternate", QPDFObjectHandle::newName("/DeviceRGB"));
    QPDFObjectHandle space = QPDFObjectHandle::newArray();
    space.appendItem(QPDFObjectHandle::newName("/ICCBased"));
    space.appendItem(profile);
    dict.replaceKey("/ColorSpace", space);
  } else {
    dict.replaceKey("/ColorSpace", QPDFObjectHandle::newName("/DeviceRGB"));
  }
  dict.replaceKey("/BitsPerCoordinate", QPDFObjectHandle::newInteger(result.bits_per_coordinate));
  dict.replaceKey("/BitsPerComponent", QPDFObjectHandle::newInteger(result.bits_per_component));
  dict.replaceKey("/BitsPerFlag", QPDFObjectHandle::newInteger(result.bits_per_flag));
  // Decode: 6 decimals of a pixel / of full scale, exactly what quantisation assumed.
  dict.replaceKey("/Decode", RealArray(std::vector<double>(result.decode.begin(), result.decode.end()), 9));
  shading.replaceStreamData(shading_data, QPDFObjectHandle::newName("/FlateDecode"),
                            QPDFObjectHandle::newNull());

  // Source pixels (y down) -> page points (y up).
  const double s = result.page_width_pt / double(image.width);
  std::string content;
  if (options.background == PdfBackground::kWhite) {
    content += "q 1 1 1 rg 0 0 " + Number(result.page_width_pt) + " " +
               Number(result.page_height_pt) + " re f Q\n";
  }
  content += "q\n" + Number(s, 9) + " 0 0 " + Number(-s, 9) + " 0 " +
             Number(result.page_height_pt, 6) + " cm\n";
  content += clip_path + "W* n\n/Sh0 sh\nQ\n";

  QPDFObjectHandle resources = QPDFObjectHandle::newDictionary();
  QPDFObjectHandle shadings = QPDFObjectHandle::newDictionary();
  shadings.replaceKey("/Sh0", shading);
  resources.replaceKey("/Shading", shadings);

  QPDFObjectHandle page = pdf.makeIndirectObject(QPDFObjectHandle::newDictionary());
  page.replaceKey("/Type", QPDFObjectHandle::newName("/Page"));
  page.replaceKey("/MediaBox",
                  RealArray({0, 0, result.page_width_pt, result.page_height_pt}, 4));
  page.replaceKey("/Resources", resources);
  page.replaceKey("/Contents", pdf.newStream(content));
  QPDFPageDocumentHelper(pdf).addPage(page, /*first=*/false);

  QPDFObjectHandle info = pdf.makeIndirectObject(QPDFObjectHandle::newDictionary());
  info.replaceKey("/Producer", QPDFObjectHandle::newUnicodeString(std::string("sdvi ") + SDVI_VERSION));
  const std::string title = MetadataValue(image, "title");
  if (!title.empty()) info.replaceKey("/Title", QPDFObjectHandle::newUnicodeString(title));
  info.replaceKey("/Subject", QPDFObjectHandle::newUnicodeString(
                                  "sdvi limit surface at level " + std::to_string(result.levels) +
                                  " of a " + std::to_string(image.width) + " x " +
                                  std::to_string(image.height) + " pixel image"));
  info.replaceKey("/SdviSourceWidth", QPDFObjectHandle::newInteger(image.width));
  info.replaceKey("/SdviSourceHeight", QPDFObjectHandle::newInteger(image.height));
  info.replaceKey("/SdviLevels", QPDFObjectHandle::newInteger(result.levels));
  pdf.getTrailer().replaceKey("/Info", info);

  QPDFWriter writer(pdf);
  writer.setOutputMemory();
  writer.setDeterministicID(true);
  writer.setCompressStreams(true);           // the content stream
  writer.setDecodeLevel(qpdf_dl_none);       // keep our Flate data as it is
  writer.setObjectStreamMode(qpdf_o_generate);
  writer.setMinimumPDFVersion("1.5");        // object streams
  writer.write();
  std::shared_ptr<Buffer> buffer = writer.getBufferSharedPointer();
  const uint8_t* begin = buffer->getBuffer();
  return std::vector<uint8_t>(begin, begin + buffer->getSize());
}

StatusOr<PdfExport> EncodePdfOrThrow(const Image& image, const PdfExportOptions& options) {
  SDVI_RETURN_IF_ERROR(CheckOptions(options));
  SDVI_RETURN_IF_ERROR(CheckImage(image));
  PdfExport result;
  result.levels = options.levels >= 0 ? options.levels : DefaultExportLevels(image);
  const uint64_t fine_triangles = uint64_t(image.triangles.size()) << (2 * result.levels);
  if (fine_triangles > kMaxPdfFineTriangles) {
    return Status(StatusCode::kLimitExceeded,
                  "PDF export: level " + std::to_string(result.levels) + " gives " +
                      std::to_string(fine_triangles) + " triangles, over the limit of " +
                      std::to_string(kMaxPdfFineTriangles));
  }
  result.page_width_pt = options.width_mm > 0 ? options.width_mm / 25.4 * 72
                                              : image.width * 72.0 / options.dpi;
  result.page_height_pt = result.page_width_pt * image.height / image.width;
  if (std::max(result.page_width_pt, result.page_height_pt) > kMaxPdfPageSide ||
      std::min(result.page_width_pt, result.page_height_pt) < 1) {
    return Status(StatusCode::kLimitExceeded,
                  "PDF export: the page would be " + Number(result.page_width_pt, 1) + " x " +
                      Number(result.page_height_pt, 1) + " pt; each side must lie in 1.." +
                      Number(kMaxPdfPageSide) + " pt (choose another --dpi or --width-mm)");
  }

  if (options.progress) options.progress->Phase("limit surface (level " + std::to_string(result.levels) + ")");
  LimitSurfaceOptions surface_options;
  surface_options.levels = result.levels;
  surface_options.to_limit = true;
  SDVI_ASSIGN_OR_RETURN(LimitSurface surface, BuildLimitSurface(image, surface_options));
  const std::vector<Vertex> fine = EvaluateSurface(surface, image.vertices);
  for (const Triangle& t : surface.triangles) {
    for (uint32_t v : t.v) {
      if (v >= fine.size()) {
        return Status(StatusCode::kInternal, "PDF export: a fine triangle refers to vertex " +
                                                 std::to_string(v) + " of " +
                                                 std::to_string(fine.size()));
      }
    }
  }
  result.vertices = uint32_t(fine.size());
  result.triangles = uint32_t(surface.triangles.size());

  // Fine vertices, then the two guard vertices.
  const std::array<float, 4> box = BoundingBox(fine);
  std::vector<Vertex> points = fine;
  for (const Vertex& g : GuardVertices(fine, box)) points.push_back(g);
  result.decode = DecodeRange(points);
  result.bits_per_component = options.color_bits;
  result.bits_per_coordinate =
      options.coordinate_bits > 0
          ? options.coordinate_bits
          : CoordinateBitsFor(std::max(result.decode[1] - result.decode[0],
                                       result.decode[3] - result.decode[2]));
  result.bits_per_flag = FlagBitsFor(result.bits_per_coordinate, result.bits_per_component);
  // Decode bounds are written with 9 decimals: quantise against exactly those values.
  for (double& d : result.decode) d = std::stod(Number(d, 9));
  std::vector<QuantisedVertex> quantised;
  quantised.reserve(points.size());
  for (const Vertex& v : points) {
    quantised.push_back(QuantiseVertex(v, result.decode, box, result.bits_per_coordinate,
                                       result.bits_per_component));
  }

  std::vector<ShadingRecord> records;
  for (uint32_t guard : {result.vertices, result.vertices + 1}) {
    records.insert(records.end(), 3, ShadingRecord{0, guard});
  }
  // Paint order: the steep triangles, then the others, each class as strips.
  std::vector<Triangle> steep, flat;
  for (const Triangle& t : surface.triangles) {
    const bool is_steep = ColorGradient(fine[t.v[0]], fine[t.v[1]], fine[t.v[2]]) > kSteepColorGradient;
    (is_steep ? steep : flat).push_back(t);
  }
  result.steep_triangles = uint32_t(steep.size());
  for (const std::vector<Triangle>* part : {&steep, &flat}) {
    for (const ShadingRecord& r : TriangleStrips(*part)) records.push_back(r);
  }
  result.records = uint32_t(records.size());
  result.strips = 0;
  for (size_t i = 0; i < records.size(); ++i) {
    if (records[i].flag == 0) {
      ++result.strips;
      i += 2;
    }
  }
  if (options.progress) options.progress->Phase("shading stream");
  const std::string raw = PackRecords(records, quantised, result.bits_per_flag,
                                      result.bits_per_coordinate, result.bits_per_component);
  result.shading_raw_bytes = raw.size();
  SDVI_ASSIGN_OR_RETURN(std::string compressed, Deflate(raw));
  result.shading_bytes = compressed.size();

  const std::string clip = ClipPath(BoundaryLoops(surface.triangles, quantised), quantised);
  SDVI_ASSIGN_OR_RETURN(result.bytes, BuildDocument(image, result, options, compressed, clip));
  if (options.progress) options.progress->Done();
  return result;
}

}  // namespace

StatusOr<PdfExport> EncodePdf(const Image& image, const PdfExportOptions& options) {
  // qpdf reports errors by exceptions; allocations may fail.
  try {
    return EncodePdfOrThrow(image, options);
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::kLimitExceeded, "PDF export: out of memory");
  } catch (const std::exception& e) {
    return Status(StatusCode::kEncodeFailed, std::string("PDF export: ") + e.what());
  }
}

StatusOr<PdfExport> WritePdf(const std::string& path, const Image& image,
                             const PdfExportOptions& options) {
  SDVI_ASSIGN_OR_RETURN(PdfExport result, EncodePdf(image, options));
  SDVI_RETURN_IF_ERROR(WriteFileAtomic(path, result.bytes));
  return result;
}

}  // namespace sdvi
