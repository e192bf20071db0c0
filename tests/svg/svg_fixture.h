// SPDX-License-Identifier: GPL-3.0-or-later
// What the SVG tests share: a document from bytes written in the test, and the two views the
// artwork import starts from (spec/SVG.md section 1), librsvg's raster and the traced outlines,
// at one size. A failure to load, render or trace ends the test case with the status's text.
#pragma once

#include <catch2/catch.hpp>

#include <string>
#include <utility>

#include "sdvi/svg.h"

namespace {

sdvi::SvgDocument Doc(const std::string& bytes) {
  auto document = sdvi::LoadSvg(bytes, "test.svg", {});
  INFO(document.status().ToString());
  REQUIRE(document.ok());
  return std::move(*document);
}

sdvi::SvgGeometry Traced(const sdvi::SvgDocument& doc, int width, int height) {
  auto traced = sdvi::TraceSvgGeometry(doc, width, height);
  INFO(traced.status().ToString());
  REQUIRE(traced.ok());
  return std::move(*traced);
}

struct RenderedSvg {
  sdvi::Raster reference;  // librsvg's drawing
  sdvi::SvgGeometry traced;
};

RenderedSvg RenderAndTrace(const sdvi::SvgDocument& doc, int width, int height) {
  auto reference = sdvi::RenderSvg(doc, width, height);
  INFO(reference.status().ToString());
  REQUIRE(reference.ok());
  return {std::move(*reference), Traced(doc, width, height)};
}

}  // namespace
