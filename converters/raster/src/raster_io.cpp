// SPDX-License-Identifier: GPL-3.0-or-later
// Raster image files through OpenImageIO (raster_io.h); OpenImageIO errors stop here.
//
// Why OpenImageIO and not OpenCV's imgcodecs (measured by build/bench/raster/bench_raster_io,
// spec/RASTER_INPUT.md): OpenCV 4.6 applies EXIF orientation only when it may also drop
// alpha and 16-bit samples (any flag but IMREAD_UNCHANGED), never exposes an ICC profile,
// reads no GIF, reads EXR only behind an environment switch, and writes no sRGB chunk;
// OpenImageIO does all of these from memory, with the same libpng/libjpeg-turbo decoders
// (identical samples) and comparable decode time.
#include "sdvi/raster_io.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <memory>
#include <mutex>
#include <new>
#include <string>
#include <vector>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include "icc_profile.h"
#include "sdvi/file_util.h"

namespace sdvi {
namespace {

constexpr uint64_t kMaxPixels = uint64_t(1) << 28;  // 16384 x 16384

std::string SizeText(int64_t w, int64_t h) { return std::to_string(w) + "x" + std::to_string(h); }

// sRGB transfer function (IEC 61966-2-1): linear 0..1 -> 0..255.
float LinearToSrgb255(double linear) {
  const double v = linear <= 0.0031308 ? linear * 12.92 : 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
  return float(v * 255.0);
}

bool IsPng(const std::vector<uint8_t>& b) {
  static const uint8_t kSig[8] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
  return b.size() >= 33 && std::equal(kSig, kSig + 8, b.begin()) && b[12] == 'I' && b[13] == 'H' &&
         b[14] == 'D' && b[15] == 'R';
}
uint32_t BigEndian32(const uint8_t* p) {
  return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | p[3];
}

// A PNG's size from its IHDR, before libpng sees the file: empty or over the limit.
Status CheckPngHeader(const std::vector<uint8_t>& bytes, const std::string& name) {
  if (!IsPng(bytes)) return Status::Ok();
  const uint64_t w = BigEndian32(&bytes[16]), h = BigEndian32(&bytes[20]);
  if (w == 0 || h == 0) return Status(StatusCode::kEmptyInput, name + ": PNG header says " + SizeText(w, h));
  if (w * h > kMaxPixels)
    return Status(StatusCode::kLimitExceeded, name + ": " + SizeText(w, h) + " pixels is over the limit of 2^28");
  return Status::Ok();
}

// Which file channels become the raster's: colour (1 or 3) then alpha (or -1).
struct ChannelPick {
  std::vector<int> colour;
  int alpha = -1;
};
StatusOr<ChannelPick> PickChannels(const OIIO::ImageSpec& spec, const std::string& name) {
  auto find = [&](const char* n) {
    for (int c = 0; c < spec.nchannels; ++c)
      if (spec.channelnames.size() > size_t(c) && spec.channelnames[c] == n) return c;
    return -1;
  };
  ChannelPick pick;
  if (spec.nchannels <= 4) {
    // The decoder's alpha channel when it names a valid one (OpenImageIO's GIF reader does
    // not), else the last of 2 or 4.
    const bool named = spec.alpha_channel >= 0 && spec.alpha_channel < spec.nchannels;
    pick.alpha = named ? spec.alpha_channel : (spec.nchannels == 2 || spec.nchannels == 4 ? spec.nchannels - 1 : -1);
    const int colours = spec.nchannels - (pick.alpha >= 0 ? 1 : 0);
    if (colours != 1 && colours != 3)
      return Status(StatusCode::kUnsupportedFormat, name + ": " + std::to_string(spec.nchannels) +
                                                        " channels with " + std::to_string(colours) + " colour channels");
    for (int c = 0; c < spec.nchannels; ++c)
      if (c != pick.alpha) pick.colour.push_back(c);
    return pick;
  }
  // More than four channels (EXR layers, an `error` channel): R, G, B or Y, and A, by name.
  const int r = find("R"), g = find("G"), b = find("B"), y = find("Y");
  if (r >= 0 && g >= 0 && b >= 0)
    pick.colour = {r, g, b};
  else if (y >= 0)
    pick.colour = {y};
  else
    return Status(StatusCode::kUnsupportedFormat,
                  name + ": " + std::to_string(spec.nchannels) + " channels and none named R, G, B or Y");
  pick.alpha = find("A");
  return pick;
}

// Decodes the first subimage of an opened input into the raster's layout and scale.
StatusOr<Raster> ReadPixels(OIIO::ImageInput& in, const std::string& name, RasterSource& source) {
  const OIIO::ImageSpec spec = in.spec();
  SDVI_ASSIGN_OR_RETURN(ChannelPick pick, PickChannels(spec, name));
  const OIIO::TypeDesc type = spec.format;
  source.file_channels = spec.nchannels;
  source.bits = int(type.size() * 8);
  source.linear = type.is_floating_point();
  // Samples as 8-bit, 16-bit or float, whichever holds the file's exactly.
  const OIIO::TypeDesc read_type = type.basetype == OIIO::TypeDesc::UINT8 || type.basetype == OIIO::TypeDesc::INT8
                                       ? OIIO::TypeDesc::UINT8
                                   : source.linear ? OIIO::TypeDesc::FLOAT
                                                   : OIIO::TypeDesc::UINT16;
  const size_t pixels = size_t(spec.width) * spec.height, nch = size_t(spec.nchannels);
  std::vector<uint8_t> buffer(pixels * nch * read_type.size());
  // A decoder that met missing or damaged data says so (has_error) even when it returns
  // what it could decode: that is an error, never a partial image.
  const bool read = in.read_image(0, 0, 0, spec.nchannels, read_type, buffer.data());
  if (!read || in.has_error()) {
    std::string why = in.geterror();
    for (char& c : why)
      if (c == '\n') c = ' ';
    const bool ended = why.find("Premature end") != std::string::npos || why.find("premature end") != std::string::npos ||
                       why.find("Read Error") != std::string::npos || why.find("Not enough") != std::string::npos ||
                       why.find("end of file") != std::string::npos || why.find("truncated") != std::string::npos;
    return Status(ended ? StatusCode::kTruncated : StatusCode::kDecodeFailed,
                  name + (ended ? ": the data ends early: " : ": cannot decode the pixels: ") +
                      (why.empty() ? std::string("the decoder failed") : why));
  }
  const int colours = int(pick.colour.size());
  Raster out(spec.width, spec.height, colours + (pick.alpha >= 0 ? 1 : 0));
  // Straight alpha unless the file stores it premultiplied (OpenEXR's convention).
  const bool premultiplied = pick.alpha >= 0 && spec.get_int_attribute("oiio:UnassociatedAlpha", 0) == 0 &&
                             source.linear;
  for (size_t p = 0; p < pixels; ++p) {
    float* d = &out.data[p * out.channels];
    if (read_type == OIIO::TypeDesc::UINT8) {
      const uint8_t* s = &buffer[p * nch];
      for (int c = 0; c < colours; ++c) d[c] = float(s[pick.colour[c]]);
      if (pick.alpha >= 0) d[colours] = float(s[pick.alpha] * (1.0 / 255));
    } else if (read_type == OIIO::TypeDesc::UINT16) {
      const uint16_t* s = reinterpret_cast<const uint16_t*>(buffer.data()) + p * nch;
      for (int c = 0; c < colours; ++c) d[c] = float(s[pick.colour[c]] * (255.0 / 65535.0));
      if (pick.alpha >= 0) d[colours] = float(s[pick.alpha] * (1.0 / 65535));
    } else {
      const float* s = reinterpret_cast<const float*>(buffer.data()) + p * nch;
      double a = pick.alpha >= 0 ? double(s[pick.alpha]) : 1.0;
      a = std::isfinite(a) ? std::clamp(a, 0.0, 1.0) : 0.0;
      for (int c = 0; c < colours; ++c) {
        double v = s[pick.colour[c]];
        if (premultiplied) v = a > 0 ? v / a : 0.0;
        d[c] = LinearToSrgb255(std::isfinite(v) ? std::clamp(v, 0.0, 1.0) : 0.0);
      }
      if (pick.alpha >= 0) d[colours] = float(a);
    }
  }
  return out;
}

// Applies the EXIF/TIFF orientation (1..8) so that the raster is upright.
StatusOr<Raster> Reorient(Raster raster, int orientation, const std::string& name) {
  if (orientation <= 1 || orientation > 8) return raster;
  OIIO::ImageSpec spec(raster.width, raster.height, raster.channels, OIIO::TypeDesc::FLOAT);
  spec.attribute("Orientation", orientation);
  OIIO::ImageBuf src(spec, raster.data.data());
  OIIO::ImageBuf upright;
  if (!OIIO::ImageBufAlgo::reorient(upright, src))
    return Status(StatusCode::kDecodeFailed, name + ": cannot apply orientation " + std::to_string(orientation) +
                                                 ": " + upright.geterror());
  const OIIO::ImageSpec& u = upright.spec();
  Raster out(u.width, u.height, raster.channels);
  if (!upright.get_pixels(OIIO::ROI(u.x, u.x + u.width, u.y, u.y + u.height), OIIO::TypeDesc::FLOAT, out.data.data()))
    return Status(StatusCode::kDecodeFailed, name + ": cannot apply orientation: " + upright.geterror());
  return out;
}

// GIF decoders always give RGBA; alpha stays only where some pixel is transparent.
Raster DropAlphaOfOpaqueGif(Raster raster, const std::string& format) {
  if (format != "gif" || !raster.has_alpha()) return raster;
  const int ch = raster.channels;
  for (size_t p = 0; p < raster.data.size(); p += size_t(ch))
    if (raster.data[p + size_t(ch) - 1] != 1.0f) return raster;
  Raster out(raster.width, raster.height, ch - 1);
  for (size_t p = 0, n = size_t(raster.width) * raster.height; p < n; ++p)
    std::copy_n(&raster.data[p * ch], ch - 1, &out.data[p * (ch - 1)]);
  return out;
}

// The embedded ICC profile (if any) converted to sRGB; an unusable one becomes a warning.
void ApplyIccProfile(const OIIO::ImageSpec& spec, Raster& raster, const std::string& name, RasterSource& source) {
  const OIIO::ParamValue* icc = spec.find_attribute("ICCProfile");
  if (!icc || icc->datasize() == 0) return;
  const auto* bytes = static_cast<const uint8_t*>(icc->data());
  const std::vector<uint8_t> profile(bytes, bytes + icc->datasize());
  if (source.linear) {
    source.warnings.push_back(name + ": the ICC profile of a float image is ignored (samples taken as linear sRGB)");
    return;
  }
  auto converted = ConvertIccToSrgb(profile, raster);
  if (!converted.ok()) {
    source.warnings.push_back(name + ": " + converted.status().message() + "; colours taken as sRGB");
    return;
  }
  source.icc_profile = converted->description;
  source.icc_converted = converted->converted;
}

// What the decoders inside OpenImageIO (libpng's default handlers, libtiff) print to
// standard error while one image is decoded: captured, so that it becomes part of our
// Status or RasterSource::warnings instead of raw text on the terminal. Decodes are
// serialised while captured (standard error is one per process).
class CapturedStderr {
 public:
  CapturedStderr() : lock_(Mutex()) {
    std::fflush(stderr);
    file_ = std::tmpfile();
    saved_ = file_ ? ::dup(STDERR_FILENO) : -1;
    if (saved_ >= 0) ::dup2(::fileno(file_), STDERR_FILENO);
  }
  ~CapturedStderr() { Restore(); }
  CapturedStderr(const CapturedStderr&) = delete;
  CapturedStderr& operator=(const CapturedStderr&) = delete;
  // Restores standard error; returns what was written (at most 4 KB, one line).
  std::string Restore() {
    std::string text;
    if (saved_ >= 0) {
      std::fflush(stderr);
      ::dup2(saved_, STDERR_FILENO);
      ::close(saved_);
      saved_ = -1;
      std::rewind(file_);
      char buf[4096];
      text.assign(buf, std::fread(buf, 1, sizeof buf, file_));
    }
    if (file_) std::fclose(file_);
    file_ = nullptr;
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    for (char& c : text)
      if (c == '\n') c = ';';
    return text;
  }

