// SPDX-License-Identifier: GPL-3.0-or-later
// Hostile and malformed SVG input (spec/SVG.md, "Safety"): each is refused with its own
// SvgError and StatusCode, the message names the input and the rule, the process stays
// under 500 MB, and the command writes no output file. Inputs are generated here.
#include <catch2/catch.hpp>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "sdvi/svg.h"

namespace {

using sdvi::StatusCode;
using sdvi::SvgError;

const char* kHeader = "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\" "
                      "width=\"64\" height=\"64\">";

std::string Svg(const std::string& body) { return std::string(kHeader) + body + "</svg>"; }

struct Outcome {
  sdvi::Status status;
  SvgError error = SvgError::kNone;
  double seconds = 0;
};

Outcome Load(const std::string& bytes, const sdvi::SvgLimits& limits = {}) {
  Outcome o;
  const auto start = std::chrono::steady_clock::now();
  auto document = sdvi::LoadSvg(bytes, "hostile.svg", limits, &o.error);
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  o.status = document.status();
  return o;
}

long PeakMegabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024;
}

void ExpectRefused(const Outcome& o, SvgError error, StatusCode code, const std::string& names) {
  INFO(o.status.ToString() << " in " << o.seconds << " s, peak " << PeakMegabytes() << " MB");
  CHECK(o.error == error);
  CHECK(o.status.code() == code);
  CHECK(o.status.message().find("hostile.svg") != std::string::npos);
  CHECK(o.status.message().find(names) != std::string::npos);
  CHECK(PeakMegabytes() < 500);
}

std::string BillionLaughs() {
  std::string s = "<?xml version=\"1.0\"?>\n<!DOCTYPE svg [\n<!ENTITY lol \"lol\">\n";
  for (int i = 1; i <= 9; ++i) {
    s += "<!ENTITY lol" + std::to_string(i) + " \"";
    for (int k = 0; k < 10; ++k) s += "&lol" + (i == 1 ? std::string() : std::to_string(i - 1)) + ";";
    s += "\">\n";
  }
  s += "]>\n" + Svg("<text x=\"0\" y=\"20\">&lol9;</text>");
  return s;
}

std::string ExternalEntity(const std::string& file) {
  return "<?xml version=\"1.0\"?>\n<!DOCTYPE svg [<!ENTITY secret SYSTEM \"file://" + file + "\">]>\n" +
         Svg("<text x=\"0\" y=\"20\">&secret;</text>");
}

std::string XInclude() {
  return std::string("<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xi=\"http://www.w3.org/2001/XInclude\" "
                     "width=\"64\" height=\"64\"><xi:include href=\"/etc/passwd\" parse=\"text\"/></svg>");
}

std::string ManyElements(size_t n) {
  std::string body;
  body.reserve(n * 5);
  for (size_t i = 0; i < n; ++i) body += "<g/>";
  return Svg(body);
}

std::string NestedGroups(int n) {
  std::string body;
  for (int i = 0; i < n; ++i) body += "<g>";
  body += "<rect width=\"1\" height=\"1\"/>";
  for (int i = 0; i < n; ++i) body += "</g>";
  return Svg(body);
}

std::string LongPath(size_t commands) {
  std::string d = "M0 0";
  d.reserve(commands * 3 + 8);
  for (size_t i = 1; i < commands; ++i) d += (i % 2) ? "h1" : "v1";
  return Svg("<path d=\"" + d + "\"/>");
}

// Runs `sdvi import-svg` on bytes; returns the exit code; *wrote says whether the output
// appeared.
int RunCommand(const std::string& bytes, const std::string& tag, bool* wrote) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("sdvi_svg_test_" + std::to_string(getpid()) + "_" + tag);
  std::filesystem::create_directories(dir);
  const std::filesystem::path in = dir / "in.svg", out = dir / "out.sdvi";
  {
    std::ofstream f(in, std::ios::binary);
    f << bytes;
  }
  const std::string command = std::string(SDVI_CLI_PATH) + " import-svg '" + in.string() + "' -o '" +
                              out.string() + "' --quiet 2>/dev/null";
  const int status = std::system(command.c_str());
  *wrote = std::filesystem::exists(out);
  std::filesystem::remove_all(dir);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST_CASE("svg: billion laughs is refused before any entity is expanded", "[svg][hostile]") {
  ExpectRefused(Load(BillionLaughs()), SvgError::kEntityDeclaration, StatusCode::kUnsupportedFormat, "entit");
}

