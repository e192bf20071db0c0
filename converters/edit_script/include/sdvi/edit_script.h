// SPDX-License-Identifier: GPL-3.0-or-later
// The JSON edit script of `sdvi edit --script` (spec/EDIT.md) and the short flags'
// values, turned into the editor's steps (sdvi/edit.h).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "sdvi/edit.h"
#include "sdvi/status.h"

namespace sdvi {

// Parses a script. Errors (kDecodeFailed for text that is not JSON, with its line and
// column; kInvalidArgument otherwise) name source_name and the key, e.g.
// "edits.json: ops[2].rgb: expected an array of 3 numbers". Ids are checked against an
// image only when the steps run (ApplyEdits names the step then).
StatusOr<std::vector<EditStep>> ParseEditScript(std::string_view text, const std::string& source_name);

// The short flags of `sdvi edit` (spec/EDIT.md), each one step labelled by its flag:
//   --sharpness PAIR=S            set_sharpness
//   --move V1,V2,...:DX,DY        translate those vertices; "pair:ID", "polyline:ID" or "all"
//                                 may stand for the vertex list
//   --recolor SELECTION:R,G,B     set_color (SELECTION as for --move)
//   --transform A,B,C,D,E,F       affine of all vertices, x' = A x + B y + C, y' = D x + E y + F
StatusOr<EditStep> ParseSharpnessFlag(const std::string& value);
StatusOr<EditStep> ParseMoveFlag(const std::string& value);
StatusOr<EditStep> ParseRecolorFlag(const std::string& value);
StatusOr<EditStep> ParseTransformFlag(const std::string& value);

}  // namespace sdvi