 private:
  static std::mutex& Mutex() {
    static std::mutex m;
    return m;
  }
  std::lock_guard<std::mutex> lock_;
  std::FILE* file_ = nullptr;
  int saved_ = -1;
};

}  // namespace

// DecodeRaster's work, while standard error is captured.
static StatusOr<Raster> DecodeCaptured(const std::vector<uint8_t>& bytes, const std::string& name,
                                const RasterLimits& limits, RasterSource* source_out);

StatusOr<Raster> DecodeRaster(const std::vector<uint8_t>& bytes, const std::string& name, RasterSource* source_out) {
  return DecodeRaster(bytes, name, RasterLimits{}, source_out);
}

StatusOr<Raster> DecodeRaster(const std::vector<uint8_t>& bytes, const std::string& name, const RasterLimits& limits,
                              RasterSource* source_out) {
  if (bytes.empty()) return Status(StatusCode::kEmptyInput, name + ": the file is empty");
  SDVI_RETURN_IF_ERROR(CheckPngHeader(bytes, name));
  CapturedStderr capture;
  StatusOr<Raster> raster = DecodeCaptured(bytes, name, limits, source_out);
  const std::string said = capture.Restore();
  if (said.empty()) return raster;
  if (!raster.ok())
    return Status(raster.status().code(), raster.status().message() + " (the decoder said: " + said + ")");
  if (source_out) source_out->warnings.push_back(name + ": the decoder said: " + said);
  return raster;
}

static StatusOr<Raster> DecodeCaptured(const std::vector<uint8_t>& bytes, const std::string& name,
                                       const RasterLimits& limits, RasterSource* source_out) {
  RasterSource source;
  try {
    // The bytes are read through an IOProxy; with a config, OpenImageIO 2.4 takes the proxy
    // from the config's "oiio:ioproxy" (a pointer to the proxy pointer) as well.
    OIIO::Filesystem::IOMemReader reader(bytes.data(), bytes.size());
    OIIO::Filesystem::IOProxy* proxy = &reader;
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // keep PNG/TIFF alpha straight, as stored
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(name, &config, &reader);
    if (!in) {
      const std::string why = OIIO::geterror();
      return Status(StatusCode::kDecodeFailed, name + ": not an image sdvi can decode" +
                                                   (why.empty() ? std::string() : " (" + why + ")"));
    }
    source.format = in->format_name();
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0)
      return Status(StatusCode::kEmptyInput, name + ": the header says " + SizeText(spec.width, spec.height));
    if (uint64_t(spec.width) * uint64_t(spec.height) > std::min(kMaxPixels, limits.max_pixels) || spec.depth > 1)
      return Status(StatusCode::kLimitExceeded,
                    name + ": " + SizeText(spec.width, spec.height) + " pixels is over the limit of " +
                        std::to_string(std::min(kMaxPixels, limits.max_pixels)));
    SDVI_ASSIGN_OR_RETURN(Raster raster, ReadPixels(*in, name, source));
    ApplyIccProfile(spec, raster, name, source);
    source.orientation = std::clamp(spec.get_int_attribute("Orientation", 1), 1, 8);
    SDVI_ASSIGN_OR_RETURN(raster, Reorient(std::move(raster), source.orientation, name));
    raster = DropAlphaOfOpaqueGif(std::move(raster), source.format);
    if (source_out) *source_out = std::move(source);
    return raster;
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::kLimitExceeded, name + ": out of memory while decoding the image");
  } catch (const std::exception& e) {
    return Status(StatusCode::kDecodeFailed, name + ": cannot decode the image: " + e.what());
  }
}