TEST_CASE("svg: an external entity naming a local file is refused and never read", "[svg][hostile]") {
  const std::filesystem::path secret = std::filesystem::temp_directory_path() / "sdvi_svg_secret.txt";
  {
    std::ofstream f(secret);
    f << "SECRET";
  }
  const Outcome o = Load(ExternalEntity(secret.string()));
  std::filesystem::remove(secret);
  ExpectRefused(o, SvgError::kExternalEntity, StatusCode::kUnsupportedFormat, "external entit");
  CHECK(o.status.message().find("SECRET") == std::string::npos);
}

TEST_CASE("svg: XInclude is refused", "[svg][hostile]") {
  ExpectRefused(Load(XInclude()), SvgError::kXInclude, StatusCode::kUnsupportedFormat, "XInclude");
}

TEST_CASE("svg: 10^6 elements exceed max_elements", "[svg][hostile]") {
  ExpectRefused(Load(ManyElements(1000000)), SvgError::kTooManyElements, StatusCode::kLimitExceeded,
                "max_elements");
}

TEST_CASE("svg: 10^4 nested groups exceed max_depth", "[svg][hostile]") {
  ExpectRefused(Load(NestedGroups(10000)), SvgError::kTooDeep, StatusCode::kLimitExceeded, "max_depth");
}

TEST_CASE("svg: a path of 10^7 commands exceeds max_path_commands", "[svg][hostile]") {
  ExpectRefused(Load(LongPath(10000000)), SvgError::kTooManyPathCommands, StatusCode::kLimitExceeded,
                "max_path_commands");
}

TEST_CASE("svg: width 10^9 exceeds max_dimension when the size is chosen", "[svg][hostile]") {
  const std::string bytes = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"1000000000\" height=\"10\">"
                            "<rect width=\"5\" height=\"5\"/></svg>";
  SvgError error = SvgError::kNone;
  auto document = sdvi::LoadSvg(bytes, "hostile.svg", {}, &error);
  REQUIRE(document.ok());
  auto size = sdvi::ChooseSvgSize(*document, 0, 0, {}, &error);
  REQUIRE_FALSE(size.ok());
  CHECK(error == SvgError::kSizeTooLarge);
  CHECK(size.status().code() == StatusCode::kLimitExceeded);
  CHECK(size.status().message().find("max_dimension") != std::string::npos);
  // An explicit output width brings it back within the limits.
  auto small = sdvi::ChooseSvgSize(*document, 1000, 0, {}, &error);
  REQUIRE(small.ok());
  CHECK(small->width == 1000);
  CHECK(small->height == 1);  // 10 * 1000 / 1e9, at least one pixel
}

TEST_CASE("svg: a use that references itself is a cycle", "[svg][hostile]") {
  ExpectRefused(Load(Svg("<g id=\"a\"><use xlink:href=\"#a\"/></g>")), SvgError::kUseCycle, StatusCode::kCorrupt,
                "references itself");
  ExpectRefused(Load(Svg("<use id=\"u\" href=\"#u\"/>")), SvgError::kUseCycle, StatusCode::kCorrupt,
                "references itself");
  // Two uses referencing each other through groups.
  ExpectRefused(Load(Svg("<g id=\"p\"><use href=\"#q\"/></g><g id=\"q\"><use href=\"#p\"/></g>")),
                SvgError::kUseCycle, StatusCode::kCorrupt, "references itself");
}

TEST_CASE("svg: exponential use expansion exceeds max_use_expansion", "[svg][hostile]") {
  // Each level holds ten uses of the one below: 10^8 elements once expanded.
  std::string body = "<defs><rect id=\"l0\" width=\"1\" height=\"1\"/>";
  for (int i = 1; i <= 8; ++i) {
    body += "<g id=\"l" + std::to_string(i) + "\">";
    for (int k = 0; k < 10; ++k) body += "<use href=\"#l" + std::to_string(i - 1) + "\"/>";
    body += "</g>";
  }
  body += "</defs><use href=\"#l8\"/>";
  ExpectRefused(Load(Svg(body)), SvgError::kUseExpansion, StatusCode::kLimitExceeded, "max_use_expansion");
}

