// SPDX-License-Identifier: GPL-3.0-or-later
// Colours in the tag stream (payload 1.5, spec/FORMAT.md 8.8): the neighbour-mean colours' grid
// indices, each predicted by the mean of the earlier neighbours, coded after the positions with
// adaptive models; the Draco mesh holds the connectivity alone. The smallest colour coding tries
// them and keeps them where the payload is smaller; they decode to exactly the colours of the
// Draco-coded neighbour-mean colours; a stream built by hand from the spec decodes to the values
// the spec gives; the header rules; damaged bytes are errors, never crashes. A grey image's one
// component coded the same way (payload 1.6, 8.9): the same checks.
#include <catch2/catch.hpp>

#include <array>
#include <bit>
#include <cmath>
#include <cstring>

#include "range_coder.h"
#include "sdvi/codec.h"
#include "synthetic_mesh.h"
#include "tag_stream.h"

using sdvi::ColorCoding;
using sdvi::CompressOptions;
using sdvi::Image;
using sdvi::StatusCode;
using sdvi::codec_internal::BitModel;
using sdvi::codec_internal::RangeEncoder;
using sdvi::testing::MustDecode;
using sdvi::testing::MustEncode;
using sdvi::testing::SameBits;

namespace {

// The image a payload decodes to, in the numbering of the image it was made from (new_index:
// EncodeDracoPayload's), triangles canonical.
Image InOriginalNumbering(const std::vector<uint8_t>& payload, const std::vector<uint32_t>& new_index) {
  Image decoded = MustDecode(payload);
  std::vector<uint32_t> old_index(new_index.size());
  for (uint32_t i = 0; i < new_index.size(); ++i) old_index[new_index[i]] = i;
  REQUIRE(sdvi::RenumberVertices(old_index, &decoded).ok());
  sdvi::CanonicalizeTriangles(&decoded.triangles);
  return decoded;
}

uint32_t GetU32(const std::vector<uint8_t>& p, size_t at) {
  return uint32_t(p[at]) | uint32_t(p[at + 1]) << 8 | uint32_t(p[at + 2]) << 16 | uint32_t(p[at + 3]) << 24;
}
void PutU32(std::vector<uint8_t>* p, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) (*p)[at + i] = static_cast<uint8_t>(v >> (8 * i));
}

// spec/FORMAT.md 8.7 step 3 and 8.8 step 3, written from the spec: the mean of the earlier
// neighbours' indices rounded half up, else the previous vertex's.
int64_t SpecPrediction(const std::vector<std::vector<uint32_t>>& earlier, const std::vector<int64_t>& q, size_t v) {
  if (earlier[v].empty()) return v > 0 ? q[v - 1] : 0;
  int64_t sum = 0;
  for (uint32_t j : earlier[v]) sum += q[j];
  const int64_t c = static_cast<int64_t>(earlier[v].size());
  return static_cast<int64_t>(std::floor(double(2 * sum + c) / double(2 * c)));
}

// One component's models of 8.7 step 2 / 8.8 step 2.
struct SpecModels {
  BitModel zero, sign;
  std::array<BitModel, 32> length{}, top{};
};

// A residual binarised as spec/FORMAT.md 8.7 step 3 says; force_lengths: that many 1 length
// bits and nothing else (a residual that does not end).
void SpecResidual(RangeEncoder& rc, SpecModels& m, int64_t r, int force_lengths = 0) {
  if (force_lengths) {
    rc.Encode(m.zero, false);
    rc.Encode(m.sign, false);
    for (int j = 0; j < force_lengths; ++j) rc.Encode(m.length[j], true);
    return;
  }
  rc.Encode(m.zero, r == 0);
  if (r == 0) return;
  rc.Encode(m.sign, r < 0);
  const uint64_t a = static_cast<uint64_t>(r < 0 ? -r : r);
  int e = 0;
  while ((a >> (e + 1)) != 0) ++e;
  for (int j = 0; j < e; ++j) rc.Encode(m.length[j], true);
  rc.Encode(m.length[e], false);
  if (e >= 1) rc.Encode(m.top[e], (a >> (e - 1)) & 1);
  if (e >= 2) rc.EncodeDirect(static_cast<uint32_t>(a & ((uint64_t{1} << (e - 1)) - 1)), e - 1);
}

