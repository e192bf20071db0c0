// SPDX-License-Identifier: GPL-3.0-or-later
// libsdvi_raster_oiio.so: the OpenImageIO side of sdvi_raster_io (oiio_module.h), loaded on
// first use by raster_io.cpp. OpenImageIO errors and exceptions stop here.
//
// Why OpenImageIO and not OpenCV's imgcodecs (measured by build/bench/raster/bench_raster_io,
// spec/RASTER_INPUT.md): OpenCV 4.6 applies EXIF orientation only when it may also drop
// alpha and 16-bit samples (any flag but IMREAD_UNCHANGED), never exposes an ICC profile,
// reads no GIF, reads EXR only behind an environment switch, and writes no sRGB chunk;
// OpenImageIO does all of these from memory, with the same libpng/libjpeg-turbo decoders
// (identical samples) and comparable decode time.
#include "oiio_module.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <exception>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include "samples.h"

namespace sdvi::raster_internal {
namespace {

std::string SizeText(int64_t w, int64_t h) { return std::to_string(w) + "x" + std::to_string(h); }

// OpenImageIO 2.4's memory reader copies from wherever its position points, before the
// buffer too: a BMP whose pixel data offset is 0xffffffc0 made it read 16 bytes before the
// file's bytes (found by fuzz.raster under ASan). Here a position outside the bytes reads
// nothing, so the decoder reports the file as truncated.
class BoundedMemReader final : public OIIO::Filesystem::IOMemReader {
 public:
  using IOMemReader::IOMemReader;
  bool seek(int64_t offset) override {
    if (offset < 0 || uint64_t(offset) > uint64_t(m_buf.size())) return false;
    return IOMemReader::seek(offset);
  }
  size_t pread(void* buf, size_t size, int64_t offset) override {
    if (offset < 0 || uint64_t(offset) > uint64_t(m_buf.size())) return 0;
    return IOMemReader::pread(buf, size, offset);
  }
  size_t read(void* buf, size_t size) override {
    const size_t n = pread(buf, size, m_pos);
    m_pos += int64_t(n);
    return n;
  }
};

// The readers sdvi uses (the formats of spec/RASTER_INPUT.md), in the order they are tried on
// bytes the extension's reader refuses or whose extension names none of them; TGA last, as
// it has no signature. OpenImageIO 2.4 carries 28 readers and, when the extension's reader
// fails, tries every one (FFmpeg, LibRaw, DCMTK, OpenVDB, and its own parsers of PSD, DDS,
// ICO, SGI, RLA, IFF, FITS, DPX, ...), each code that a hostile file could reach. sdvi opens
// only these.
struct Reader {
  const char* format;  // OpenImageIO's name
  const char* title;   // for messages
};
constexpr Reader kReaders[] = {{"png", "PNG"},          {"jpeg", "JPEG"}, {"tiff", "TIFF"},   {"bmp", "BMP"},
                               {"gif", "GIF"},          {"webp", "WebP"}, {"openexr", "OpenEXR"},
                               {"hdr", "Radiance HDR"}, {"pnm", "PNM"},   {"targa", "TGA"}};

// OpenImageIO's format for the name's extension ("" when it has none or an unknown one).
std::string FormatOfExtension(const std::string& name) {
  std::string ext = OIIO::Filesystem::extension(name, false);
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext.empty()) return {};
  for (const auto& [format, extensions] : OIIO::get_extension_map())
    if (std::find(extensions.begin(), extensions.end(), ext) != extensions.end()) return format;
  return {};
}

// The bytes opened by the first of kReaders that accepts them, the extension's reader first.
StatusOr<std::unique_ptr<OIIO::ImageInput>> OpenWithReaders(BoundedMemReader& reader, const OIIO::ImageSpec& config,
                                                            const std::string& name) {
  const std::string implied = FormatOfExtension(name);
  std::vector<const Reader*> order;
  std::string titles;
  for (const Reader& r : kReaders) {
    order.push_back(&r);
    titles += std::string(titles.empty() ? "" : ", ") + r.title;
  }
  std::stable_partition(order.begin(), order.end(), [&](const Reader* r) { return implied == r->format; });
  const bool implied_read = implied == order.front()->format;
  std::string why;  // the extension's reader's words, when it refused the bytes
  for (const Reader* r : order) {
    OIIO::Filesystem::IOProxy* proxy = &reader;
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::create(r->format, false, &config, proxy);
    if (!in) continue;  // a reader this OpenImageIO was built without
    in->set_ioproxy(proxy);
    reader.seek(0);
    OIIO::ImageSpec spec;
    if (in->open(name, spec, config)) return in;
    if (r->format == implied) why = in->geterror();
  }
  for (char& c : why)
    if (c == '\n') c = ' ';
  if (!implied.empty() && !implied_read)
    return Status(StatusCode::kUnsupportedFormat, name + ": the extension says " + implied +
                                                      ", which sdvi does not read, and the bytes are none of " +
                                                      titles);
  return Status(StatusCode::kDecodeFailed, name + ": not an image sdvi can decode (" +
                                               (why.empty() ? "the bytes are none of " + titles : why) + ")");
}

// sRGB transfer function (IEC 61966-2-1): linear 0..1 -> 0..255.
float LinearToSrgb255(double linear) {
  const double v = linear <= 0.0031308 ? linear * 12.92 : 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
  return float(v * 255.0);
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
StatusOr<Raster> ReadPixels(OIIO::ImageInput& in, const std::string& name, DecodedImage& source) {
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
      for (int c = 0; c < colours; ++c) d[c] = ColourOf8(s[pick.colour[c]]);
      if (pick.alpha >= 0) d[colours] = AlphaOf8(s[pick.alpha]);
    } else if (read_type == OIIO::TypeDesc::UINT16) {
      const uint16_t* s = reinterpret_cast<const uint16_t*>(buffer.data()) + p * nch;
      for (int c = 0; c < colours; ++c) d[c] = ColourOf16(s[pick.colour[c]]);
      if (pick.alpha >= 0) d[colours] = AlphaOf16(s[pick.alpha]);
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
StatusOr<Raster> Reorient(const Raster& raster, int orientation, const std::string& name) {
  if (orientation <= 1 || orientation > 8) return raster;
  OIIO::ImageSpec spec(raster.width, raster.height, raster.channels, OIIO::TypeDesc::FLOAT);
  spec.attribute("Orientation", orientation);
  // ImageBuf wraps the samples without writing them.
  OIIO::ImageBuf src(spec, const_cast<float*>(raster.data.data()));
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

StatusOr<DecodedImage> Decode(const std::vector<uint8_t>& bytes, const std::string& name, uint64_t max_pixels) {
  try {
    // The bytes are read through an IOProxy; with a config, OpenImageIO 2.4 takes the proxy
    // from the config's "oiio:ioproxy" (a pointer to the proxy pointer) as well.
    BoundedMemReader reader(bytes.data(), bytes.size());
    OIIO::Filesystem::IOProxy* proxy = &reader;
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // keep PNG/TIFF alpha straight, as stored
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    SDVI_ASSIGN_OR_RETURN(std::unique_ptr<OIIO::ImageInput> in, OpenWithReaders(reader, config, name));
    DecodedImage out;
    out.format = in->format_name();
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0)
      return Status(StatusCode::kEmptyInput, name + ": the header says " + SizeText(spec.width, spec.height));
    if (uint64_t(spec.width) * uint64_t(spec.height) > max_pixels || spec.depth > 1)
      return Status(StatusCode::kLimitExceeded, name + ": " + SizeText(spec.width, spec.height) +
                                                    " pixels is over the limit of " + std::to_string(max_pixels));
    SDVI_ASSIGN_OR_RETURN(out.raster, ReadPixels(*in, name, out));
    if (const OIIO::ParamValue* icc = spec.find_attribute("ICCProfile"); icc && icc->datasize() > 0) {
      const auto* p = static_cast<const uint8_t*>(icc->data());
      out.icc_profile.assign(p, p + icc->datasize());
    }
    out.orientation = std::clamp(spec.get_int_attribute("Orientation", 1), 1, 8);
    return out;
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::kLimitExceeded, name + ": out of memory while decoding the image");
  } catch (const std::exception& e) {
    return Status(StatusCode::kDecodeFailed, name + ": cannot decode the image: " + e.what());
  }
}

StatusOr<Raster> ReorientCaught(const Raster& raster, int orientation, const std::string& name) {
  try {
    return Reorient(raster, orientation, name);
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::kLimitExceeded, name + ": out of memory while turning the image upright");
  } catch (const std::exception& e) {
    return Status(StatusCode::kDecodeFailed, name + ": cannot apply orientation: " + e.what());
  }
}

}  // namespace
}  // namespace sdvi::raster_internal

extern "C" const sdvi::raster_internal::OiioModule* sdvi_raster_oiio_module() {
  using namespace sdvi::raster_internal;
  static const OiioModule kModule = {kOiioModuleAbi, uint32_t(sizeof(DecodedImage)), Decode, ReorientCaught};
  return &kModule;
}