TEST_CASE("svg: malformed XML is a decode error with a line", "[svg][hostile]") {
  ExpectRefused(Load(Svg("<g><rect width=\"1\" height=\"1\"></g>")), SvgError::kMalformedXml,
                StatusCode::kDecodeFailed, "line");
  ExpectRefused(Load("not xml at all"), SvgError::kMalformedXml, StatusCode::kDecodeFailed, "hostile.svg");
  ExpectRefused(Load("<html xmlns=\"http://www.w3.org/1999/xhtml\"/>"), SvgError::kMalformedXml,
                StatusCode::kDecodeFailed, "not <svg>");
  ExpectRefused(Load(""), SvgError::kMalformedXml, StatusCode::kDecodeFailed, "empty");
}

TEST_CASE("svg: bad path data is refused with the place", "[svg][hostile]") {
  ExpectRefused(Load(Svg("<path d=\"M 10 10 L 20\"/>")), SvgError::kBadPathData, StatusCode::kDecodeFailed,
                "expects 2 numbers");
  ExpectRefused(Load(Svg("<path d=\"L 10 10\"/>")), SvgError::kBadPathData, StatusCode::kDecodeFailed,
                "moveto");
  ExpectRefused(Load(Svg("<path d=\"M 0 0 X 1 1\"/>")), SvgError::kBadPathData, StatusCode::kDecodeFailed,
                "unknown command");
  ExpectRefused(Load(Svg("<path d=\"M0 0 A 5 5 0 2 0 10 10\"/>")), SvgError::kBadPathData,
                StatusCode::kDecodeFailed, "'A' expects 7");
  ExpectRefused(Load(Svg("<polygon points=\"0 0 10\"/>")), SvgError::kBadPathData, StatusCode::kDecodeFailed,
                "odd count");
}

TEST_CASE("svg: a file over max_bytes is refused before it is read", "[svg][hostile]") {
  sdvi::SvgLimits limits;
  limits.max_bytes = 100;
  ExpectRefused(Load(Svg(std::string(200, ' ')), limits), SvgError::kFileTooLarge, StatusCode::kLimitExceeded,
                "max_bytes");
}

// A closed path reaching x = 1.6e49 (cairo clamps it to its fixed-point range, about 6e6 px
// in device space), stroked, optionally dashed.
std::string FarPath(const std::string& dash) {
  return Svg("<path d=\"M10 10 L1.6e49 30 L30 60z\" fill=\"red\" stroke=\"black\" stroke-width=\"3\"" +
             (dash.empty() ? std::string() : " stroke-dasharray=\"" + dash + "\"") + "/>");
}

TEST_CASE("svg: dashes over max_dashes are refused before librsvg draws them", "[svg][hostile]") {
  // 2 x 6.25e6 px of dashed outline with a 4 px period: about 3e6 dashes.
  const std::string bytes = FarPath("2 2");
  SvgError error = SvgError::kNone;
  auto document = sdvi::LoadSvg(bytes, "hostile.svg", {}, &error);
  REQUIRE(document.ok());
  CHECK(document->shortest_dash == 4);
  CHECK(document->traced.find("dasharray") == std::string::npos);
  const auto start = std::chrono::steady_clock::now();
  Outcome o;
  auto raster = sdvi::RenderSvg(*document, 64, 64);
  o.status = raster.status();
  o.error = o.status.message().find("[too_many_dashes]") != std::string::npos ? SvgError::kTooManyDashes
                                                                               : SvgError::kNone;
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ExpectRefused(o, SvgError::kTooManyDashes, StatusCode::kLimitExceeded, "max_dashes");
  sdvi::SvgArtworkOptions options;
  auto artwork = sdvi::ImportSvgArtwork(*document, options, &error);
  REQUIRE_FALSE(artwork.ok());
  CHECK(error == SvgError::kTooManyDashes);
  CHECK(PeakMegabytes() < 500);

  // The same dashes hidden in a <style> rule with !important, and a tiny period in a
  // style attribute: the estimate counts every stroke with the shortest dash anywhere.
  for (const std::string& hidden :
       {Svg("<style>path { stroke-dasharray: 0.01 !important }</style>"
            "<path d=\"M10 10 L4e6 30\" stroke=\"black\" fill=\"none\"/>"),
        Svg("<g style=\"stroke-dasharray:1em\"><path d=\"M10 10 L4e6 30\" stroke=\"black\"/></g>"),
        Svg("<style>path { stroke-dash<!-- split -->arr<![CDATA[ay: 0.02 ]]>}</style>"
            "<path d=\"M10 10 L4e6 30\" stroke=\"black\" fill=\"none\"/>")}) {
    error = SvgError::kNone;
    auto hidden_document = sdvi::LoadSvg(hidden, "hostile.svg", {}, &error);
    REQUIRE(hidden_document.ok());
    CHECK(hidden_document->shortest_dash > 0);
    CHECK(hidden_document->traced.find("dasharray") == std::string::npos);
    auto refused = sdvi::ImportSvgArtwork(*hidden_document, options, &error);
    REQUIRE_FALSE(refused.ok());
    CHECK(error == SvgError::kTooManyDashes);
    CHECK(refused.status().message().find("hostile.svg") != std::string::npos);
    CHECK(PeakMegabytes() < 500);
  }
}

