// SPDX-License-Identifier: GPL-3.0-or-later
// Synthetic control meshes for the codec tests and benchmark: a jittered grid over a
// width x height image, a feature polyline pair across it, tagged boundary and corners.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "sdvi/codec.h"
#include "sdvi/image.h"

namespace sdvi::testing {

// cols x rows grid vertices over [0,width] x [0,height], interior positions jittered
// (deterministic, seeded), colours a smooth gradient with a jump across the middle row;
// boundary edges and the middle row's edges tagged crease; the four image corners and
// the polyline's two ends tagged corner; the middle row recorded as a feature polyline.
// Vertices are numbered in a scrambled (but deterministic) order when shuffle is set.
Image SyntheticGridImage(uint32_t width, uint32_t height, uint32_t cols, uint32_t rows,
                         uint32_t seed = 1, bool shuffle = false);

// The 256 x 256 synthetic grid of cols x cols vertices with colours like a fitted photo's: a
// smooth luminance over the image with random detail per vertex and small tints (R, G, B
// correlated), overshooting 0..255.
Image PhotoLikeGridImage(uint32_t seed, uint32_t cols = 30);

// Checks that the golden file NAME.sdvi of the test data reads to exactly the values of
// NAME.json (written by `sdvi convert` when the file was made; kept forever).
void CheckGoldenFile(const std::string& name);

// Rewrites the CRC-32 field of a Draco payload so that damaged bytes behind it reach
// the Draco decoder and the tag stream (for robustness tests).
void FixPayloadChecksum(std::vector<uint8_t>* payload);

// Flips bytes of a good Draco payload one at a time (three patterns each, every draco_step-th
// byte of the Draco mesh and every stream_step-th byte after it, the checksum fixed) and
// decodes each: never a crash. Returns how many of them were refused; *tried counts them.
int DamagedPayloadErrors(const std::vector<uint8_t>& good, size_t draco_step, size_t stream_step, int* tried);

// Sets each (byte, value) of a good Draco payload in turn (the checksum fixed) and checks that
// the decoder refuses every one as kCorrupt with a message naming name.
void CheckRefused(const std::vector<uint8_t>& good, const std::vector<std::pair<size_t, uint8_t>>& byte_values,
                  const std::string& name);

// The Draco payload of image; fails the current test (Catch2 REQUIRE, with the encoder's
// message) when it does not encode.
std::vector<uint8_t> MustEncode(const Image& image, const CompressOptions& options,
                                std::vector<uint32_t>* new_index = nullptr);

// True when a and b hold the same vertices bit for bit and the same triangles, tags and
// feature layer.
bool SameBits(const Image& a, const Image& b);

// The image a Draco payload decodes to; fails the current test (Catch2 REQUIRE, with the
// decoder's message) when it does not decode.
Image MustDecode(const std::vector<uint8_t>& payload);

// The image a reader of the .sdvi file gets: image written with EncodeImage(options) and read
// back with DecodeImage; fails the current test when either step fails.
Image MustReadBack(const Image& image, const CompressOptions& options);

}  // namespace sdvi::testing
