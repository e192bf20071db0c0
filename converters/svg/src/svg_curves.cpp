// SPDX-License-Identifier: GPL-3.0-or-later
// Curves mode (spec/CURVES.md section 2): the sdvi curve attributes of a checked document
// become a CurveDrawing for engine/create. Geometry: each curve element is given an id (when
// it has none) and a plain black stroke, and librsvg draws that element alone
// (rsvg_handle_render_layer) into a cairo script surface at the output viewport, so every
// transform, the viewBox and the shapes' own directions are librsvg's. Colours: SVG colour
// syntax through Pango's parser (CSS colour names, #rgb, #rrggbb) and rgb(...) here.
#include <libxml/parser.h>
#include <libxml/tree.h>
#include <pango/pango.h>

#include <cairo-script.h>
#include <cairo.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <set>
#include <string>
#include <vector>

#include "svg_internal.h"
#include "svg_rsvg.h"

namespace sdvi {
namespace {

constexpr const char* kCurvesNamespace = "https://sdvi.dev/ns/curves/1";

std::string Trim(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

// A number, or a percentage (divided by 100) when percent_ok; false when malformed.
bool ParseNumber(const std::string& text, double* value, bool percent_ok) {
  const std::string t = Trim(text);
  if (t.empty()) return false;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (end == t.c_str() || !std::isfinite(v)) return false;
  std::string rest(end);
  if (rest.empty()) {
    *value = v;
    return true;
  }
  if (percent_ok && rest == "%") {
    *value = v / 100.0;
    return true;
  }
  return false;
}

// SVG colour: #rgb, #rrggbb, a CSS colour keyword (Pango), rgb(R, G, B) with integers
// 0..255 or percentages.
bool ParseColor(const std::string& text, CurveColor* color) {
  const std::string t = Trim(text);
  if (t.rfind("rgb(", 0) == 0 && t.back() == ')') {
    std::string inner = t.substr(4, t.size() - 5);
    double v[3];
    size_t start = 0;
    for (int k = 0; k < 3; ++k) {
      const size_t comma = k < 2 ? inner.find(',', start) : inner.size();
      if (comma == std::string::npos) return false;
      std::string part = Trim(inner.substr(start, comma - start));
      const bool percent = !part.empty() && part.back() == '%';
      if (!ParseNumber(part, &v[k], true)) return false;
      v[k] = percent ? v[k] * 255.0 : v[k];
      if (!(v[k] >= 0 && v[k] <= 255)) return false;
      start = comma + 1;
    }
    *color = {float(v[0]), float(v[1]), float(v[2])};
    return true;
  }
  if (t.empty() || t == "none" || t == "currentColor" || t.rfind("url(", 0) == 0) return false;
  PangoColor c;
  if (!pango_color_parse(&c, t.c_str())) return false;
  *color = {float(c.red / 257.0), float(c.green / 257.0), float(c.blue / 257.0)};
  return true;
}

// "COLOR" or "OFFSET COLOR; OFFSET COLOR; ..." (spec/CURVES.md).
bool ParseColorList(const std::string& text, std::vector<CurveColorStop>* stops, std::string* what) {
  CurveColor single;
  if (ParseColor(text, &single)) {
    stops->push_back({0.0, single});
    return true;
  }
  size_t start = 0;
  double previous = 0;
  while (start <= text.size()) {
    size_t end = text.find(';', start);
    if (end == std::string::npos) end = text.size();
    const std::string item = Trim(text.substr(start, end - start));
    start = end + 1;
    if (item.empty()) {
      if (end == text.size()) break;
      *what = "empty colour stop";
      return false;
    }
    size_t space = 0;
    while (space < item.size() && !std::isspace(static_cast<unsigned char>(item[space]))) ++space;
    CurveColorStop stop;
    if (!ParseNumber(item.substr(0, space), &stop.offset, true) || stop.offset < 0 || stop.offset > 1) {
      *what = "stop \"" + item + "\": the offset must be a number in [0, 1] or a percentage";
      return false;
    }
    if (!stops->empty() && stop.offset < previous) {
      *what = "stop \"" + item + "\": offsets must not decrease";
      return false;
    }
    if (!ParseColor(item.substr(space), &stop.color)) {
      *what = "stop \"" + item + "\": not an SVG colour";
      return false;
    }
    previous = stop.offset;
    stops->push_back(stop);
  }
  if (stops->empty()) {
    *what = "no colour";
    return false;
  }
  return true;
}

std::string Prop(xmlNodePtr node, const char* name, const char* ns = nullptr) {
  xmlChar* v = ns != nullptr ? xmlGetNsProp(node, reinterpret_cast<const xmlChar*>(name),
                                            reinterpret_cast<const xmlChar*>(ns))
                             : xmlGetProp(node, reinterpret_cast<const xmlChar*>(name));
  if (v == nullptr) return "";
  std::string s(reinterpret_cast<const char*>(v));
  xmlFree(v);
  return s;
}

bool HasProp(xmlNodePtr node, const char* name, const char* ns) {
  return xmlHasNsProp(node, reinterpret_cast<const xmlChar*>(name), reinterpret_cast<const xmlChar*>(ns)) != nullptr;
}

bool IsShape(const std::string& name) {
  return name == "path" || name == "line" || name == "polyline" || name == "polygon" || name == "rect" ||
         name == "circle" || name == "ellipse";
}

struct CurveElement {
  std::string id;     // the id librsvg draws it by
  std::string label;  // for messages: <path id="x"> or <path> (line N)
  std::vector<CurveColorStop> left, right;
  float sharpness = 1;
};

struct Collector {
  std::vector<CurveElement> curves;
  std::vector<std::string> warnings;
  std::set<std::string> ids;
  int next_id = 0;
  std::string error;

  void Visit(xmlNodePtr node) {
    for (xmlNodePtr child = node->children; child != nullptr && error.empty(); child = child->next) {
      if (child->type != XML_ELEMENT_NODE) continue;
      const std::string name = reinterpret_cast<const char*>(child->name);
      if (name == "defs" || name == "symbol" || name == "clipPath" || name == "mask" || name == "pattern" ||
          name == "marker" || Prop(child, "display") == "none") {
        continue;
      }
      if (IsShape(name)) {
        Shape(child, name);
      } else {
        Visit(child);
      }
    }
  }

  void Shape(xmlNodePtr node, const std::string& name) {
    const std::string id = Prop(node, "id");
    const std::string label = "<" + name + (id.empty() ? "" : " id=\"" + id + "\"") + "> (line " +
                              std::to_string(xmlGetLineNo(node)) + ")";
    const bool has_left = HasProp(node, "left-color", kCurvesNamespace);
    const bool has_right = HasProp(node, "right-color", kCurvesNamespace);
    if (!has_left && !has_right) {
      warnings.push_back("skipped " + label + ": no sdvi:left-color or sdvi:right-color");
      return;
    }
    CurveElement curve;
    curve.label = label;
    std::string what;
    if (has_left && !ParseColorList(Prop(node, "left-color", kCurvesNamespace), &curve.left, &what)) {
      error = label + " sdvi:left-color: " + what;
      return;
    }
    if (has_right && !ParseColorList(Prop(node, "right-color", kCurvesNamespace), &curve.right, &what)) {
      error = label + " sdvi:right-color: " + what;
      return;
    }
    if (!has_left) curve.left = curve.right;
    if (!has_right) curve.right = curve.left;
    if (HasProp(node, "sharpness", kCurvesNamespace)) {
      double s = 0;
      if (!ParseNumber(Prop(node, "sharpness", kCurvesNamespace), &s, false) || s < 0 || s > 1) {
        error = label + " sdvi:sharpness: not a number in [0, 1]";
        return;
      }
      curve.sharpness = float(s);
    }
    curve.id = id;
    if (curve.id.empty()) {
      do {
        curve.id = "sdvi-curve-" + std::to_string(next_id++);
      } while (ids.count(curve.id) > 0);
      xmlSetProp(node, reinterpret_cast<const xmlChar*>("id"), reinterpret_cast<const xmlChar*>(curve.id.c_str()));
    }
    ids.insert(curve.id);
    // Drawn as a plain stroke so that librsvg emits the path whatever its paint (a fill of a
    // zero-area path, such as a straight line, fails on the script surface).
    const std::string style = Prop(node, "style") + ";fill:none;stroke:#000;stroke-width:1;stroke-opacity:1;"
                                                    "stroke-dasharray:none;opacity:1;visibility:visible";
    xmlSetProp(node, reinterpret_cast<const xmlChar*>("style"), reinterpret_cast<const xmlChar*>(style.c_str()));
    curves.push_back(std::move(curve));
  }
};

void CollectIds(xmlNodePtr node, std::set<std::string>* ids) {
  for (xmlNodePtr c = node; c != nullptr; c = c->next) {
    if (c->type != XML_ELEMENT_NODE) continue;
    const std::string id = Prop(c, "id");
    if (!id.empty()) ids->insert(id);
    CollectIds(c->children, ids);
  }
}

}  // namespace

StatusOr<SvgCurvesResult> ImportSvgCurves(const SvgDocument& document, const SvgCurvesOptions& options,
                                          SvgError* error) {
  SDVI_ASSIGN_OR_RETURN(SvgSize size, ChooseSvgSize(document, options.width, options.scale, options.limits, error));
  // The document passed CheckSvg (no entities, within the limits): a tree is safe to build.
  xmlDocPtr doc = xmlReadMemory(document.bytes.data(), int(document.bytes.size()), nullptr, nullptr,
                                XML_PARSE_NONET | XML_PARSE_NOWARNING | XML_PARSE_NOERROR | XML_PARSE_HUGE);
  if (doc == nullptr) return SvgFailure(SvgError::kMalformedXml, document.name, "libxml2 cannot read it", error);
  RemoveDashes(doc);  // curves are traced without dashes (spec/SVG.md, "Dashes")
  Collector collector;
  CollectIds(xmlDocGetRootElement(doc), &collector.ids);
  collector.Visit(reinterpret_cast<xmlNodePtr>(doc));
  if (!collector.error.empty()) {
    xmlFreeDoc(doc);
    return SvgFailure(SvgError::kBadCurveAttribute, document.name, collector.error, error);
  }
  xmlChar* dumped = nullptr;
  int dumped_size = 0;
  xmlDocDumpMemory(doc, &dumped, &dumped_size);
  xmlFreeDoc(doc);
  if (dumped == nullptr) return Status(StatusCode::kInternal, document.name + ": cannot serialise the tree");
  SvgDocument marked = document;
  marked.bytes.assign(reinterpret_cast<const char*>(dumped), size_t(dumped_size));
  marked.traced.clear();
  marked.shortest_dash = 0;
  xmlFree(dumped);
  if (collector.curves.empty()) {
    return SvgFailure(SvgError::kNoCurves, document.name,
                      "no element carries sdvi:left-color or sdvi:right-color (spec/CURVES.md)", error);
  }

  SDVI_ASSIGN_OR_RETURN(RsvgHandlePtr handle, OpenRsvg(marked, error));
  CurveDrawing drawing;
  drawing.width = size.width;
  drawing.height = size.height;
  SvgCurvesResult result;
  result.warnings = document.warnings;
  result.warnings.insert(result.warnings.end(), collector.warnings.begin(), collector.warnings.end());
  for (const CurveElement& element : collector.curves) {
    std::string script;
    cairo_device_t* device = cairo_script_create_for_stream(AppendScript, &script);
    cairo_script_set_mode(device, CAIRO_SCRIPT_MODE_ASCII);
    cairo_surface_t* surface =
        cairo_script_surface_create(device, CAIRO_CONTENT_COLOR_ALPHA, size.width, size.height);
    cairo_t* cr = cairo_create(surface);
    RsvgRectangle viewport{0, 0, double(size.width), double(size.height)};
    GError* gerror = nullptr;
    const std::string target = "#" + element.id;
    const bool drawn = rsvg_handle_render_layer(handle.get(), cr, target.c_str(), &viewport, &gerror);
    cairo_destroy(cr);
    cairo_surface_finish(surface);
    cairo_surface_destroy(surface);
    cairo_device_finish(device);
    cairo_device_destroy(device);
    if (!drawn) {
      std::string what = gerror != nullptr ? gerror->message : "unknown error";
      if (gerror != nullptr) g_error_free(gerror);
      return SvgFailure(SvgError::kRenderFailed, document.name, element.label + ": librsvg cannot draw it: " + what,
                        error);
    }
    const std::vector<SvgShape> shapes = ReadCairoScript(script);
    size_t subpaths = 0;
    for (const SvgShape& shape : shapes) {
      if (shape.paint != SvgPaint::kStroke) continue;
      for (const SvgOutline& outline : shape.outlines) {
        ColoredCurve curve;
        curve.start = outline.points[0];
        for (size_t k = 1; k + 2 < outline.points.size(); k += 3) {
          curve.segments.push_back({outline.points[k], outline.points[k + 1], outline.points[k + 2]});
        }
        curve.closed = outline.closed;
        curve.left = element.left;
        curve.right = element.right;
        curve.sharpness = element.sharpness;
        curve.name = element.label + (subpaths > 0 ? " subpath " + std::to_string(subpaths + 1) : "");
        drawing.curves.push_back(std::move(curve));
        ++subpaths;
      }
    }
    if (subpaths == 0) result.warnings.push_back(element.label + " draws no path (empty or zero size): skipped");
  }
  result.curves = drawing.curves.size();
  StatusOr<Image> image = CreateFromCurves(drawing, options.create);
  if (!image.ok()) return Status(image.status().code(), document.name + ": " + image.status().message());
  result.image = std::move(image).value();
  result.width = size.width;
  result.height = size.height;
  return result;
}

}  // namespace sdvi
