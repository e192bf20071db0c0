// SPDX-License-Identifier: GPL-3.0-or-later
// sdvi edit: apply an edit script and short-flag edits to a .sdvi file (spec/EDIT.md).
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "args.h"
#include "commands.h"
#include "io.h"
#include "sdvi/codec.h"
#include "sdvi/edit.h"
#include "sdvi/edit_script.h"
#include "sdvi/file_util.h"
#include "sdvi/format.h"

namespace sdvi::cli {
namespace {

struct EditArgs {
  std::string input, output, script, transform;
  std::vector<std::string> sharpness, move, recolor;
  bool quiet = false, json = false, repair = false;
};

// The steps of the script, then of the short flags in the order --sharpness, --move,
// --recolor, --transform (each flag's values in the order given). A bad flag value is a
// usage error (*usage set), a bad script a failure.
StatusOr<std::vector<EditStep>> CollectSteps(const EditArgs& a, bool* usage) {
  std::vector<EditStep> steps;
  if (!a.script.empty()) {
    SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> text, ReadFileBytes(a.script));
    const std::string name = IsStdStream(a.script) ? std::string("<stdin>") : a.script;
    SDVI_ASSIGN_OR_RETURN(steps, ParseEditScript(std::string_view(reinterpret_cast<const char*>(text.data()), text.size()), name));
  }
  *usage = true;
  for (const std::string& v : a.sharpness) {
    SDVI_ASSIGN_OR_RETURN(EditStep step, ParseSharpnessFlag(v));
    steps.push_back(std::move(step));
  }
  for (const std::string& v : a.move) {
    SDVI_ASSIGN_OR_RETURN(EditStep step, ParseMoveFlag(v));
    steps.push_back(std::move(step));
  }
  for (const std::string& v : a.recolor) {
    SDVI_ASSIGN_OR_RETURN(EditStep step, ParseRecolorFlag(v));
    steps.push_back(std::move(step));
  }
  if (!a.transform.empty()) {
    SDVI_ASSIGN_OR_RETURN(EditStep step, ParseTransformFlag(a.transform));
    steps.push_back(std::move(step));
  }
  *usage = false;
  return steps;
}

// The Draco settings of the input's payload, so that the output is coded the same way.
StatusOr<CompressOptions> SameDracoSettings(const SdviFile& file, const std::string& source) {
  SDVI_ASSIGN_OR_RETURN(DracoPayloadInfo info, InspectDracoPayload(file.compressed_payload, source));
  CompressOptions options;
  options.position_bits = info.position_bits;
  options.color_bits = info.color_bits;
  options.speed = info.speed;
  options.keep_vertex_order = info.has_vertex_ids;
  options.feature_layer = info.has_feature_layer;
  return options;
}

int Edit(const EditArgs& a) {
  const char* command = "edit";
  if (a.script.empty() && a.sharpness.empty() && a.move.empty() && a.recolor.empty() && a.transform.empty())
    return ReportUsage(command, "nothing to do: give --script FILE or one of --sharpness, --move, --recolor, --transform");
  if (a.json && IsStdStream(a.output)) return ReportUsage(command, "--json and -o - both use standard output");
  if (IsStdStream(a.script) && IsStdStream(a.input))
    return ReportUsage(command, "the input and the script cannot both come from standard input");
  bool usage = false;
  auto steps = CollectSteps(a, &usage);
  if (!steps.ok()) return usage ? ReportUsage(command, steps.status().message()) : ReportError(command, steps.status());

  auto bytes = ReadFileBytes(a.input);
  if (!bytes.ok()) return ReportError(command, bytes.status());
  auto file = DecodeSdvi(*bytes, a.input);
  if (!file.ok()) return ReportError(command, file.status());
  auto image = DecodeImage(*bytes, a.input);
  if (!image.ok()) return ReportError(command, image.status());
  EditOptions options;
  options.repair_folds = a.repair;
  auto edited = ApplyEdits(*image, *steps, options);
  if (!edited.ok()) return ReportError(command, edited.status());

  // Unchanged: the input's bytes (a Draco payload would not re-encode to itself).
  const bool unchanged = *edited == *image;
  std::vector<uint8_t> out;
  if (unchanged) {
    out = std::move(*bytes);
  } else {
    auto encoded = [&]() -> StatusOr<std::vector<uint8_t>> {
      if (file->payload == PayloadKind::kRaw) return EncodeImage(*edited, nullptr, a.output);
      SDVI_ASSIGN_OR_RETURN(CompressOptions options, SameDracoSettings(*file, a.input));
      return EncodeImage(*edited, &options, a.output);
    }();
    if (!encoded.ok()) return ReportError(command, encoded.status());
    out = std::move(*encoded);
  }
  if (Status s = WriteFileAtomic(a.output, out); !s.ok()) return ReportError(command, s);

  size_t moved = 0, recoloured = 0;
  for (size_t i = 0; i < image->vertices.size(); ++i) {
    const Vertex &p = image->vertices[i], &q = edited->vertices[i];
    moved += p.x != q.x || p.y != q.y;
    recoloured += p.r != q.r || p.g != q.g || p.b != q.b;
  }
  const char* payload = file->payload == PayloadKind::kDraco ? "draco" : "raw";
  if (a.json) {
    nlohmann::ordered_json j;
    j["output"] = a.output;
    j["operations"] = steps->size();
    j["vertices_moved"] = moved;
    j["vertices_recoloured"] = recoloured;
    j["unchanged"] = unchanged;
    j["payload"] = payload;
    j["bytes"] = out.size();
    std::printf("%s\n", j.dump(2).c_str());
  } else if (!a.quiet) {
    std::fprintf(SummaryStream(a.output), "%s: %zu operations, %zu vertices moved, %zu recoloured%s (%s payload, %zu bytes)\n",
                 a.output.c_str(), steps->size(), moved, recoloured, unchanged ? ", unchanged: input copied" : "",
                 payload, out.size());
  }
  return kExitOk;
}

}  // namespace

