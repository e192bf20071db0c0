// The sdvi subcommands. Each takes its arguments (after the subcommand name) and
// returns the process exit code: 0 success, 1 usage error, 2 failure (see ReportError).
// Each command lives in its own cmd_*.cpp, next to the module it drives.
#pragma once

#include <string>
#include <vector>

namespace sdvi::cli {

using CommandArgs = std::vector<std::string>;

int RunConvert(const CommandArgs& args);      // cmd_format.cpp: mesh JSON <-> .sdvi
int RunInfo(const CommandArgs& args);         // cmd_format.cpp
int RunSubdivide(const CommandArgs& args);    // cmd_subdivide.cpp: refined mesh -> PLY
int RunRender(const CommandArgs& args);       // cmd_render.cpp: .sdvi -> PNG / EXR
int RunCompare(const CommandArgs& args);      // cmd_render.cpp: PSNR, MSSIM, mean error
int RunVectorize(const CommandArgs& args);    // cmd_vectorize.cpp: raster -> .sdvi
int RunExportGltf(const CommandArgs& args);   // cmd_gltf.cpp: .sdvi -> .glb / .gltf
int RunCompress(const CommandArgs& args);     // cmd_codec.cpp: raw -> Draco payload
int RunDecompress(const CommandArgs& args);   // cmd_codec.cpp: Draco -> raw payload
int RunSample(const CommandArgs& args);       // cmd_vectorize.cpp: writes the built-in sample image
int RunImportSvg(const CommandArgs& args);    // cmd_import_svg.cpp: SVG -> .sdvi

}  // namespace sdvi::cli