TEST_CASE("svg: the dash estimate counts a squashed stroke's length in user units", "[svg][hostile]") {
  // 6e7 user units of dashed outline squashed to 60 px (1.2e8 dashes, seconds in cairo):
  // sqrt |det| (1.5e-3) would estimate 8e4 dashes; the smaller scale (1e-6) gives 1.2e8.
  sdvi::SvgArtworkOptions options;
  for (const std::string& squash : {std::string("scale(2.2,0.000001)"), std::string("matrix(0,0.000001,2.2,0,0,0)"),
                                    std::string("rotate(30) scale(1,0.000001) rotate(-30)")}) {
    SvgError error = SvgError::kNone;
    auto document = sdvi::LoadSvg(Svg("<g transform=\"" + squash + "\"><path d=\"M0 0 L20 0 L20 60000000\" "
                                      "fill=\"none\" stroke=\"black\" stroke-width=\"3\" stroke-dasharray=\"0.5 0.5\"/></g>"
                                      "<rect x=\"10\" y=\"10\" width=\"20\" height=\"20\" fill=\"blue\"/>"),
                                  "squashed.svg", {}, &error);
    REQUIRE(document.ok());
    const auto start = std::chrono::steady_clock::now();
    auto refused = sdvi::ImportSvgArtwork(*document, options, &error);
    INFO(squash);
    REQUIRE_FALSE(refused.ok());
    CHECK(error == SvgError::kTooManyDashes);
    CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < 5);
  }
  // Undashed, the same drawing imports.
  SvgError error = SvgError::kNone;
  auto plain = sdvi::LoadSvg(Svg("<g transform=\"scale(2.2,0.000001)\"><path d=\"M0 0 L20 0 L20 60000000\" "
                                 "fill=\"none\" stroke=\"black\" stroke-width=\"3\"/></g>"
                                 "<rect x=\"10\" y=\"10\" width=\"20\" height=\"20\" fill=\"blue\"/>"),
                             "plain.svg", {}, &error);
  REQUIRE(plain.ok());
  CHECK(sdvi::ImportSvgArtwork(*plain, options, &error).ok());
}

TEST_CASE("svg: the dash estimate counts dash lengths in user units", "[svg]") {
  auto shortest = [](const std::string& body) {
    auto document = sdvi::LoadSvg(Svg(body), "dash.svg", {});
    REQUIRE(document.ok());
    return document->shortest_dash;
  };
  CHECK(shortest("<path d=\"M0 0h9\" stroke=\"red\"/>") == 0);
  CHECK(shortest("<path d=\"M0 0h9\" stroke-dasharray=\"none\"/>") == 0);
  CHECK(shortest("<path d=\"M0 0h9\" stroke-dasharray=\"0 0\"/>") == 0);
  CHECK(shortest("<path d=\"M0 0h9\" stroke-dasharray=\"2 4\"/>") == 6);
  // An odd list repeats: 1 2 3 1 2 3 is three pairs of mean 4.
  CHECK(shortest("<path d=\"M0 0h9\" style=\"stroke-dasharray: 1, 2, 3\"/>") == 4);
  CHECK(shortest("<path d=\"M0 0h9\" stroke-dasharray=\"1in\"/>") == 192);
  // The shortest of several, from a <style> element too; relative units count as 1/100.
  CHECK(shortest("<style>.a{stroke-dasharray:5mm 5mm}</style><path class=\"a\" d=\"M0 0h9\" "
                 "stroke-dasharray=\"30 30\"/>") == Approx(2 * 5 * 96 / 25.4));
  CHECK(shortest("<path d=\"M0 0h9\" stroke-dasharray=\"10% 10%\"/>") == Approx(0.2));
}

