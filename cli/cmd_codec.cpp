// SPDX-License-Identifier: GPL-3.0-or-later
// sdvi compress (raw -> Draco payload) and sdvi decompress (any payload -> raw).
#include <cstdio>
#include <map>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "args.h"
#include "commands.h"
#include "sdvi/codec.h"
#include "sdvi/file_util.h"
#include "sdvi/format.h"
#include "sdvi/parallel.h"
#include "sdvi/raster_io.h"
#include "sdvi/rate.h"
#include "sdvi/render.h"

namespace sdvi::cli {
namespace {

// The options of `sdvi compress` and `sdvi decompress`.
struct CodecArgs {
  std::string input, output, reference;
  CompressOptions options;
  int threads = 1;
  bool quiet = false, json = false;
};

int Compress(CodecArgs& a) {
  const char* command = "compress";
  if (a.json && IsStdStream(a.output)) return ReportUsage(command, "--json and -o - both use standard output");
  CompressOptions& options = a.options;
  auto image = ReadImage(a.input);
  if (!image.ok()) return ReportError(command, image.status());
  // With the original image: the rate control of `vectorize --compress` (spec/RATE.md 2, 3).
  std::optional<RateResult> rate;
  if (!a.reference.empty()) {
    auto reference = LoadRaster(a.reference);
    if (!reference.ok()) return ReportError(command, reference.status());
    RateOptions rate_options;
    rate_options.threads = a.threads;
    auto chosen = CompressImageForRate(*image, *reference, rate_options);
    if (!chosen.ok()) return ReportError(command, Status(chosen.status().code(), a.reference + ": " + chosen.status().message()));
    rate = std::move(chosen).value();
  }
  auto bytes = rate ? StatusOr<std::vector<uint8_t>>(std::move(rate->file)) : EncodeImage(*image, &options, a.input);
  if (!bytes.ok()) return ReportError(command, bytes.status());
  const uint64_t paper = PaperSizeBytes(image->vertices.size(), image->triangles.size());
  const double pixels = double(image->width) * double(image->height);
  // The bits the file holds (the writer may raise default position bits, spec/FORMAT.md 8.2).
  auto written = DecodeSdvi(*bytes, a.output);
  if (!written.ok()) return ReportError(command, written.status());
  auto payload = InspectDracoPayload(written->compressed_payload, a.output);
  if (!payload.ok()) return ReportError(command, payload.status());
  const int position_bits = payload->position_bits, color_bits = payload->color_bits;
  if (Status s = WriteFileAtomic(a.output, *bytes); !s.ok()) return ReportError(command, s);
  const double bpp = pixels > 0 ? 8.0 * double(bytes->size()) / pixels : 0.0;
  if (a.json) {
    nlohmann::ordered_json j;
    j["output"] = a.output;
    j["vertices"] = image->vertices.size();
    j["triangles"] = image->triangles.size();
    j["bytes"] = bytes->size();
    j["paper_size_bytes"] = paper;
    j["bits_per_pixel"] = bpp;
    j["position_bits"] = position_bits;
    j["color_bits"] = color_bits;
    if (rate) {
      j["psnr_db"] = rate->psnr;
      j["rate"] = nlohmann::json::parse(RateChoicesJson(*rate, -1));
    }
    std::printf("%s\n", j.dump(2).c_str());
  } else if (!a.quiet) {
    std::fprintf(SummaryStream(a.output),
                 "%s: %zu vertices, %zu triangles: %zu bytes (paper raw size %llu, ratio %.3f, "
                 "%.3f bits/pixel, %.2f bytes/vertex; position bits %d, colour bits %d)\n",
                 a.output.c_str(), image->vertices.size(), image->triangles.size(), bytes->size(),
                 static_cast<unsigned long long>(paper), double(bytes->size()) / double(paper), bpp,
                 double(bytes->size()) / double(image->vertices.size()), position_bits, color_bits);
    if (rate) std::fprintf(SummaryStream(a.output), "%s: PSNR %.2f dB against %s\n", a.output.c_str(), rate->psnr, a.reference.c_str());
  }
  return kExitOk;
}

int Decompress(const CodecArgs& a) {
  auto image = ReadImage(a.input);
  if (!image.ok()) return ReportError("decompress", image.status());
  if (Status s = WriteImage(a.output, *image, nullptr); !s.ok()) return ReportError("decompress", s);
  return kExitOk;
}

}  // namespace

void RegisterCompress(CLI::App& app, Outcome& outcome) {
  auto a = std::make_shared<CodecArgs>();
  a->threads = DefaultThreads();
  CompressOptions& o = a->options;
  CLI::App* c = AddCommand(
      app, "compress", "re-encode a .sdvi with a Draco payload (quantised positions and colours, edgebreaker)",
      {"sdvi compress in.sdvi -o small.sdvi",
       "sdvi compress in.sdvi -o small.sdvi --reference original.png   # the bits by rate-distortion, colours refitted",
       "sdvi compress in.sdvi -o small.sdvi --position-bits 14 --color-bits 8 --speed 0",
       "sdvi compress in.sdvi -o small.sdvi --colors smallest   # decorrelated colours where smaller",
       "sdvi compress raw/ -O small/ -j 2   # every .sdvi in raw/"});
  AddOutput(c, a->output, "the compressed .sdvi file");
  AddInputs(c, a->input, "the .sdvi file (any payload; '-' reads standard input)", {{"sdvi"}, "sdvi", "", {}});
  MarkInput(c, a->reference);
  UsesRasterCodecs(c, &a->reference);
  auto* reference = c->add_option("--reference", a->reference,
                                  "the image the .sdvi was made from: bits chosen by rate-distortion and colours refitted "
                                  "on the quantised positions, the file `vectorize --compress` writes (spec/RATE.md)")
                        ->type_name("IMG");
  c->add_option("--threads", a->threads, "worker threads of --reference's rate control")->check(CLI::Range(1, 256));
  c->add_option("--position-bits", o.position_bits, "quantisation bits for x, y (0: automatic)")
      ->check(CLI::Range(0, 30))->excludes(reference);
  c->add_option("--color-bits", o.color_bits, "quantisation bits for R, G, B (0: automatic)")
      ->check(CLI::Range(0, 30))->excludes(reference);
  c->add_option("--speed", o.speed, "Draco speed: 0 smallest file .. 10 fastest")->check(CLI::Range(0, 10))->excludes(reference);
  c->add_option("--colors", o.color_coding,
                "how colours are coded: rgb (R, G, B), decorrelated (L, C1, C2: smaller on most photos), smallest "
                "(both, decorrelated predicted by the decoded neighbours' mean, and positions and colours predicted so in the tag "
                "stream: the smallest file) (spec/FORMAT.md 8.2, 8.7, 8.8)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, ColorCoding>{{"rgb", ColorCoding::kRgb},
                                                                              {"decorrelated", ColorCoding::kDecorrelated},
                                                                              {"smallest", ColorCoding::kSmallest}}))
      ->default_str("rgb")
      ->excludes(reference);
  c->add_option("--reference-mse", o.reference_mse,
                "the fit's MSE (8-bit units): automatic bits keep the error added to ~1% of it (0: none)")
      ->check(CLI::Range(0.0, 65025.0))
      ->excludes(reference);
  c->add_flag("--keep-vertex-order", o.keep_vertex_order,
              "keep the vertex numbering (sequential coding, larger) instead of Draco's edgebreaker order")
      ->excludes(reference);
  AddQuiet(c, a->quiet);
  AddJson(c, a->json);
  SetAction(c, outcome, [a] { return Compress(*a); });
}

void RegisterDecompress(CLI::App& app, Outcome& outcome) {
  auto a = std::make_shared<CodecArgs>();
  CLI::App* c = AddCommand(app, "decompress", "re-encode a .sdvi with the raw payload",
                           {"sdvi decompress small.sdvi -o raw.sdvi", "sdvi decompress small/ -O raw/ -j 2"});
  AddOutput(c, a->output, "the raw-payload .sdvi file");
  AddInputs(c, a->input, "the .sdvi file (any payload; '-' reads standard input)", {{"sdvi"}, "sdvi", "", {}});
  AddQuiet(c, a->quiet);
  SetAction(c, outcome, [a] { return Decompress(*a); });
}

}  // namespace sdvi::cli
