// SPDX-License-Identifier: GPL-3.0-or-later
// ICC -> sRGB through Little CMS 2 (icc_profile.h).
#include "icc_profile.h"

#include <lcms2.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace sdvi {
namespace {

struct ProfileCloser {
  void operator()(void* p) const { cmsCloseProfile(p); }
};
struct TransformDeleter {
  void operator()(void* t) const { cmsDeleteTransform(t); }
};
struct CurveDeleter {
  void operator()(cmsToneCurve* c) const { cmsFreeToneCurve(c); }
};
using Profile = std::unique_ptr<void, ProfileCloser>;

std::string Description(cmsHPROFILE profile) {
  const cmsUInt32Number n = cmsGetProfileInfoASCII(profile, cmsInfoDescription, "en", "US", nullptr, 0);
  if (n <= 1) return {};
  std::string text(n, '\0');
  cmsGetProfileInfoASCII(profile, cmsInfoDescription, "en", "US", text.data(), n);
  text.resize(text.find('\0') == std::string::npos ? text.size() : text.find('\0'));
  return text;
}

// A grey profile with sRGB's tone curve (IEC 61966-2-1: parametric curve type 4).
Profile SrgbGreyProfile() {
  const cmsFloat64Number params[5] = {2.4, 1 / 1.055, 0.055 / 1.055, 1 / 12.92, 0.04045};
  std::unique_ptr<cmsToneCurve, CurveDeleter> curve(cmsBuildParametricToneCurve(nullptr, 4, params));
  if (!curve) return nullptr;
  return Profile(cmsCreateGrayProfile(cmsD50_xyY(), curve.get()));
}

}  // namespace

StatusOr<IccConversion> ConvertIccToSrgb(const std::vector<uint8_t>& icc, Raster& raster) {
  Profile in(cmsOpenProfileFromMem(icc.data(), cmsUInt32Number(icc.size())));
  if (!in) return Status(StatusCode::kDecodeFailed, "the embedded ICC profile cannot be parsed");
  IccConversion result;
  result.description = Description(in.get());
  const int colours = raster.channels >= 3 ? 3 : 1;
  const cmsColorSpaceSignature space = cmsGetColorSpace(in.get());
  const cmsColorSpaceSignature expected = colours == 3 ? cmsSigRgbData : cmsSigGrayData;
  if (space != expected)
    return Status(StatusCode::kUnsupportedFormat,
                  "the embedded ICC profile '" + result.description + "' is not a " +
                      (colours == 3 ? "RGB" : "grey") + " profile and the image is " +
                      (colours == 3 ? "RGB" : "grey"));
  Profile out = colours == 3 ? Profile(cmsCreate_sRGBProfile()) : SrgbGreyProfile();
  // 16-bit samples: exact for 8- and 16-bit files (v * 257), and the transform Little CMS
  // optimises (a float transform of a 12-megapixel photo takes seconds).
  const cmsUInt32Number type = colours == 3 ? TYPE_RGB_16 : TYPE_GRAY_16;
  std::unique_ptr<void, TransformDeleter> transform(cmsCreateTransform(
      in.get(), type, out.get(), type, cmsGetHeaderRenderingIntent(in.get()), cmsFLAGS_NOCACHE | cmsFLAGS_HIGHRESPRECALC));
  if (!out || !transform)
    return Status(StatusCode::kDecodeFailed,
                  "Little CMS cannot build a transform from the ICC profile '" + result.description + "' to sRGB");
  // Colour samples only, 0..65535, one row at a time (alpha stays where it is).
  std::vector<uint16_t> row(size_t(raster.width) * colours);
  for (int y = 0; y < raster.height; ++y) {
    for (int x = 0; x < raster.width; ++x)
      for (int c = 0; c < colours; ++c)
        row[size_t(x) * colours + c] = uint16_t(std::lround(std::clamp(raster.at(x, y, c), 0.0f, 255.0f) * 257.0f));
    cmsDoTransform(transform.get(), row.data(), row.data(), cmsUInt32Number(raster.width));
    for (int x = 0; x < raster.width; ++x)
      for (int c = 0; c < colours; ++c) raster.at(x, y, c) = float(row[size_t(x) * colours + c] * (255.0 / 65535.0));
  }
  result.converted = true;
  return result;
}

}  // namespace sdvi