StatusOr<Raster> LoadRaster(const std::string& path, RasterSource* source) {
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, ReadFileBytes(path));
  return DecodeRaster(bytes, path, source);
}

namespace {

constexpr int kPngCompressionLevel = 1;

// The PNG of samples (8- or 16-bit, interleaved, channels as the raster has them).
StatusOr<std::vector<uint8_t>> EncodePngSamples(int width, int height, int ch, bool has_alpha, int bits,
                                                const void* data, const std::string& name) {
  const OIIO::TypeDesc type = bits == 8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::UINT16;
  OIIO::ImageSpec spec(width, height, ch, type);
  spec.alpha_channel = has_alpha ? ch - 1 : -1;
  spec.attribute("oiio:ColorSpace", "sRGB");  // -> sRGB, gAMA and cHRM chunks
  spec.attribute("oiio:UnassociatedAlpha", 1);  // the samples are straight: write them as they are
  // zlib level 1, OpenCV's imwrite default (libpng's is 6): on a 4096 x 4096 render 3.3x
  // faster to encode (1.0 s, not 3.2 s) for a file 35% larger (7.7 MB, not 5.7 MB).
  spec.attribute("png:compressionLevel", kPngCompressionLevel);
  std::vector<uint8_t> encoded;
  try {
    OIIO::Filesystem::IOVecOutput writer(encoded);
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create("png");
    if (!out) return Status(StatusCode::kEncodeFailed, name + ": no PNG writer: " + OIIO::geterror());
    out->set_ioproxy(&writer);
    if (!out->open("out.png", spec) || !out->write_image(type, data) || !out->close())
      return Status(StatusCode::kEncodeFailed, name + ": PNG encoding failed: " + out->geterror());
  } catch (const std::exception& e) {
    return Status(StatusCode::kEncodeFailed, name + ": PNG encoding failed: " + e.what());
  }
  return encoded;
}

// Which channels an output needs (see WithNeededChannels): alpha unless every pixel is
// opaque, and colour unless every pixel is grey.
struct NeededChannels {
  bool keep_alpha, colours;
};
template <typename RasterT>
NeededChannels FindNeededChannels(const RasterT& raster, decltype(raster.data[0]) opaque_value) {
  const int ch = raster.channels;
  const size_t n = size_t(raster.width) * raster.height;
  bool opaque = raster.has_alpha(), grey = ch >= 3;
  for (size_t p = 0; p < n && (opaque || grey); ++p) {
    const auto* s = &raster.data[p * ch];
    if (raster.has_alpha() && s[ch - 1] != opaque_value) opaque = false;
    if (ch >= 3 && (s[0] != s[1] || s[0] != s[2])) grey = false;
  }
  return {raster.has_alpha() && !opaque, ch >= 3 && !grey};
}

// raster with the channels needed.
template <typename RasterT>
RasterT KeepChannels(const RasterT& raster, NeededChannels needed) {
  const int ch = raster.channels;
  const size_t n = size_t(raster.width) * raster.height;
  const int colours = ch >= 3 ? 3 : 1, out_colours = needed.colours ? 3 : 1;
  if (out_colours == colours && needed.keep_alpha == raster.has_alpha()) return raster;
  RasterT out(raster.width, raster.height, out_colours + (needed.keep_alpha ? 1 : 0));
  for (size_t p = 0; p < n; ++p) {
    const auto* s = &raster.data[p * ch];
    auto* d = &out.data[p * out.channels];
    std::copy_n(s, out_colours, d);
    if (needed.keep_alpha) d[out_colours] = s[ch - 1];
  }
  return out;
}

Status CheckRasterToEncode(int width, int height, int channels, size_t samples, const std::string& name) {
  if (width <= 0 || height <= 0) return Status(StatusCode::kEmptyInput, name + ": the raster to write is empty");
  if (channels < 1 || channels > 4 || samples != size_t(width) * height * channels)
    return Status(StatusCode::kInvalidArgument, name + ": raster has " + std::to_string(channels) +
                                                    " channels and " + std::to_string(samples) + " samples");
  return Status::Ok();
}

}  // namespace