TEST_CASE("svg: a dashed stroke within max_dashes renders dashed and traces whole", "[svg]") {
  const std::string bytes = Svg("<path d=\"M4 32 H60\" fill=\"none\" stroke=\"black\" stroke-width=\"4\" "
                                "stroke-dasharray=\"8 8\"/>");
  auto document = sdvi::LoadSvg(bytes, "dash.svg", {});
  REQUIRE(document.ok());
  auto raster = sdvi::RenderSvg(*document, 64, 64);
  REQUIRE(raster.ok());
  CHECK(raster->at(8, 32, 3) == Approx(1.0f));   // in the first dash, [4, 12)
  CHECK(raster->at(16, 32, 3) == Approx(0.0f));  // in the first gap, [12, 20)
  auto geometry = sdvi::TraceSvgGeometry(*document, 64, 64);
  REQUIRE(geometry.ok());
  REQUIRE(geometry->shapes.size() == 1);
  CHECK(geometry->shapes[0].outlines[0].points.back().x == Approx(60));
  CHECK(geometry->dashes == Approx(56.0 / 16.0));
}

TEST_CASE("svg: an outline far outside the canvas costs what its visible part costs", "[svg][hostile]") {
  // Without dashes the far path is valid: the samples are taken within the raster and a
  // margin only, so the import stays small.
  auto document = sdvi::LoadSvg(FarPath(""), "far.svg", {});
  REQUIRE(document.ok());
  sdvi::SvgArtworkOptions options;
  auto result = sdvi::ImportSvgArtwork(*document, options);
  REQUIRE(result.ok());
  CHECK(result->outline_features > 0);
  CHECK(PeakMegabytes() < 500);
  // max_outline_samples bounds what is left: a limit below the visible outline is refused.
  options.limits.max_outline_samples = 100;
  SvgError error = SvgError::kNone;
  auto refused = sdvi::ImportSvgArtwork(*document, options, &error);
  REQUIRE_FALSE(refused.ok());
  CHECK(error == SvgError::kTooManyOutlineSamples);
  CHECK(refused.status().code() == StatusCode::kLimitExceeded);
  CHECK(refused.status().message().find("far.svg") != std::string::npos);
  CHECK(refused.status().message().find("max_outline_samples") != std::string::npos);
}

TEST_CASE("svg: CSS escapes, @import and stylesheets in data: URLs are refused", "[svg][hostile]") {
  ExpectRefused(Load(Svg("<path d=\"M0 0h9\" style=\"stroke-d\\61sharray:1\"/>")), SvgError::kUnsafeCss,
                StatusCode::kUnsupportedFormat, "CSS escape");
  ExpectRefused(Load(Svg("<style>path{stroke-d\\61sharray:1}</style>")), SvgError::kUnsafeCss,
                StatusCode::kUnsupportedFormat, "CSS escape");
  ExpectRefused(Load(Svg("<style>@import url(other.css);</style>")), SvgError::kUnsafeCss,
                StatusCode::kUnsupportedFormat, "@import");
  ExpectRefused(Load("<?xml-stylesheet type=\"text/css\" href=\"data:text/css,path{fill:red}\"?>" + Svg("")),
                SvgError::kUnsafeCss, StatusCode::kUnsupportedFormat, "xml-stylesheet");
}

TEST_CASE("svg: data: URLs other than raster images are refused", "[svg][hostile]") {
  ExpectRefused(Load(Svg("<image width=\"9\" height=\"9\" href=\"data:image/svg+xml;base64,PHN2Zy8+\"/>")),
                SvgError::kNestedDocument, StatusCode::kUnsupportedFormat, "data: URL");
  ExpectRefused(Load(Svg("<rect width=\"9\" height=\"9\" fill=\"url(data:image/svg+xml,x#a)\"/>")),
                SvgError::kNestedDocument, StatusCode::kUnsupportedFormat, "data: URL");
  ExpectRefused(Load(Svg("<style>@font-face{src:url(data:font/woff,AAAA)}</style>")), SvgError::kNestedDocument,
                StatusCode::kUnsupportedFormat, "data: URL");
  // A PNG in a data: URL is an image librsvg decodes itself: accepted.
  auto ok = sdvi::LoadSvg(Svg("<image width=\"9\" height=\"9\" xlink:href=\"data:image/png;base64,iVBORw0KGgo=\"/>"),
                          "ok.svg", {});
  CHECK(ok.ok());
}