// What a hand-built stream codes and the payload it makes.
struct HandBuilt {
  std::vector<uint8_t> payload;
  std::vector<sdvi::Vertex> expected;  // the decoded vertices the spec gives
};

enum class Damage { kNone, kZeroStep, kNanOrigin, kEndlessResidual };

// A payload 1.5 (grey: 1.6) for the connectivity of `writer_payload` (a 1.5 or 1.6 payload of a
// mesh without crease edges, corners or feature layer): its header and Draco mesh, and a tag
// stream written here from spec/FORMAT.md 8.7, 8.8 (grey: 8.9) and 8.5 steps 1-2, with chosen
// grids and indices.
HandBuilt BuildByHand(const std::vector<uint8_t>& writer_payload, Damage damage = Damage::kNone,
                      bool grey = false) {
  const Image mesh = MustDecode(writer_payload);
  const size_t n = mesh.vertices.size();
  // Earlier neighbours and the edges (a < b, sorted) with their triangle counts.
  std::vector<std::pair<std::pair<uint32_t, uint32_t>, int>> edges;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = std::min(t.v[k], t.v[(k + 1) % 3]), b = std::max(t.v[k], t.v[(k + 1) % 3]);
      auto it = std::find_if(edges.begin(), edges.end(), [&](const auto& e) { return e.first == std::pair{a, b}; });
      if (it == edges.end()) edges.push_back({{a, b}, 1});
      else ++it->second;
    }
  std::sort(edges.begin(), edges.end());
  std::vector<std::vector<uint32_t>> earlier(n);
  for (const auto& e : edges) earlier[e.first.second].push_back(e.first.first);

  HandBuilt out;
  out.expected.resize(n);
  RangeEncoder rc;
  // 8.7: a grid of 6 bits (M = 63) over [-1.5, -1.5 + 70]; indices 0..63 chosen per vertex.
  const int bits = 6;
  const float min_x = -1.5f, min_y = 2.25f, range = 70.f;
  rc.EncodeDirect(std::bit_cast<uint32_t>(min_x), 32);
  rc.EncodeDirect(std::bit_cast<uint32_t>(min_y), 32);
  rc.EncodeDirect(std::bit_cast<uint32_t>(range), 32);
  std::vector<int64_t> qx(n), qy(n);
  SpecModels mx, my;
  const float d = range / 63.f;
  for (size_t v = 0; v < n; ++v) {
    qx[v] = (7 * int64_t(v) + 3) % 64;
    qy[v] = (v * v + 11) % 64;
    SpecResidual(rc, mx, qx[v] - SpecPrediction(earlier, qx, v));
    SpecResidual(rc, my, qy[v] - SpecPrediction(earlier, qy, v));
    out.expected[v].x = float(float(qx[v]) * d) + min_x;
    out.expected[v].y = float(float(qy[v]) * d) + min_y;
  }
  // 8.8: step 0.375 (1/2.666...), origins; per vertex L, C1, C2 indices, one of them large (a
  // residual of 2^20 and more: the top-bit model and 19 direct bits). 8.9 (grey): the same
  // step, the first origin and the first component only.
  const double step = damage == Damage::kZeroStep ? 0.0 : 0.375;
  const float origin[3] = {damage == Damage::kNanOrigin ? std::nanf("") : 12.5f, -40.f, -7.25f};
  const int components = grey ? 1 : 3;
  const uint64_t step_bits = std::bit_cast<uint64_t>(step);
  rc.EncodeDirect(static_cast<uint32_t>(step_bits >> 32), 32);
  rc.EncodeDirect(static_cast<uint32_t>(step_bits), 32);
  for (int k = 0; k < components; ++k) rc.EncodeDirect(std::bit_cast<uint32_t>(origin[k]), 32);
  std::array<std::vector<int64_t>, 3> q;
  for (auto& c : q) c.assign(n, 0);
  std::array<SpecModels, 3> mc;
  for (size_t v = 0; v < n; ++v) {
    q[0][v] = 300 + 13 * int64_t(v) - (v == 4 ? (int64_t{1} << 21) + 12345 : 0);
    q[1][v] = int64_t(v % 3) - 1;
    q[2][v] = -2 * int64_t(v);
    for (int k = 0; k < components; ++k) {
      const int64_t r = q[k][v] - SpecPrediction(earlier, q[k], v);
      SpecResidual(rc, mc[k], r, damage == Damage::kEndlessResidual && v == 2 && k == components / 2 ? 32 : 0);
    }
    if (grey) {  // 8.9 step 4
      out.expected[v].r = out.expected[v].g = out.expected[v].b =
          static_cast<float>(double(origin[0]) + double(q[0][v]) * step);
      continue;
    }
    // 8.8 step 4 and the inverse transform of 8.2, as the spec gives them.
    float lcc[3];
    for (int k = 0; k < 3; ++k) lcc[k] = static_cast<float>(double(origin[k]) + double(q[k][v]) * step);
    const double y = lcc[0] * (1 / std::sqrt(3.0)), u = lcc[1] * (1 / std::sqrt(2.0)), w = lcc[2] * (1 / std::sqrt(6.0));
    out.expected[v].r = static_cast<float>((y + u) + w);
    out.expected[v].g = static_cast<float>(y - 2 * w);
    out.expected[v].b = static_cast<float>((y - u) + w);
  }
  // 8.5 step 1: no crease edge, so every degree stays 0 and the model is 9 * boundary; step 2:
  // no corner, model 0.
  std::array<BitModel, 18> edge_models{};
  for (const auto& e : edges) rc.Encode(edge_models[e.second == 1 ? 9 : 0], false);
  BitModel corner_model;
  for (size_t v = 0; v < n; ++v) rc.Encode(corner_model, false);
  const std::vector<uint8_t> tags = rc.Finish();

  const uint32_t draco_size = GetU32(writer_payload, 28);
  out.payload.assign(writer_payload.begin(), writer_payload.begin() + 40 + draco_size);
  out.payload.insert(out.payload.end(), tags.begin(), tags.end());
  out.payload[6] = grey ? 4 : 8 | 128;  // grey, or decorrelated and neighbour mean; no feature layer
  out.payload[7] = bits;
  out.payload[10] = 3;  // positions and colours in the tag stream
  PutU32(&out.payload, 20, 0);
  PutU32(&out.payload, 24, 0);
  PutU32(&out.payload, 32, static_cast<uint32_t>(tags.size()));
  sdvi::testing::FixPayloadChecksum(&out.payload);
  return out;
}