StatusOr<std::vector<uint8_t>> EncodePng(const Raster& raster, int bits, const std::string& name) {
  if (bits != 8 && bits != 16)
    return Status(StatusCode::kInvalidArgument, name + ": PNG bit depth " + std::to_string(bits) + " (8 or 16 expected)");
  SDVI_RETURN_IF_ERROR(CheckRasterToEncode(raster.width, raster.height, raster.channels, raster.data.size(), name));
  const int ch = raster.channels;
  const double max = bits == 8 ? 255.0 : 65535.0;
  auto quantise = [max](double v, double unit) {
    if (!(v == v)) return 0.0;  // NaN
    return std::round(std::clamp(v * unit, 0.0, max));
  };
  const size_t n = raster.data.size();
  std::vector<uint16_t> wide(bits == 16 ? n : 0);
  std::vector<uint8_t> narrow(bits == 8 ? n : 0);
  for (size_t i = 0; i < n; ++i) {
    const bool alpha = raster.has_alpha() && int(i % size_t(ch)) == ch - 1;
    const double q = quantise(raster.data[i], alpha ? max : max / 255.0);
    if (bits == 8)
      narrow[i] = uint8_t(q);
    else
      wide[i] = uint16_t(q);
  }
  const void* data = bits == 8 ? static_cast<const void*>(narrow.data()) : static_cast<const void*>(wide.data());
  return EncodePngSamples(raster.width, raster.height, ch, raster.has_alpha(), bits, data, name);
}

StatusOr<std::vector<uint8_t>> EncodePng(const Raster8& raster, const std::string& name) {
  SDVI_RETURN_IF_ERROR(CheckRasterToEncode(raster.width, raster.height, raster.channels, raster.data.size(), name));
  return EncodePngSamples(raster.width, raster.height, raster.channels, raster.has_alpha(), 8, raster.data.data(),
                          name);
}

Status SaveRasterPng(const std::string& path, const Raster& raster, int bits) {
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> encoded, EncodePng(raster, bits, path));
  return WriteFileAtomic(path, encoded);
}

Status SaveRasterPng(const std::string& path, const Raster8& raster) {
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> encoded, EncodePng(raster, path));
  return WriteFileAtomic(path, encoded);
}

Raster WithNeededChannels(const Raster& raster) {
  return KeepChannels(raster, FindNeededChannels(raster, 1.0f));
}

Raster8 WithNeededChannels(const Raster8& raster) {
  return KeepChannels(raster, FindNeededChannels(raster, uint8_t(255)));
}

}  // namespace sdvi
