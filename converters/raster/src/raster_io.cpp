// SPDX-License-Identifier: GPL-3.0-or-later
// Raster image files (raster_io.h): the checks, ICC conversion and channel rules here; the
// decoders and the PNG encoder in OpenImageIO, through the module libsdvi_raster_oiio.so
// (oiio_module.h), opened on first use (spec/RASTER_INPUT.md, "Loading").
#include "sdvi/raster_io.h"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <new>
#include <string>
#include <vector>

#include "icc_profile.h"
#include "oiio_module.h"
#include "png_reader.h"
#include "png_writer.h"
#include "sdvi/file_util.h"

namespace sdvi {
namespace {

using raster_internal::OiioModule;
using raster_internal::kOiioModuleAbi;

#ifndef SDVI_RASTER_OIIO_LINKED
constexpr const char* kOiioModuleFile = "libsdvi_raster_oiio.so";

// Opens the module: $SDVI_MODULE_DIR, then the install layout next to the binary that holds
// this code (bin/../lib/sdvi), then the build tree's copy, then the configured install
// directory. Null with *why set when none opens or none matches this build.
const OiioModule* OpenOiioModule(std::string* why) {
  std::vector<std::string> candidates;
  if (const char* dir = std::getenv("SDVI_MODULE_DIR"); dir && *dir)
    candidates.push_back(std::string(dir) + "/" + kOiioModuleFile);
  Dl_info self;
  if (::dladdr(reinterpret_cast<void*>(&OpenOiioModule), &self) && self.dli_fname) {
    const std::string binary = self.dli_fname;
    const size_t slash = binary.rfind('/');
    if (slash != std::string::npos)
      candidates.push_back(binary.substr(0, slash + 1) + SDVI_MODULE_DIR_FROM_BIN + "/" + kOiioModuleFile);
  }
  candidates.push_back(SDVI_OIIO_MODULE_BUILD_PATH);
  candidates.push_back(std::string(SDVI_MODULE_INSTALL_DIR) + "/" + kOiioModuleFile);
  std::string tried;
  for (const std::string& path : candidates) {
    if (::access(path.c_str(), R_OK) != 0) continue;
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    const char* error = handle ? nullptr : ::dlerror();
    auto entry = handle ? reinterpret_cast<const OiioModule* (*)()>(::dlsym(handle, "sdvi_raster_oiio_module")) : nullptr;
    const OiioModule* module = entry ? entry() : nullptr;
    if (module && module->abi == kOiioModuleAbi && module->sizeof_decoded == sizeof(raster_internal::DecodedImage))
      return module;  // stays open for the life of the process
    tried += (tried.empty() ? "" : "; ") + path + (error ? std::string(": ") + error : ": built for another sdvi");
    if (handle) ::dlclose(handle);
  }
  *why = "cannot load " + std::string(kOiioModuleFile) + " (" +
         (tried.empty() ? "not found; set SDVI_MODULE_DIR to the directory that holds it" : tried) + ")";
  return nullptr;
}

#endif

// The module, opened once per process (or linked in: SDVI_RASTER_MODULE off).
StatusOr<const OiioModule*> Oiio(StatusCode code, const std::string& name) {
#ifdef SDVI_RASTER_OIIO_LINKED
  (void)code;
  (void)name;
  return sdvi_raster_oiio_module();
#else
  static std::string why;
  static const OiioModule* const module = OpenOiioModule(&why);
  if (!module) return Status(code, name + ": raster support is not available: " + why);
  return module;
#endif
}

constexpr uint64_t kMaxPixels = uint64_t(1) << 28;  // 16384 x 16384

std::string SizeText(int64_t w, int64_t h) { return std::to_string(w) + "x" + std::to_string(h); }

// The bytes of a PNG's signature (8) and its IHDR chunk (length, type, 13 bytes, CRC).
constexpr size_t kPngHeadBytes = 8 + 8 + 13 + 4;

// A PNG's size from its IHDR, before libpng sees the file: empty or over the limit.
Status CheckPngHeader(const std::vector<uint8_t>& bytes, const std::string& name) {
  if (bytes.size() < kPngHeadBytes || !raster_internal::StartsAsPng(bytes.data())) return Status::Ok();
  const uint64_t w = raster_internal::BigEndian32(&bytes[16]), h = raster_internal::BigEndian32(&bytes[20]);
  if (w == 0 || h == 0) return Status(StatusCode::kEmptyInput, name + ": PNG header says " + SizeText(w, h));
  if (w * h > kMaxPixels)
    return Status(StatusCode::kLimitExceeded, name + ": " + SizeText(w, h) + " pixels is over the limit of 2^28");
  return Status::Ok();
}

// A BMP's size and compression from its header, before OpenImageIO sees the file (its
// signature "BM", whatever the name says), because OpenImageIO 2.4's BMP reader trusts both
// when it opens the file:
//   - it decodes an RLE image whole while opening, before sdvi can compare the size with the
//     limit: a 108-byte file declaring 5 x 419430406 pixels made it fill 2 GB (found by
//     fuzz.raster);
//   - it looks RLE-compressed pixels up in the colour table without checking that there is
//     one: 24 bits a pixel with RLE8 made it read before a null pointer (a crash, found by
//     fuzz.raster). The format pairs RLE8 with 8 bits a pixel and RLE4 with 4 (the only
//     depths with a colour table to look up), so any other pairing is a damaged header.
// Headers: BITMAPCOREHEADER (12 bytes: 16-bit width and height), BITMAPINFOHEADER and later
// (40 bytes and up: 32-bit width, height negative for top-down rows, bits at 28,
// compression at 30).
Status CheckBmpHeader(const std::vector<uint8_t>& bytes, const std::string& name, uint64_t max_pixels) {
  if (bytes.size() < 26 || bytes[0] != 'B' || bytes[1] != 'M') return Status::Ok();
  auto le = [&](size_t at, int n) {
    uint32_t v = 0;
    for (int i = n - 1; i >= 0; --i) v = v << 8 | bytes[at + size_t(i)];
    return v;
  };
  const uint32_t header = le(14, 4);
  int64_t w = 0, h = 0;
  if (header == 12) {
    w = le(18, 2), h = le(20, 2);
  } else if (header >= 40 && bytes.size() >= 34) {
    w = int32_t(le(18, 4)), h = int32_t(le(22, 4));
    const uint32_t bits = le(28, 2), compression = le(30, 4);
    const uint32_t needs = compression == 1 ? 8 : compression == 2 ? 4 : bits;
    if (bits != needs)
      return Status(StatusCode::kDecodeFailed, name + ": damaged BMP header: RLE" + std::to_string(needs) +
                                                   " compression with " + std::to_string(bits) + " bits a pixel (RLE" +
                                                   std::to_string(needs) + " needs " + std::to_string(needs) + ")");
  } else {
    return Status::Ok();  // another header: OpenImageIO's to judge
  }
  h = h < 0 ? -h : h;
  if (w < 0) return Status(StatusCode::kDecodeFailed, name + ": damaged BMP header: width " + std::to_string(w));
  if (w == 0 || h == 0) return Status(StatusCode::kEmptyInput, name + ": BMP header says " + SizeText(w, h));
  if (uint64_t(w) * uint64_t(h) > max_pixels)
    return Status(StatusCode::kLimitExceeded,
                  name + ": " + SizeText(w, h) + " pixels is over the limit of " + std::to_string(max_pixels));
  return Status::Ok();
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
void ApplyIccProfile(const std::vector<uint8_t>& profile, Raster& raster, const std::string& name,
                     RasterSource& source) {
  if (profile.empty()) return;
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

Status OpenRasterCodecs(const std::vector<std::string>& paths) {
  for (const std::string& path : paths) {
    if (path == "-") return Oiio(StatusCode::kDecodeFailed, "raster input").status();
    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (!file) continue;  // its decode reports it
    const bool png = raster_internal::DecodesWithLibpng([file](uint64_t at, size_t n, uint8_t* out) {
      return at <= uint64_t(std::numeric_limits<long>::max()) && std::fseek(file, long(at), SEEK_SET) == 0 &&
             std::fread(out, 1, n, file) == n;
    });
    std::fclose(file);
    if (!png) return Oiio(StatusCode::kDecodeFailed, "raster input").status();
  }
  return Status::Ok();
}

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
  SDVI_RETURN_IF_ERROR(CheckBmpHeader(bytes, name, std::min(kMaxPixels, limits.max_pixels)));
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
  try {
    // PNGs with libpng (no module to load), unless an eXIf chunk asks for OpenImageIO.
    const uint64_t max_pixels = std::min(kMaxPixels, limits.max_pixels);
    const bool png = raster_internal::DecodesWithLibpng(bytes);
    const OiioModule* oiio = nullptr;
    if (!png) {
      SDVI_ASSIGN_OR_RETURN(oiio, Oiio(StatusCode::kDecodeFailed, name));
    }
    SDVI_ASSIGN_OR_RETURN(raster_internal::DecodedImage decoded,
                          png ? raster_internal::DecodePngWithLibpng(bytes, name, max_pixels)
                              : oiio->decode(bytes, name, max_pixels));
    RasterSource source;
    source.format = decoded.format;
    source.file_channels = decoded.file_channels;
    source.bits = decoded.bits;
    source.linear = decoded.linear;
    source.orientation = decoded.orientation;
    Raster raster = std::move(decoded.raster);
    ApplyIccProfile(decoded.icc_profile, raster, name, source);
    if (source.orientation != 1) {  // only OpenImageIO's decoders read an orientation
      SDVI_ASSIGN_OR_RETURN(raster, oiio->reorient(raster, source.orientation, name));
    }
    raster = DropAlphaOfOpaqueGif(std::move(raster), source.format);
    if (source_out) *source_out = std::move(source);
    return raster;
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::kLimitExceeded, name + ": out of memory while decoding the image");
  }
}

StatusOr<Raster> LoadRaster(const std::string& path, RasterSource* source) {
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, ReadFileBytes(path));
  return DecodeRaster(bytes, path, source);
}

namespace {

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
  return raster_internal::EncodePngWithLibpng(raster.width, raster.height, ch, bits, data, name);
}

StatusOr<std::vector<uint8_t>> EncodePng(const Raster8& raster, const std::string& name) {
  SDVI_RETURN_IF_ERROR(CheckRasterToEncode(raster.width, raster.height, raster.channels, raster.data.size(), name));
  return raster_internal::EncodePngWithLibpng(raster.width, raster.height, raster.channels, 8, raster.data.data(), name);
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