// A small image whose smallest payload is 1.5 (grey: 1.6), without crease edges, corners or
// feature layer.
std::vector<uint8_t> WriterPayloadWithoutTags(bool grey = false) {
  Image image = sdvi::testing::PhotoLikeGridImage(21, 8);
  if (grey)
    for (auto& v : image.vertices) v.g = v.b = v.r;
  image.crease_edges.clear();
  image.corners.clear();
  image.polylines.clear();
  image.pairs.clear();
  CompressOptions options;
  options.color_coding = ColorCoding::kSmallest;
  options.feature_layer = false;
  options.position_bits = 10;
  return MustEncode(image, options);
}

// The rules shared by the colour streams (header byte 10 bit 1, spec/FORMAT.md 8.8 and 8.9),
// on `good`, a payload with its colour in the tag stream, and `in_draco`, the same image with
// the colour in the Draco mesh (bit 1 clear): the bit set on `in_draco` (its Draco mesh has a
// COLOR attribute) or cleared on `good` (its Draco mesh has none), or the tag stream cut short,
// are corrupt; damaged bytes behind a valid checksum are errors or images, never a crash, and
// many are errors.
void CheckColorFlagCutAndDamage(const std::vector<uint8_t>& good, std::vector<uint8_t> in_draco,
                                const char* name) {
  Image out;
  REQUIRE(in_draco[10] == 1);
  in_draco[5] = good[5];
  in_draco[10] = 3;
  sdvi::testing::FixPayloadChecksum(&in_draco);
  CHECK(sdvi::DecodeDracoPayload(in_draco, name, &out).code() == StatusCode::kCorrupt);
  std::vector<uint8_t> bad = good;
  bad[10] = 1;
  sdvi::testing::FixPayloadChecksum(&bad);
  CHECK(sdvi::DecodeDracoPayload(bad, name, &out).code() == StatusCode::kCorrupt);
  bad = good;
  const uint32_t tags = GetU32(bad, 32);
  bad.resize(bad.size() - tags / 2);
  PutU32(&bad, 32, tags - tags / 2);
  sdvi::testing::FixPayloadChecksum(&bad);
  CHECK(sdvi::DecodeDracoPayload(bad, name, &out).code() == StatusCode::kCorrupt);
  int tried = 0;
  const int errors = sdvi::testing::DamagedPayloadErrors(good, 5, 3, &tried);
  CHECK(errors > tried / 4);
}

}  // namespace

