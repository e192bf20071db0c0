// SPDX-License-Identifier: GPL-3.0-or-later
// The Python binding `sdvi` (python/README section of the top-level README): vectorize,
// render, compress and compare on files and numpy arrays, through the same library calls as
// the `sdvi` command, so that a file written here is byte-identical to the command's.
// Every call releases the GIL while the library works.
//
// Arrays. An input image is an (H, W) or (H, W, C) array, C = 1 grey, 2 grey+alpha, 3 RGB,
// 4 RGBA: uint8 as is, uint16 scaled by 255/65535 (alpha by 1/65535), float32/float64 in
// sdvi::Raster's convention (colours on the 0..255 scale, alpha 0..1), uint8 alpha by 1/255.
// A rendered image is returned as float32 (H, W, 4) in that same convention.
// Errors: every sdvi Status becomes a Python exception (ValueError for bad arguments and
// input, OSError for files, RuntimeError otherwise) whose text names the input.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <variant>

#include "sdvi/codec.h"
#include "sdvi/file_util.h"
#include "sdvi/format.h"
#include "sdvi/parallel.h"
#include "sdvi/rate.h"
#include "sdvi/raster_io.h"
#include "sdvi/render.h"
#include "sdvi/vectorize.h"

namespace py = pybind11;

namespace sdvi::python {
namespace {

// A Status as a C++ exception that pybind11 turns into a Python one (the translator in
// the module definition): OSError for files, ValueError for bad arguments and input,
// RuntimeError for the rest. Thrown without the GIL; translated with it.
struct FileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

[[noreturn]] void Raise(const Status& status) {
  const std::string text = status.ToString();
  switch (status.code()) {
    case StatusCode::kNotFound:
    case StatusCode::kIoError:
      throw FileError(text);
    case StatusCode::kInternal:
      throw std::runtime_error(text);
    default:
      throw std::invalid_argument(text);
  }
}

template <typename T>
T Take(StatusOr<T>&& value) {
  if (!value.ok()) Raise(value.status());
  return std::move(value).value();
}

void Check(const Status& status) {
  if (!status.ok()) Raise(status);
}

// An array (see the header comment) as a Raster.
Raster RasterFromArray(const py::array& input) {
  if (input.ndim() != 2 && input.ndim() != 3) {
    throw py::value_error("sdvi: image array must be (H, W) or (H, W, C), got " +
                          std::to_string(input.ndim()) + " dimensions");
  }
  const py::ssize_t h = input.shape(0), w = input.shape(1);
  const py::ssize_t c = input.ndim() == 3 ? input.shape(2) : 1;
  if (h < 1 || w < 1 || h > 65536 || w > 65536 || c < 1 || c > 4) {
    throw py::value_error("sdvi: image array of shape (" + std::to_string(h) + ", " + std::to_string(w) +
                          ", " + std::to_string(c) + ") is outside 1..65536 x 1..65536 x 1..4 channels");
  }
  Raster raster(static_cast<int>(w), static_cast<int>(h), static_cast<int>(c));
  const bool alpha = raster.has_alpha();
  auto fill = [&](auto typed, double colour_scale, double alpha_scale) {
    using T = typename decltype(typed)::value_type;
    py::array_t<T, py::array::c_style | py::array::forcecast> a(input);
    const T* src = a.data();
    const size_t n = size_t(w) * size_t(h) * size_t(c);
    for (size_t i = 0; i < n; ++i) {
      const bool is_alpha = alpha && int(i % size_t(c)) == c - 1;
      const double v = double(src[i]) * (is_alpha ? alpha_scale : colour_scale);
      if (!std::isfinite(v)) throw py::value_error("sdvi: image array holds a non-finite value");
      raster.data[i] = float(v);
    }
  };
  const py::dtype dt = input.dtype();
  if (dt.is(py::dtype::of<uint8_t>())) {
    fill(std::vector<uint8_t>(), 1.0, 1.0 / 255.0);
  } else if (dt.is(py::dtype::of<uint16_t>())) {
    fill(std::vector<uint16_t>(), 255.0 / 65535.0, 1.0 / 65535.0);
  } else if (dt.kind() == 'f' || dt.kind() == 'i' || dt.kind() == 'u') {
    fill(std::vector<double>(), 1.0, 1.0);
  } else {
    throw py::value_error("sdvi: image array dtype must be uint8, uint16 or floating point");
  }
  return raster;
}

py::array_t<float> ArrayFromRaster(const Raster& raster) {
  py::array_t<float> out({py::ssize_t(raster.height), py::ssize_t(raster.width), py::ssize_t(raster.channels)});
  std::memcpy(out.mutable_data(), raster.data.data(), raster.data.size() * sizeof(float));
  return out;
}

// A path (str / os.PathLike) or an array.
using Source = std::variant<std::string, py::array>;

Raster LoadSource(const Source& source) {
  if (const auto* path = std::get_if<std::string>(&source)) {
    Raster raster;
    {
      py::gil_scoped_release release;
      raster = Take(LoadRaster(*path));
    }
    return raster;
  }
  return RasterFromArray(std::get<py::array>(source));
}

// An sdvi image (a .sdvi path or an Image object).
using ImageSource = std::variant<std::string, Image>;

Image LoadImageSource(const ImageSource& source) {
  if (const auto* path = std::get_if<std::string>(&source)) {
    py::gil_scoped_release release;
    return Take(ReadImage(*path));
  }
  return std::get<Image>(source);
}


// vectorize(source, output=None, ...) -> (Image, report dict). The options and the file
// written (raw payload, or Draco with compress=True) are those of `sdvi vectorize`.
py::tuple VectorizePy(const Source& source, std::optional<std::string> output,
                      std::optional<Source> mask_source, double compression_ratio, int max_triangles,
                      double target_psnr, int iterations, int threads, bool compress, double quality,
                      uint64_t target_bytes) {
  const int targets = int(quality >= 0) + int(target_bytes > 0) + int(target_psnr > 0);
  if (targets > 1) throw py::value_error("sdvi: choose one of quality, target_bytes, target_psnr");
  if (quality > 100) throw py::value_error("sdvi: quality must be in 0..100");
  const Raster raster = LoadSource(source);
  std::optional<Raster> mask;
  if (mask_source) mask = LoadSource(*mask_source);
  const Raster* mask_ptr = mask ? &*mask : nullptr;
  VectorizeOptions options;
  options.compression_ratio = compression_ratio;
  options.max_triangles = max_triangles;
  options.target_psnr = target_psnr;
  options.iterations = iterations;
  options.threads = threads > 0 ? threads : DefaultThreads();
  options.fit.threads = options.threads;
  options.final_metrics = false;  // the file is measured, as by the command
  compress = compress || quality >= 0 || target_bytes > 0;  // targets imply compress, as in the CLI
  const std::string name =
      std::holds_alternative<std::string>(source) ? std::get<std::string>(source) : std::string("array");
  auto named = [&](const Status& s) { Raise(Status(s.code(), name + ": " + s.message())); };
  VectorizedFile made;
  {
    py::gil_scoped_release release;
    RateOptions rate;
    rate.threads = options.threads;
    RateTarget target;
    target.quality = quality;
    target.bytes = target_bytes;
    // The one path of `sdvi vectorize` (VectorizeToFile): the image returned is what a reader
    // of the file gets, the report's PSNR, MSSIM and mean error the file's (spec/RATE.md 1).
    StatusOr<VectorizedFile> done = VectorizeToFile(raster, mask_ptr, options, compress, target, rate, name);
    if (!done.ok()) named(done.status());
    made = std::move(done).value();
    if (output) Check(WriteFileAtomic(*output, made.bytes));
  }
  // The report of `sdvi vectorize --report`, field for field (VectorizedFileReportJson).
  py::dict report = py::module_::import("json").attr("loads")(VectorizedFileReportJson(made, name, output.value_or(""), -1));
  return py::make_tuple(std::move(made.decoded), report);
}

// The viewport of `sdvi render` for --scale, or --width/--height (one side keeps the aspect).
Viewport OutputViewport(const Image& image, double scale, int width, int height) {
  if (image.width == 0 || image.height == 0) throw py::value_error("sdvi: the image has no size");
  Viewport vp;
  if (width > 0 || height > 0) {
    if (width < 0 || height < 0) throw py::value_error("sdvi: width and height must be >= 0");
    if (width == 0) width = std::max(1, int(std::lround(double(height) * image.width / image.height)));
    if (height == 0) height = std::max(1, int(std::lround(double(width) * image.height / image.width)));
    vp.width = width, vp.height = height;
    vp.scale_x = double(width) / image.width, vp.scale_y = double(height) / image.height;
  } else {
    if (!(scale > 0) || scale > 65536) throw py::value_error("sdvi: scale must be in (0, 65536]");
    vp.scale_x = vp.scale_y = scale;
    vp.width = int(std::min(1e9, std::max(1.0, std::round(image.width * scale))));
    vp.height = int(std::min(1e9, std::max(1.0, std::round(image.height * scale))));
  }
  return vp;
}

// render(source, output=None, ...) -> float32 (H, W, 4) array, or None when output (a PNG)
// is written.
py::object RenderPy(const ImageSource& source, std::optional<std::string> output, double scale, int width,
                    int height, int levels, int threads, int bits) {
  if (bits != 8 && bits != 16) throw py::value_error("sdvi: bits must be 8 or 16");
  const Image image = LoadImageSource(source);
  RenderOptions options;
  options.viewport = OutputViewport(image, scale, width, height);
  options.levels = levels;
  options.threads = std::max(0, threads);
  Raster raster;
  {
    py::gil_scoped_release release;
    // The file holds what `sdvi render` writes: an 8-bit PNG from the 8-bit render, only the
    // channels needed (RGB stays RGB).
    if (output && bits == 8) {
      Check(SaveRasterPng(*output, WithNeededChannels(Take(Render8(image, options)))));
    } else {
      raster = Take(Render(image, options));
      if (output) Check(SaveRasterPng(*output, WithNeededChannels(raster), bits));
    }
  }
  if (output) return py::none();
  return ArrayFromRaster(raster);
}

// compress(source, output, ...) -> bytes written: a Draco payload as `sdvi compress` writes it.
size_t CompressPy(const ImageSource& source, const std::string& output, int position_bits, int color_bits,
                  int speed, double reference_mse, std::optional<Source> reference, int threads) {
  if (position_bits < 0 || position_bits > 30 || color_bits < 0 || color_bits > 30 || speed < 0 || speed > 10 ||
      !(reference_mse >= 0)) {
    throw py::value_error("sdvi: position_bits and color_bits take 0..30, speed 0..10, reference_mse >= 0");
  }
  if (reference && (position_bits != 0 || color_bits != 0 || speed != 0 || reference_mse != 0))
    throw py::value_error("sdvi: reference excludes position_bits, color_bits, speed and reference_mse");
  const std::string name = std::holds_alternative<std::string>(source) ? std::get<std::string>(source) : "image";
  const Image image = LoadImageSource(source);
  std::optional<Raster> raster;
  if (reference) raster = LoadSource(*reference);
  py::gil_scoped_release release;
  std::vector<uint8_t> bytes;
  if (raster) {
    // The rate control of `sdvi compress --reference` (spec/RATE.md 2).
    RateOptions rate;
    rate.threads = threads > 0 ? threads : DefaultThreads();
    StatusOr<RateResult> chosen = CompressImageForRate(image, *raster, rate);
    if (!chosen.ok()) Raise(Status(chosen.status().code(), name + ": " + chosen.status().message()));
    bytes = std::move(chosen->file);
  } else {
    CompressOptions options;
    options.position_bits = position_bits;
    options.color_bits = color_bits;
    options.speed = speed;
    options.reference_mse = reference_mse;
    bytes = Take(EncodeImage(image, &options, name));
  }
  Check(WriteFileAtomic(output, bytes));
  return bytes.size();
}

// A compare input: an array, an image file, a .sdvi file or an Image (rendered at the
// other side's size, as `sdvi compare` does).
using CompareSource = std::variant<Image, std::string, py::array>;

bool IsSdviPath(const std::string& path) {
  if (FileExtension(path) == "sdvi") return true;
  StatusOr<std::vector<uint8_t>> bytes = ReadFileBytes(path);
  return bytes.ok() && bytes->size() >= 8 && std::equal(bytes->begin() + 4, bytes->begin() + 8, "SDVI");
}

py::dict ComparePy(const CompareSource& a, const CompareSource& b, int levels) {
  struct Side {
    std::optional<Image> image;
    Raster raster;
  };
  auto load = [](const CompareSource& s) {
    Side side;
    if (const auto* img = std::get_if<Image>(&s)) {
      side.image = *img;
    } else if (const auto* path = std::get_if<std::string>(&s)) {
      py::gil_scoped_release release;
      if (IsSdviPath(*path)) {
        side.image = Take(ReadImage(*path));
      } else {
        side.raster = Take(LoadRaster(*path));
      }
    } else {
      side.raster = RasterFromArray(std::get<py::array>(s));
    }
    return side;
  };
  Side x = load(a), y = load(b);
  ImageMetrics m;
  {
    py::gil_scoped_release release;
    auto render_at = [&](const Image& image, int w, int h) {
      RenderOptions o;
      o.viewport.width = w, o.viewport.height = h;
      o.viewport.scale_x = double(w) / image.width, o.viewport.scale_y = double(h) / image.height;
      o.levels = levels;
      return Take(Render(image, o));
    };
    if (x.image && !y.image) {
      x.raster = render_at(*x.image, y.raster.width, y.raster.height);
    } else if (x.image) {
      x.raster = render_at(*x.image, int(x.image->width), int(x.image->height));
    }
    if (y.image) y.raster = render_at(*y.image, x.raster.width, x.raster.height);
    m = Take(CompareImages(x.raster, y.raster));
  }
  py::dict d;
  d["psnr_db"] = m.psnr;
  d["mssim"] = m.mssim;
  d["mean_error"] = m.mean_error;
  d["mse"] = m.mse;
  d["pixels"] = m.pixels;
  return d;
}

}  // namespace
}  // namespace sdvi::python

