// SPDX-License-Identifier: GPL-3.0-or-later
// The report of a vectorized file (sdvi/rate.h): one list of fields for `sdvi vectorize
// --report` and the Python binding.
#include <nlohmann/json.hpp>

#include "sdvi/rate.h"

namespace sdvi {
namespace {

nlohmann::json RateChoices(const RateResult& c) {
  return {{"position_bits", c.position_bits},     {"color_bits", c.color_bits},
          {"colors_refitted", c.colors_refitted}, {"mended_vertices", c.mended_vertices},
          {"colors_decorrelated", c.colors_decorrelated}, {"slope_db", c.slope_db},
          {"candidates", c.evaluations}};
}

}  // namespace

std::string RateChoicesJson(const RateResult& choices, int indent) { return RateChoices(choices).dump(indent); }

std::string VectorizedFileReportJson(const VectorizedFile& made, const std::string& input, const std::string& output,
                                     int indent) {
  const VectorizeReport& r = made.vectorized.report;
  const VectorizeTimings& s = r.seconds;
  nlohmann::json history = nlohmann::json::array();
  for (const VectorizeIteration& it : r.history) {
    history.push_back({{"vertices", it.vertices},
                       {"triangles", it.triangles},
                       {"added_samples", it.added_samples},
                       {"psnr_db", it.psnr},
                       {"time_s", it.seconds.total}});
  }
  nlohmann::json report = {{"input", input},
                           {"output", output},
                           {"width", made.decoded.width},
                           {"height", made.decoded.height},
                           {"time_s", s.total + s.load},
                           {"iterations", r.iterations},
                           {"triangles", r.triangles},
                           {"vertices", r.vertices},
                           {"paper_size_bytes", r.paper_size},
                           {"file_size_bytes", made.bytes.size()},
                           {"pixels", r.pixels},
                           {"mean_error", r.mean_error},
                           {"compression_ratio", r.compression_ratio},
                           {"psnr_db", r.psnr},
                           {"mssim", r.mssim},
                           {"mssim_channels", "mean over R, G, B"},
                           {"feature_curves", r.feature_curves},
                           {"phases_s",
                            {{"load", s.load},
                             {"features", s.features},
                             {"triangulate", s.triangulate},
                             {"flips", s.flips},
                             {"limit_surface", s.surface},
                             {"coverage", s.coverage},
                             {"assemble", s.assemble},
                             {"solve", s.solve},
                             {"refine", s.refine},
                             {"metrics", s.metrics}}},
                           {"history", history},
                           {"fit_psnr_db", r.fit_psnr}};
  if (made.compressed) {
    nlohmann::json rate = RateChoices(made.choices);
    if (made.targeted) rate["vectorize_runs"] = made.vectorize_runs;
    report["rate"] = rate;
  }
  if (made.targeted) {
    report["target_reached"] = made.reached;
    if (!made.reached) report["target_note"] = made.note;
  }
  return report.dump(indent);
}

}  // namespace sdvi