TEST_CASE("colours in the tag stream: smaller, and exactly the colours of neighbour-mean colours in Draco",
          "[codec][colors][color_stream]") {
  const Image image = sdvi::testing::PhotoLikeGridImage(5);
  for (int color_bits : {6, 8}) {
    INFO("colour bits " << color_bits);
    CompressOptions options;
    options.position_bits = 12;
    options.color_bits = color_bits;
    options.color_coding = ColorCoding::kSmallest;
    std::vector<uint32_t> streamed_index, in_draco_index;
    const std::vector<uint8_t> streamed = MustEncode(image, options, &streamed_index);
    options.stream_colors = false;
    const std::vector<uint8_t> in_draco = MustEncode(image, options, &in_draco_index);
    options.stream_colors = true;
    REQUIRE(streamed.size() > 40);
    CHECK(streamed[5] == 5);                      // payload 1.5
    CHECK(streamed[10] == 3);                     // positions and colours in the tag stream
    CHECK((streamed[6] & (128 | 8 | 1)) == (128 | 8));  // neighbour mean, decorrelated, no ids
    // The same image without it: positions in the tag stream, neighbour-mean colours in Draco.
    REQUIRE(in_draco[5] == 4);
    REQUIRE(in_draco[10] == 1);
    REQUIRE((in_draco[6] & 128) != 0);
    CHECK(streamed.size() < in_draco.size());
    CHECK(MustEncode(image, options) == streamed);  // deterministic
    auto info = sdvi::InspectDracoPayload(streamed, "streamed");
    REQUIRE(info.ok());
    CHECK(info->stream_colors);
    CHECK(info->stream_positions);
    CHECK(info->neighbour_mean);
    // The same grids and indices: the same vertices bit for bit, the same tags and feature
    // layer; the vertex order is that of a Draco mesh with one attribute (FORMAT.md 8.8), so
    // the two are compared in the image's own numbering.
    CHECK(SameBits(InOriginalNumbering(in_draco, in_draco_index), InOriginalNumbering(streamed, streamed_index)));
    // The parts: the colours' bytes are in the tag stream now, the Draco mesh is connectivity.
    auto parts = sdvi::codec_internal::MeasureDracoParts(streamed, "streamed");
    REQUIRE(parts.ok());
    CHECK(parts->colors > 100);
    CHECK(parts->connectivity + parts->positions + parts->colors + parts->tags + parts->feature_layer ==
          GetU32(streamed, 28) + GetU32(streamed, 32));
  }
  // Through the container: what a reader of the file gets is the same image.
  CompressOptions options;
  options.position_bits = 12;
  options.color_coding = ColorCoding::kSmallest;
  CHECK(sdvi::testing::MustReadBack(image, options).vertices.size() == image.vertices.size());
}