TEST_CASE("svg: an embedded image declaring a huge size is refused before it is decoded", "[svg][hostile]") {
  // A PNG (written for this test) whose header declares 20000 x 20000 grey pixels: decoding
  // it would take 400 MB (1.6 GB as librsvg's RGBA); the size is read from the header.
  const std::string huge = "iVBORw0KGgoAAAANSUhEUgAATiAAAE4gCAAAAADGGxnlAAAAPUlEQVR4nO3BMQEAAADCoPVP7WkJoAAAAAAAAAAAAAAAAAAAAA"
                           "AAAAAAAAAAAAAAAAAAAAAAAAAAAAAAgBucQgABievriwAAAABJRU5ErkJggg==";
  ExpectRefused(Load(Svg("<image width=\"9\" height=\"9\" href=\"data:image/png;base64," + huge + "\"/>")),
                SvgError::kSizeTooLarge, StatusCode::kLimitExceeded, "max_dimension");
  // The same header at 2 x 2 passes, and librsvg draws it.
  const std::string small = "iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAAAAABX3VL4AAAAC0lEQVR4nGNgAAEAAAYAAf6MZ8gAAAAASUVORK5CYII=";
  auto ok = sdvi::LoadSvg(Svg("<image width=\"64\" height=\"64\" href=\"data:image/png;base64," + small + "\"/>"),
                          "ok.svg", {});
  REQUIRE(ok.ok());
  auto raster = sdvi::RenderSvg(*ok, 64, 64);
  REQUIRE(raster.ok());
  CHECK(raster->at(32, 32, 3) == Approx(1.0f));
}

TEST_CASE("svg: valid path data of every command passes the check", "[svg]") {
  const std::string d = "M10,10 L20 20 H30 V40 C 1 2 3 4 5 6 S 1 2 3 4 Q 1 2 3 4 T 5 6 A 5 5 30 1 0 15 15 "
                        "a5,5,0,0,1,1,1 m 1 1 l 1 1 2 2 h 1 v 1 c 1 2 3 4 5 6 s 1 2 3 4 q 1 2 3 4 t 1 1 z "
                        "M.5.5l-1e2+3E-1 a1 1 0 1010 10";
  SvgError error = SvgError::kNone;
  auto document = sdvi::LoadSvg(Svg("<path d=\"" + d + "\"/><polyline points=\"1,2 3,4\"/>"), "ok.svg", {}, &error);
  INFO(document.status().ToString());
  CHECK(document.ok());
  CHECK(error == SvgError::kNone);
}

TEST_CASE("svg: the command refuses hostile files without writing output", "[svg][hostile][cli]") {
  const std::pair<const char*, std::string> cases[] = {
      {"laughs", BillionLaughs()},
      {"entity", ExternalEntity("/etc/hostname")},
      {"xinclude", XInclude()},
      {"elements", ManyElements(1000000)},
      {"nesting", NestedGroups(10000)},
      {"path", LongPath(10000000)},
      {"width", "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"1e9\" height=\"1e9\"><rect width=\"5\" "
                "height=\"5\"/></svg>"},
      {"use", Svg("<g id=\"a\"><use href=\"#a\"/></g>")},
      {"malformed", Svg("<g>")},
      {"pathdata", Svg("<path d=\"M 0 0 L\"/>")},
      {"dashes", FarPath("2 2")},
      {"css", Svg("<path d=\"M0 0h9\" style=\"stroke-d\\61sharray:1\"/>")},
      {"nested", Svg("<image width=\"9\" height=\"9\" href=\"data:image/svg+xml;base64,PHN2Zy8+\"/>")},
      {"image", Svg("<image width=\"9\" height=\"9\" href=\"data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAATiAAAE4g"
                    "CAAAAADGGxnlAAAAPUlEQVR4nO3BMQEAAADCoPVP7WkJoAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAgBuc"
                    "QgABievriwAAAABJRU5ErkJggg==\"/>")},
  };
  for (const auto& [tag, bytes] : cases) {
    bool wrote = true;
    const int code = RunCommand(bytes, tag, &wrote);
    INFO(tag);
    CHECK(code == 1);  // a failure (README "Exit codes"), not a usage error
    CHECK_FALSE(wrote);
  }
}