void RegisterEdit(CLI::App& app, Outcome& outcome) {
  auto a = std::make_shared<EditArgs>();
  CLI::App* c = AddCommand(
      app, "edit",
      "edit a vectorized image: move deBoor points, recolour, change sharpness, transform, deform (spec/EDIT.md)",
      {"sdvi edit in.sdvi -o out.sdvi --script edits.json",
       "sdvi edit in.sdvi -o out.sdvi --sharpness 3=1          # pair 3 becomes a sharp edge",
       "sdvi edit in.sdvi -o out.sdvi --move pair:2:4,0 --recolor polyline:7:255,0,0",
       "sdvi edit in.sdvi -o out.sdvi --transform 1,0,10,0,1,-5   # x' = x + 10, y' = y - 5",
       "sdvi info in.sdvi --features                            # the ids to pick from"});
  MarkInput(c, a->input);
  c->add_option("input", a->input, "the .sdvi file (raw or Draco payload; '-' reads standard input)")
      ->required()
      ->type_name("IN.sdvi");
  AddOutput(c, a->output, "the edited .sdvi file, with the input's payload kind");
  MarkInput(c, a->script);
  c->add_option("--script", a->script, "a JSON edit script (spec/EDIT.md; '-' reads standard input); runs first")
      ->type_name("FILE");
  c->add_option("--sharpness", a->sharpness, "set the sharpness of a pair: PAIR=S, S in [0, 1] (repeatable)")
      ->type_name("PAIR=S");
  c->add_option("--move", a->move,
                "translate vertices: SELECTION:DX,DY, SELECTION = all, pair:N, polyline:N or V1,V2,... (repeatable)")
      ->type_name("SEL:DX,DY");
  c->add_option("--recolor", a->recolor, "set the colour of vertices: SELECTION:R,G,B (0..255; repeatable)")
      ->type_name("SEL:R,G,B");
  c->add_option("--transform", a->transform, "affine map of every vertex: x' = A x + B y + C, y' = D x + E y + F")
      ->type_name("A,B,C,D,E,F");
  c->add_flag("--repair", a->repair,
              "re-triangulate folds by edge flips instead of refusing them (spec/EDIT.md, Validity)");
  AddQuiet(c, a->quiet);
  AddJson(c, a->json);
  SetAction(c, outcome, [a] { return Edit(*a); });
}

}  // namespace sdvi::cli

namespace sdvi::cli {

int PrintFeatures(const std::string& input, bool json) {
  auto image = LoadSdvi(input);
  if (!image.ok()) return ReportError("info", image.status());
  const std::vector<FeatureInfo> features = ListFeatures(*image);
  auto name = [](const FeatureInfo& f) { return std::string(f.kind == FeatureKind::kPair ? "P" : "L") + std::to_string(f.id); };
  if (json) {
    nlohmann::ordered_json j;
    j["file"] = input;
    j["width"] = image->width;
    j["height"] = image->height;
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (const FeatureInfo& f : features) {
      nlohmann::ordered_json e;
      e["id"] = f.id;
      e["name"] = name(f);
      e["kind"] = FeatureKindName(f.kind);
      if (f.kind == FeatureKind::kPair) {
        e["first"] = f.first;
        e["second"] = f.second;
      }
      if (f.kind == FeatureKind::kPairSide) e["pair"] = f.pair;
      e["closed"] = f.closed;
      e["sharpness"] = f.sharpness >= 0 ? nlohmann::ordered_json(f.sharpness) : nlohmann::ordered_json(nullptr);
      e["length"] = f.length;
      e["bbox"] = {f.box.min_x, f.box.min_y, f.box.max_x, f.box.max_y};
      e["vertex_count"] = f.vertex_count;
      if (f.kind != FeatureKind::kPair) {
        nlohmann::ordered_json points = nlohmann::ordered_json::array();
        for (uint32_t v : image->polylines[f.id].vertices)
          points.push_back({v, image->vertices[v].x, image->vertices[v].y});
        e["deboor_points"] = std::move(points);
      }
      list.push_back(std::move(e));
    }
    j["features"] = std::move(list);
    std::printf("%s\n", j.dump(2).c_str());
    return kExitOk;
  }
  std::printf("%s: %zu pairs, %zu polylines (ids for sdvi edit: P<n> = pair n, L<n> = polyline n)\n", input.c_str(),
              image->pairs.size(), image->polylines.size());
  std::printf("%-7s %-10s %-11s %9s  %-31s %8s\n", "id", "kind", "sharpness", "length", "bbox (x0, y0, x1, y1)", "vertices");
  for (const FeatureInfo& f : features) {
    char sharp[32] = "-";
    if (f.kind == FeatureKind::kPair) std::snprintf(sharp, sizeof sharp, "%.3f", f.sharpness);
    if (f.kind == FeatureKind::kPairSide) std::snprintf(sharp, sizeof sharp, "%.3f P%lld", f.sharpness, (long long)f.pair);
    char box[64];
    std::snprintf(box, sizeof box, "%.1f, %.1f, %.1f, %.1f", f.box.min_x, f.box.min_y, f.box.max_x, f.box.max_y);
    std::printf("%-7s %-10s %-11s %9.1f  %-31s %8u%s\n", name(f).c_str(), FeatureKindName(f.kind), sharp, f.length, box,
                f.vertex_count, f.closed ? " closed" : "");
  }
  return kExitOk;
}

}  // namespace sdvi::cli
