// SPDX-License-Identifier: GPL-3.0-or-later
// sdvi subdivide IN.sdvi --levels r [--limit] -o OUT.ply
// Writes the level-r fine mesh (or its limit surface with --limit) as binary PLY:
// per-vertex x, y, z = 0 (source pixels, y down), colour as uchar red/green/blue
// (rounded, clamped to 0..255) and uchar tag (0 smooth, 1 crease, 2 corner); faces as
// uint index triples in the orientation of their control triangle.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "args.h"
#include "commands.h"
#include "io.h"
#include "sdvi/file_util.h"
#include "sdvi/subdiv.h"

namespace sdvi::cli {
namespace {

void PutU32(std::vector<uint8_t>& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
}
void PutF32(std::vector<uint8_t>& out, float f) {
  uint32_t bits;
  std::memcpy(&bits, &f, 4);
  PutU32(out, bits);
}
uint8_t ColourByte(float c) { return static_cast<uint8_t>(std::lround(std::clamp(c, 0.0f, 255.0f))); }

// The binary little-endian PLY file of mesh.
std::vector<uint8_t> EncodePly(const RefinedMesh& mesh, bool limit) {
  std::string header =
      "ply\nformat binary_little_endian 1.0\n"
      "comment sdvi subdivide: Loop level " + std::to_string(mesh.levels) +
      (limit ? ", limit positions" : ", level positions") +
      "\ncomment x, y in source pixels (y down); tag: 0 smooth, 1 crease, 2 corner\n"
      "element vertex " + std::to_string(mesh.vertices.size()) +
      "\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar tag\n"
      "element face " + std::to_string(mesh.triangles.size()) +
      "\nproperty list uchar uint vertex_indices\nend_header\n";
  std::vector<uint8_t> out(header.begin(), header.end());
  out.reserve(out.size() + 16 * mesh.vertices.size() + 13 * mesh.triangles.size());
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vertex& v = mesh.vertices[i];
    PutF32(out, v.x);
    PutF32(out, v.y);
    PutF32(out, 0.0f);
    out.push_back(ColourByte(v.r));
    out.push_back(ColourByte(v.g));
    out.push_back(ColourByte(v.b));
    out.push_back(static_cast<uint8_t>(mesh.vertex_tags[i]));
  }
  for (const Triangle& t : mesh.triangles) {
    out.push_back(3);
    for (uint32_t v : t.v) PutU32(out, v);
  }
  return out;
}

// The options of `sdvi subdivide`.
struct SubdivideArgs {
  std::string input, output;
  int levels = 2;
  bool limit = false, quiet = false, json = false;
};

int Subdivide(const SubdivideArgs& a) {
  const std::string command = "subdivide";
  if (a.json && IsStdStream(a.output)) return ReportUsage(command, "--json and -o - both use standard output");
  auto image = LoadSdvi(a.input);
  if (!image.ok()) return ReportError(command, image.status());
  LimitSurfaceOptions options;
  options.levels = a.levels;
  options.to_limit = a.limit;
  auto mesh = RefineImage(*image, options);
  if (!mesh.ok()) return ReportError(command, Status(mesh.status().code(), a.input + ": " + mesh.status().message()));
  const Status written = WriteFileAtomic(a.output, EncodePly(*mesh, options.to_limit));
  if (!written.ok()) return ReportError(command, written);
  if (a.json) {
    nlohmann::ordered_json j;
    j["output"] = a.output;
    j["level"] = mesh->levels;
    j["limit"] = a.limit;
    j["vertices"] = mesh->vertices.size();
    j["triangles"] = mesh->triangles.size();
    std::printf("%s\n", j.dump(2).c_str());
  } else if (!a.quiet) {
    std::fprintf(SummaryStream(a.output), "%s: %zu vertices, %zu triangles (level %d%s)\n", a.output.c_str(),
                 mesh->vertices.size(), mesh->triangles.size(), mesh->levels, options.to_limit ? ", limit" : "");
  }
  return kExitOk;
}

}  // namespace

void RegisterSubdivide(CLI::App& app, Outcome& outcome) {
  auto a = std::make_shared<SubdivideArgs>();
  CLI::App* c = AddCommand(
      app, "subdivide", "write the level-r refined mesh (or its limit surface) as binary PLY with colours and tags",
      {"sdvi subdivide in.sdvi --levels 3 -o fine.ply", "sdvi subdivide in.sdvi --levels 2 --limit -o limit.ply"});
  MarkInput(c, a->input);
  c->add_option("input", a->input, "the .sdvi file ('-' reads standard input)")->required()->type_name("IN.sdvi");
  AddOutput(c, a->output, "the PLY file");
  c->add_option("--levels", a->levels, "subdivision level r")->check(CLI::Range(0, 8));
  c->add_flag("--limit", a->limit, "push every vertex to its limit position");
  AddQuiet(c, a->quiet);
  AddJson(c, a->json);
  SetAction(c, outcome, [a] { return Subdivide(*a); });
}

}  // namespace sdvi::cli