PYBIND11_MODULE(_sdvi, m) {
  using namespace sdvi;
  using namespace sdvi::python;
  namespace py = pybind11;
  m.doc() = "sdvi: images as curvilinear-feature-driven subdivision surfaces";

  py::class_<Image>(m, "Image", "An sdvi image: control mesh in R^5 (x, y, R, G, B) with feature curves.")
      .def_property_readonly("width", [](const Image& i) { return i.width; })
      .def_property_readonly("height", [](const Image& i) { return i.height; })
      .def_property_readonly("vertex_count", [](const Image& i) { return i.vertices.size(); })
      .def_property_readonly("triangle_count", [](const Image& i) { return i.triangles.size(); })
      .def_property_readonly(
          "vertices",
          [](const Image& i) {
            py::array_t<float> a({py::ssize_t(i.vertices.size()), py::ssize_t(5)});
            std::memcpy(a.mutable_data(), i.vertices.data(), i.vertices.size() * sizeof(Vertex));
            return a;
          },
          "(N, 5) float32 copy: x, y (pixels), R, G, B (0..255)")
      .def_property_readonly(
          "triangles",
          [](const Image& i) {
            py::array_t<uint32_t> a({py::ssize_t(i.triangles.size()), py::ssize_t(3)});
            std::memcpy(a.mutable_data(), i.triangles.data(), i.triangles.size() * sizeof(Triangle));
            return a;
          },
          "(M, 3) uint32 copy of the control triangles")
      .def(
          "save",
          [](const Image& i, const std::string& path) {
            py::gil_scoped_release release;
            Check(WriteImage(path, i, nullptr));
          },
          py::arg("path"), "Writes a raw-payload .sdvi file atomically (as `sdvi vectorize` does).");
  static_assert(sizeof(Vertex) == 5 * sizeof(float) && sizeof(Triangle) == 3 * sizeof(uint32_t));

  m.def(
      "load",
      [](const std::string& path) {
        py::gil_scoped_release release;
        return Take(ReadImage(path));
      },
      py::arg("path"), "Reads a .sdvi file (raw or Draco payload).");
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const FileError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    }
  });
  m.def(
      "read_raster",
      [](const std::string& path) {
        Raster raster;
        {
          py::gil_scoped_release release;
          raster = Take(LoadRaster(path));
        }
        return ArrayFromRaster(raster);
      },
      py::arg("path"),
      "Reads an image file as sdvi reads it: float32 (H, W, C), colours 0..255, alpha 0..1.");
  m.def("vectorize", &VectorizePy, py::arg("source"), py::arg("output") = py::none(), py::kw_only(),
        py::arg("mask") = py::none(), py::arg("compression_ratio") = 64.0, py::arg("max_triangles") = 0,
        py::arg("target_psnr") = 0.0, py::arg("iterations") = 8, py::arg("threads") = 0,
        py::arg("compress") = false, py::arg("quality") = -1.0, py::arg("target_bytes") = 0,
        "Vectorizes an image file or array; writes output (.sdvi) when given, exactly as "
        "`sdvi vectorize SOURCE -o OUTPUT` does. Returns (Image, report dict): the image a reader "
        "of the file gets and the report `sdvi vectorize --report` writes (the file's PSNR, MSSIM "
        "and mean error, sizes, timings, history; with a target (quality, target_bytes, "
        "target_psnr) also target_reached and, when missed, target_note).");
  m.def("render", &RenderPy, py::arg("source"), py::arg("output") = py::none(), py::kw_only(),
        py::arg("scale") = 1.0, py::arg("width") = 0, py::arg("height") = 0, py::arg("levels") = -1,
        py::arg("threads") = 0, py::arg("bits") = 8,
        "Renders a .sdvi path or Image: to a PNG when output is given (as `sdvi render`), else "
        "returns a float32 (H, W, 4) array (colours 0..255, alpha 0..1).");
  m.def("compress", &CompressPy, py::arg("source"), py::arg("output"), py::kw_only(),
        py::arg("position_bits") = 0, py::arg("color_bits") = 0, py::arg("speed") = 0,
        py::arg("reference_mse") = 0.0, py::arg("reference") = py::none(), py::arg("threads") = 0,
        "Writes source with a Draco payload, as `sdvi compress`; returns the file size. With "
        "reference (the image file or array source was made from): bits by rate-distortion and "
        "colours refitted, as `sdvi compress --reference`.");
  m.def("compare", &ComparePy, py::arg("a"), py::arg("b"), py::kw_only(), py::arg("levels") = -1,
        "PSNR, MSSIM, mean error between two images (arrays, image files, .sdvi files or Images; "
        "an sdvi image is rendered at the other side's size), as `sdvi compare A B`.");
}