TEST_CASE("colours in the tag stream are not taken without their options",
          "[codec][colors][color_stream]") {
  const Image image = sdvi::testing::PhotoLikeGridImage(6);
  CompressOptions options;
  options.position_bits = 12;
  options.color_coding = ColorCoding::kSmallest;
  options.neighbour_mean = false;
  CHECK(MustEncode(image, options)[5] < 5);
  options.neighbour_mean = true;
  options.stream_positions = false;  // the colours follow the positions only
  CHECK(MustEncode(image, options)[5] < 4);
  options.stream_positions = true;
  options.color_coding = ColorCoding::kDecorrelated;
  CHECK(MustEncode(image, options)[5] < 4);
  options.color_coding = ColorCoding::kSmallest;
  // A grey image: its one component (payload 1.6) only with stream_grey_colors and stream_colors.
  Image grey = image;
  for (auto& v : grey.vertices) v.g = v.b = v.r;
  options.stream_grey_colors = false;
  std::vector<uint8_t> grey_payload = MustEncode(grey, options);
  CHECK((grey_payload[10] & 2) == 0);
  CHECK((grey_payload[6] & 4) != 0);
  CHECK(grey_payload[5] < 5);
  options.stream_grey_colors = true;
  options.stream_colors = false;
  grey_payload = MustEncode(grey, options);
  CHECK((grey_payload[10] & 2) == 0);
  CHECK(grey_payload[5] < 5);
}

TEST_CASE("a colour stream built by hand from the spec decodes to the values it gives",
          "[codec][colors][color_stream]") {
  const std::vector<uint8_t> writer = WriterPayloadWithoutTags();
  INFO("minor " << int(writer[5]) << " flags " << int(writer[6]) << " flags2 " << int(writer[10]));
  REQUIRE(writer[5] == 5);
  REQUIRE(writer[10] == 3);
  const HandBuilt hand = BuildByHand(writer);
  Image decoded;
  const sdvi::Status status = sdvi::DecodeDracoPayload(hand.payload, "hand.sdvi", &decoded);
  INFO(status.ToString());
  REQUIRE(status.ok());
  REQUIRE(decoded.vertices.size() == hand.expected.size());
  for (size_t v = 0; v < hand.expected.size(); ++v) {
    INFO("vertex " << v);
    CHECK(std::bit_cast<uint32_t>(decoded.vertices[v].x) == std::bit_cast<uint32_t>(hand.expected[v].x));
    CHECK(std::bit_cast<uint32_t>(decoded.vertices[v].y) == std::bit_cast<uint32_t>(hand.expected[v].y));
    CHECK(std::bit_cast<uint32_t>(decoded.vertices[v].r) == std::bit_cast<uint32_t>(hand.expected[v].r));
    CHECK(std::bit_cast<uint32_t>(decoded.vertices[v].g) == std::bit_cast<uint32_t>(hand.expected[v].g));
    CHECK(std::bit_cast<uint32_t>(decoded.vertices[v].b) == std::bit_cast<uint32_t>(hand.expected[v].b));
  }
  CHECK(decoded.triangles == MustDecode(writer).triangles);
  CHECK(decoded.crease_edges.empty());
  CHECK(decoded.corners.empty());

  // Refused: a step of 0, an origin that is not finite, a residual that does not end, a stream
  // cut short.
  for (Damage damage : {Damage::kZeroStep, Damage::kNanOrigin, Damage::kEndlessResidual}) {
    const HandBuilt bad = BuildByHand(writer, damage);
    const sdvi::Status refused = sdvi::DecodeDracoPayload(bad.payload, "bad.sdvi", &decoded);
    INFO(refused.ToString());
    CHECK(refused.code() == StatusCode::kCorrupt);
    CHECK(refused.message().find("bad.sdvi") != std::string::npos);
  }
  const HandBuilt grey = BuildByHand(WriterPayloadWithoutTags(true), Damage::kNone, true);
  REQUIRE(grey.payload[5] == 6);
  const sdvi::Status grey_status = sdvi::DecodeDracoPayload(grey.payload, "grey.sdvi", &decoded);
  INFO(grey_status.ToString());
  REQUIRE(grey_status.ok());
  REQUIRE(decoded.vertices.size() == grey.expected.size());
  for (size_t v = 0; v < grey.expected.size(); ++v) {
    INFO("grey vertex " << v);
    CHECK(std::memcmp(&decoded.vertices[v], &grey.expected[v], sizeof(sdvi::Vertex)) == 0);
  }
  for (Damage damage : {Damage::kZeroStep, Damage::kNanOrigin, Damage::kEndlessResidual}) {
    const HandBuilt bad = BuildByHand(WriterPayloadWithoutTags(true), damage, true);
    const sdvi::Status refused = sdvi::DecodeDracoPayload(bad.payload, "bad.sdvi", &decoded);
    INFO("grey: " << refused.ToString());
    CHECK(refused.code() == StatusCode::kCorrupt);
    CHECK(refused.message().find("bad.sdvi") != std::string::npos);
  }
  std::vector<uint8_t> cut = hand.payload;
  const uint32_t tags = GetU32(cut, 32);
  cut.resize(cut.size() - tags / 2);
  PutU32(&cut, 32, tags - tags / 2);
  sdvi::testing::FixPayloadChecksum(&cut);
  CHECK(sdvi::DecodeDracoPayload(cut, "cut.sdvi", &decoded).code() == StatusCode::kCorrupt);
}

