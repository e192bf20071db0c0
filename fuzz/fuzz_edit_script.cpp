// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target over the edit script (spec/EDIT.md): ParseEditScript, and every script
// that parses applied by ApplyEdits to a small control mesh with one feature pair, with and
// without the fold repair. Besides "never crash", a failure must carry a message, and an
// edit that succeeds must leave an image the format accepts (ValidateImage).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>
#include <vector>

#include "sdvi/edit.h"
#include "sdvi/edit_script.h"
#include "sdvi/features.h"
#include "sdvi/format.h"

namespace {

// 64 x 48 px: a vertical feature pair at x = 32 (sharpness 0.5), grid samples every 8 px,
// dark left of the pair and light right of it.
sdvi::Image StartImage() {
  sdvi::FeatureCurve curve;
  for (int k = 0; k <= 6; ++k) curve.points.push_back({32.0, 2.0 + 44.0 * k / 6});
  curve.sharpness = 0.5f;
  std::vector<sdvi::Point2> samples;
  for (int y = 4; y < 48; y += 8)
    for (int x = 4; x < 64; x += 8) samples.push_back({x + 0.25, y + 0.1});
  auto image = sdvi::BuildControlMesh(64, 48, {curve}, samples, sdvi::ControlMeshOptions{});
  if (!image.ok()) std::abort();
  for (sdvi::Vertex& v : image->vertices) v.r = v.g = v.b = v.x < 32 ? 40.f : 200.f;
  return *image;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const sdvi::Image start = StartImage();
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto steps = sdvi::ParseEditScript(text, "fuzz.json");
  if (!steps.ok()) {
    if (steps.status().message().empty()) std::abort();
    return 0;
  }
  for (bool repair : {false, true}) {
    sdvi::EditOptions options;
    options.repair_folds = repair;
    auto edited = sdvi::ApplyEdits(start, *steps, options);
    if (!edited.ok()) {
      if (edited.status().message().empty()) std::abort();
      continue;
    }
    const sdvi::Status valid = sdvi::ValidateImage(*edited, "edited");
    if (!valid.ok()) {
      std::fprintf(stderr, "ApplyEdits (repair_folds %d) gave an invalid image: %s\n", int(repair),
                   valid.ToString().c_str());
      std::abort();
    }
  }
  return 0;
}
