// SPDX-License-Identifier: GPL-3.0-or-later
// The sdvi subcommands. Each Register* adds one subcommand to the app: its options (with
// meanings and defaults for --help), examples, and a callback that runs it and stores the
// exit code in the Outcome (args.h). Each command lives in its own cmd_*.cpp, next to the
// module it drives.
#pragma once

#include <string>

#include "args.h"

namespace sdvi::cli {

void RegisterVectorize(CLI::App& app, Outcome& outcome);   // cmd_vectorize.cpp: raster -> .sdvi
void RegisterImportSvg(CLI::App& app, Outcome& outcome);   // cmd_import_svg.cpp: SVG -> .sdvi
void RegisterSample(CLI::App& app, Outcome& outcome);      // cmd_vectorize.cpp: the built-in sample image
void RegisterRender(CLI::App& app, Outcome& outcome);      // cmd_render.cpp: .sdvi -> PNG / EXR
void RegisterCompare(CLI::App& app, Outcome& outcome);     // cmd_render.cpp: PSNR, MSSIM, mean error
void RegisterInfo(CLI::App& app, Outcome& outcome);        // cmd_format.cpp: what a .sdvi holds
void RegisterConvert(CLI::App& app, Outcome& outcome);     // cmd_format.cpp: mesh JSON <-> .sdvi
void RegisterSubdivide(CLI::App& app, Outcome& outcome);   // cmd_subdivide.cpp: refined mesh -> PLY
void RegisterExportGltf(CLI::App& app, Outcome& outcome);  // cmd_gltf.cpp: .sdvi -> .glb / .gltf
void RegisterCompress(CLI::App& app, Outcome& outcome);    // cmd_codec.cpp: raw -> Draco payload
void RegisterDecompress(CLI::App& app, Outcome& outcome);  // cmd_codec.cpp: Draco -> raw payload
void RegisterExportPdf(CLI::App& app, Outcome& outcome);   // cmd_pdf.cpp: .sdvi -> PDF (ShadingType 4)
void RegisterExportSvg(CLI::App& app, Outcome& outcome);   // cmd_svg_export.cpp: .sdvi -> SVG 1.1 (flat triangles)
void RegisterEdit(CLI::App& app, Outcome& outcome);        // cmd_edit.cpp: edit a vectorized image

// cmd_edit.cpp: `sdvi info --features`, the feature table (spec/EDIT.md); returns the exit code.
int PrintFeatures(const std::string& input, bool json);

}  // namespace sdvi::cli