TEST_CASE("colours in the tag stream: header rules and damaged bytes", "[codec][colors][color_stream][corrupt]") {
  // 16 x 16 vertices: every third byte of the stream is damaged below, each a whole decode, and
  // the sweep also runs under the sanitizers.
  const Image image = sdvi::testing::PhotoLikeGridImage(7, 16);
  CompressOptions options;
  options.color_coding = ColorCoding::kSmallest;
  options.position_bits = 12;
  const std::vector<uint8_t> good = MustEncode(image, options);
  REQUIRE(good[5] == 5);
  REQUIRE(good[10] == 3);
  // The flag in a 1.4 payload, without the positions' flag, without neighbour-mean colours, with
  // an unknown bit: corrupt.
  sdvi::testing::CheckRefused(good, {{5, 4}, {10, 2}, {6, static_cast<uint8_t>(good[6] & ~128)}, {10, 7}},
                              "colors.sdvi");
  // The flag set on a payload 1.4 whose Draco mesh has the colours, cleared, the stream cut,
  // damaged bytes.
  options.stream_colors = false;
  CheckColorFlagCutAndDamage(good, MustEncode(image, options), "colors.sdvi");
}

TEST_CASE("the golden payload 1.5 file reads (kept forever)", "[codec][colors][color_stream]") {
  // The built-in sample (`sdvi sample`) vectorized by `sdvi vectorize s.png -o s.sdvi --compress
  // --compression-ratio 600`: positions and colours in the tag stream, features first.
  sdvi::testing::CheckGoldenFile("golden_draco_v1_5");
}

TEST_CASE("a grey image's colour in the tag stream (payload 1.6): smaller, R = G = B on the grey grid",
          "[codec][colors][color_stream][grey]") {
  Image grey = sdvi::testing::PhotoLikeGridImage(5);
  for (auto& v : grey.vertices) v.g = v.b = v.r;
  float lo = grey.vertices[0].r, hi = lo;
  for (const auto& v : grey.vertices) lo = std::min(lo, v.r), hi = std::max(hi, v.r);
  for (int color_bits : {6, 8}) {
    INFO("colour bits " << color_bits);
    CompressOptions options;
    options.position_bits = 12;
    options.color_bits = color_bits;
    options.color_coding = ColorCoding::kSmallest;
    std::vector<uint32_t> streamed_index, in_draco_index;
    const std::vector<uint8_t> streamed = MustEncode(grey, options, &streamed_index);
    options.stream_grey_colors = false;
    const std::vector<uint8_t> in_draco = MustEncode(grey, options, &in_draco_index);
    options.stream_grey_colors = true;
    REQUIRE(streamed.size() > 40);
    CHECK(streamed[5] == 6);                         // payload 1.6
    CHECK(streamed[10] == 3);                        // positions and the grey value in the tag stream
    CHECK((streamed[6] & (128 | 8 | 4 | 1)) == 4);  // grey; not decorrelated, no ids
    // Without it: positions in the tag stream, the grey COLOR in Draco.
    REQUIRE(in_draco[5] == 4);
    REQUIRE(in_draco[10] == 1);
    REQUIRE((in_draco[6] & 4) != 0);
    CHECK(streamed.size() < in_draco.size());
    CHECK(MustEncode(grey, options) == streamed);  // deterministic
    auto info = sdvi::InspectDracoPayload(streamed, "grey");
    REQUIRE(info.ok());
    CHECK(info->grey);
    CHECK(info->stream_colors);
    CHECK(info->stream_positions);
    CHECK_FALSE(info->neighbour_mean);
    // The same positions and tags bit for bit; R = G = B within half a grey step of the image's.
    const Image a = InOriginalNumbering(in_draco, in_draco_index);
    const Image b = InOriginalNumbering(streamed, streamed_index);
    REQUIRE(a.vertices.size() == b.vertices.size());
    CHECK(a.triangles == b.triangles);
    CHECK(a.crease_edges == b.crease_edges);
    CHECK(a.corners == b.corners);
    CHECK(a.polylines == b.polylines);
    CHECK(a.pairs == b.pairs);
    const double step = (double(hi) - double(lo)) / double((1 << color_bits) - 1);
    for (size_t i = 0; i < b.vertices.size(); ++i) {
      INFO("vertex " << i);
      CHECK(std::bit_cast<uint32_t>(a.vertices[i].x) == std::bit_cast<uint32_t>(b.vertices[i].x));
      CHECK(std::bit_cast<uint32_t>(a.vertices[i].y) == std::bit_cast<uint32_t>(b.vertices[i].y));
      CHECK(b.vertices[i].r == b.vertices[i].g);
      CHECK(b.vertices[i].r == b.vertices[i].b);
      CHECK(std::abs(double(b.vertices[i].r) - double(grey.vertices[i].r)) <= 0.5 * step * (1 + 1e-5));
    }
    auto parts = sdvi::codec_internal::MeasureDracoParts(streamed, "grey");
    REQUIRE(parts.ok());
    CHECK(parts->colors > 50);
    CHECK(parts->connectivity + parts->positions + parts->colors + parts->tags + parts->feature_layer ==
          GetU32(streamed, 28) + GetU32(streamed, 32));
  }
}

TEST_CASE("a grey image's colour in the tag stream: header rules and damaged bytes",
          "[codec][colors][color_stream][grey][corrupt]") {
  // 16 x 16 vertices, as for the colours above: the sweep also runs under the sanitizers.
  Image grey = sdvi::testing::PhotoLikeGridImage(7, 16);
  for (auto& v : grey.vertices) v.g = v.b = v.r;
  CompressOptions options;
  options.color_coding = ColorCoding::kSmallest;
  options.position_bits = 12;
  const std::vector<uint8_t> good = MustEncode(grey, options);
  REQUIRE(good[5] == 6);
  REQUIRE(good[10] == 3);
  // In a 1.5 payload, without the positions' flag, without the grey flag (no colour coding
  // left), with decorrelated colours too: corrupt.
  sdvi::testing::CheckRefused(
      good, {{5, 5}, {10, 2}, {6, static_cast<uint8_t>(good[6] & ~4)}, {6, static_cast<uint8_t>(good[6] | 8)}},
      "grey.sdvi");
  // The flag set on a payload whose Draco mesh has the grey COLOR, cleared, the stream cut,
  // damaged bytes.
  options.stream_grey_colors = false;
  CheckColorFlagCutAndDamage(good, MustEncode(grey, options), "grey.sdvi");
}

TEST_CASE("the golden payload 1.6 file reads (kept forever)", "[codec][colors][color_stream][grey]") {
  // The built-in sample's red channel as a grey PNG, vectorized by `sdvi vectorize g.png -o
  // g.sdvi --compress --compression-ratio 600`: positions and the grey value in the tag stream.
  sdvi::testing::CheckGoldenFile("golden_draco_v1_6");
}
