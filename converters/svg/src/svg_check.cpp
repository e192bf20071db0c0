// SPDX-License-Identifier: GPL-3.0-or-later
// CheckSvg: the one pass over the XML before librsvg sees it (spec/SVG.md, "Safety").
// libxml2's SAX2 parser with XML_PARSE_NONET and without XML_PARSE_NOENT /
// XML_PARSE_DTDLOAD / XML_PARSE_XINCLUDE: no network, no external DTD or entity is read,
// no entity is substituted, XInclude is never processed (and refused when present); the
// first entity declaration or reference stops the parse.
#include "svg_internal.h"

#include <libxml/parser.h>
#include <libxml/SAX2.h>
#include <libxml/parserInternals.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

namespace sdvi {
namespace {

constexpr const char* kXIncludeNamespace = "http://www.w3.org/2001/XInclude";
constexpr const char* kXIncludeNamespace2003 = "http://www.w3.org/2003/XInclude";

// Elements whose rendering has no exact features in the artwork mode. Text is not among
// them: librsvg draws it as the glyphs' outlines, which are traced like any fill.
// A pattern's tiles are copied over what it fills (spec/SVG.md section 1, "Patterns"); where
// they cannot be, the trace says so (SvgGeometry::patterns_not_copied).
bool IsApproximated(std::string_view name) {
  static const char* const kNames[] = {"filter", "mask", "image", "foreignObject", "meshgradient", "feImage"};
  for (const char* n : kNames) {
    if (name == n) return true;
  }
  return false;
}

struct Node {
  int parent = -1;
  std::string use_target;  // id referenced by a <use>, without '#'
};

std::string Str(const xmlChar* s) { return s != nullptr ? reinterpret_cast<const char*>(s) : ""; }

// Elements drawn after expanding every <use> (each use adds its target's subtree), capped
// at cap + 1; -1 when a use reaches itself.
int64_t ExpandedSize(const std::vector<Node>& nodes, const std::unordered_map<std::string, int>& ids,
                     uint64_t cap, int* cycle_node) {
  const int n = int(nodes.size());
  std::vector<std::vector<int>> deps(n);
  for (int i = 0; i < n; ++i) {
    if (nodes[i].parent >= 0) deps[nodes[i].parent].push_back(i);
    if (!nodes[i].use_target.empty()) {
      auto it = ids.find(nodes[i].use_target);
      if (it != ids.end()) deps[i].push_back(it->second);
    }
  }
  std::vector<uint8_t> state(n, 0);  // 0 new, 1 on the stack, 2 done
  std::vector<uint64_t> size(n, 0);
  for (int root = 0; root < n; ++root) {
    if (state[root] != 0) continue;
    std::vector<std::pair<int, size_t>> stack{{root, 0}};
    state[root] = 1;
    while (!stack.empty()) {
      auto& [node, next] = stack.back();
      if (next < deps[node].size()) {
        const int d = deps[node][next++];
        if (state[d] == 1) {
          *cycle_node = node;
          return -1;
        }
        if (state[d] == 0) {
          state[d] = 1;
          stack.push_back({d, 0});
        }
        continue;
      }
      uint64_t s = 1;
      for (int d : deps[node]) s = std::min(cap + 1, s + size[d]);
      size[node] = s;
      state[node] = 2;
      stack.pop_back();
    }
  }
  return n > 0 ? int64_t(size[0]) : 0;
}

}  // namespace

Status SvgFailure(SvgError code, const std::string& name, const std::string& what, SvgError* out) {
  if (out != nullptr) *out = code;
  StatusCode status = StatusCode::kDecodeFailed;
  switch (code) {
    case SvgError::kFileTooLarge:
    case SvgError::kTooManyElements:
    case SvgError::kTooDeep:
    case SvgError::kTooManyPathCommands:
    case SvgError::kUseExpansion:
    case SvgError::kSizeTooLarge:
    case SvgError::kTooManyDashes:
    case SvgError::kTooManyOutlineSamples:
      status = StatusCode::kLimitExceeded;
      break;
    case SvgError::kUseCycle:
      status = StatusCode::kCorrupt;
      break;
    case SvgError::kEntityDeclaration:
    case SvgError::kExternalEntity:
    case SvgError::kXInclude:
    case SvgError::kUnsafeCss:
    case SvgError::kNestedDocument:
      status = StatusCode::kUnsupportedFormat;
      break;
    case SvgError::kNoSize:
    case SvgError::kBadCurveAttribute:
      status = StatusCode::kInvalidArgument;
      break;
    case SvgError::kNoCurves:
      status = StatusCode::kEmptyInput;
      break;
    default:
      break;
  }
  return Status(status, name + ": " + what + " [" + std::string(SvgErrorName(code)) + "]");
}

std::string_view SvgErrorName(SvgError error) {
  switch (error) {
    case SvgError::kNone: return "none";
    case SvgError::kFileTooLarge: return "file_too_large";
    case SvgError::kTooManyElements: return "too_many_elements";
    case SvgError::kTooDeep: return "too_deep";
    case SvgError::kTooManyPathCommands: return "too_many_path_commands";
    case SvgError::kUseExpansion: return "use_expansion";
    case SvgError::kUseCycle: return "use_cycle";
    case SvgError::kEntityDeclaration: return "entity_declaration";
    case SvgError::kExternalEntity: return "external_entity";
    case SvgError::kXInclude: return "xinclude";
    case SvgError::kMalformedXml: return "malformed_xml";
    case SvgError::kBadPathData: return "bad_path_data";
    case SvgError::kSizeTooLarge: return "size_too_large";
    case SvgError::kNoSize: return "no_size";
    case SvgError::kRenderFailed: return "render_failed";
    case SvgError::kBadCurveAttribute: return "bad_curve_attribute";
    case SvgError::kNoCurves: return "no_curves";
    case SvgError::kTooManyDashes: return "too_many_dashes";
    case SvgError::kTooManyOutlineSamples: return "too_many_outline_samples";
    case SvgError::kUnsafeCss: return "unsafe_css";
    case SvgError::kNestedDocument: return "nested_document";
  }
  return "unknown";
}

namespace {

// Position of the first case-insensitive occurrence of needle (lower case) at or after from.
size_t FindNoCase(std::string_view text, std::string_view needle, size_t from = 0) {
  if (needle.size() > text.size()) return std::string_view::npos;
  for (size_t i = from; i + needle.size() <= text.size(); ++i) {
    size_t k = 0;
    while (k < needle.size() && std::tolower(static_cast<unsigned char>(text[i + k])) == needle[k]) ++k;
    if (k == needle.size()) return i;
  }
  return std::string_view::npos;
}

// User units per unit of a dash length; relative units (em, ex, %, ...) count as 1/100 of
// a user unit so that the dash estimate stays an upper bound (spec/SVG.md, "Dashes").
double UnitFactor(std::string_view unit) {
  std::string u;
  for (char c : unit) u += char(std::tolower(static_cast<unsigned char>(c)));
  if (u.empty() || u == "px") return 1;
  if (u == "in") return 96;
  if (u == "cm") return 96 / 2.54;
  if (u == "mm") return 96 / 25.4;
  if (u == "q") return 96 / 101.6;
  if (u == "pt") return 96.0 / 72;
  if (u == "pc") return 16;
  return 0.01;
}

}  // namespace

double MeanDashPair(std::string_view value) {
  std::vector<double> lengths;
  size_t i = 0;
  while (i < value.size()) {
    const char c = value[i];
    const bool starts = (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+';
    if (!starts) {
      ++i;
      continue;
    }
    size_t end = i + 1;
    while (end < value.size() && (std::isdigit(static_cast<unsigned char>(value[end])) || value[end] == '.' ||
                                  ((value[end] == 'e' || value[end] == 'E') && end + 1 < value.size() &&
                                   (std::isdigit(static_cast<unsigned char>(value[end + 1])) ||
                                    value[end + 1] == '-' || value[end + 1] == '+')) ||
                                  ((value[end] == '-' || value[end] == '+') &&
                                   (value[end - 1] == 'e' || value[end - 1] == 'E')))) {
      ++end;
    }
    const std::string number(value.substr(i, end - i));
    char* parsed = nullptr;
    const double x = std::strtod(number.c_str(), &parsed);
    size_t unit_end = end;
    while (unit_end < value.size() && (std::isalpha(static_cast<unsigned char>(value[unit_end])) ||
                                       value[unit_end] == '%')) {
      ++unit_end;
    }
    if (parsed != number.c_str() && std::isfinite(x)) {
      lengths.push_back(std::abs(x) * UnitFactor(value.substr(end, unit_end - end)));
    }
    i = std::max(unit_end, i + 1);
  }
  double sum = 0;
  for (double l : lengths) sum += l;
  if (lengths.empty() || !(sum > 0)) return 0;
  // An odd list repeats once: n dashes and n gaps either way; the mean pair is 2 sum / n.
  return 2 * sum / double(lengths.size());
}

void RemoveDashes(xmlDocPtr doc) {
  auto rename = [](std::string text) {
    for (size_t at = FindNoCase(text, "dasharray"); at != std::string::npos; at = FindNoCase(text, "dasharray", at)) {
      text[at + 8] = 'x';  // stroke-dasharrax: an unknown property, ignored
    }
    return text;
  };
  std::vector<xmlNodePtr> stack{xmlDocGetRootElement(doc)};
  while (!stack.empty()) {
    xmlNodePtr node = stack.back();
    stack.pop_back();
    if (node == nullptr || node->type != XML_ELEMENT_NODE) continue;
    for (xmlAttrPtr a = node->properties; a != nullptr;) {
      xmlAttrPtr next = a->next;
      const std::string name = Str(a->name);
      if (FindNoCase(name, "dasharray") != std::string::npos) {
        xmlRemoveProp(a);
      } else if (name == "style") {
        xmlChar* v = xmlNodeListGetString(doc, a->children, 1);
        const std::string renamed = rename(Str(v));
        xmlFree(v);
        xmlSetNsProp(node, a->ns, a->name, reinterpret_cast<const xmlChar*>(renamed.c_str()));
      }
      a = next;
    }
    // A <style>'s text is the concatenation of its text and CDATA children (a property name
    // may be split by a comment or a CDATA section): renamed as a whole, kept in the first.
    const bool style = Str(node->name) == "style";
    std::string text;
    xmlNodePtr first_text = nullptr;
    for (xmlNodePtr c = node->children; c != nullptr; c = c->next) {
      if (c->type == XML_ELEMENT_NODE) {
        stack.push_back(c);
      } else if (style && (c->type == XML_TEXT_NODE || c->type == XML_CDATA_SECTION_NODE)) {
        text += Str(c->content);
        if (first_text == nullptr) first_text = c;
        xmlNodeSetContent(c, reinterpret_cast<const xmlChar*>(""));
      }
    }
    if (first_text != nullptr) {
      const std::string renamed = rename(text);
      xmlNodeSetContentLen(first_text, reinterpret_cast<const xmlChar*>(renamed.data()), int(renamed.size()));
    }
  }
}

namespace {

// cairo's script surface fails on the fill of an axis-aligned path without area (and then
// refuses everything after it), so the traced document fills no shape without area.
void UnfillFlatShapes(xmlNodePtr root) {
  std::vector<xmlNodePtr> stack{root};
  while (!stack.empty()) {
    xmlNodePtr node = stack.back();
    stack.pop_back();
    if (node == nullptr || node->type != XML_ELEMENT_NODE) continue;
    for (xmlNodePtr c = node->children; c != nullptr; c = c->next) {
      if (c->type == XML_ELEMENT_NODE) stack.push_back(c);
    }
    const std::string name = Str(node->name);
    bool flat = name == "line";
    if (name == "path" || name == "polyline" || name == "polygon") {
      xmlChar* v = xmlGetProp(node, reinterpret_cast<const xmlChar*>(name == "path" ? "d" : "points"));
      if (v != nullptr) {
        flat = name == "path" ? PathIsFlat(Str(v)) : PointsAreFlat(Str(v));
        xmlFree(v);
      }
    }
    if (!flat) continue;
    xmlChar* style = xmlGetProp(node, reinterpret_cast<const xmlChar*>("style"));
    const std::string unfilled = Str(style) + ";fill:none !important";
    if (style != nullptr) xmlFree(style);
    xmlSetProp(node, reinterpret_cast<const xmlChar*>("style"), reinterpret_cast<const xmlChar*>(unfilled.c_str()));
  }
}

}  // namespace

std::string TracedDocument(const std::string& bytes) {
  xmlDocPtr doc = xmlReadMemory(bytes.data(), int(bytes.size()), nullptr, nullptr,
                                XML_PARSE_NONET | XML_PARSE_NOWARNING | XML_PARSE_NOERROR | XML_PARSE_HUGE);
  if (doc == nullptr) return std::string();
  RemoveDashes(doc);
  UnfillFlatShapes(xmlDocGetRootElement(doc));
  xmlChar* dumped = nullptr;
  int size = 0;
  xmlDocDumpMemory(doc, &dumped, &size);
  xmlFreeDoc(doc);
  if (dumped == nullptr) return std::string();
  std::string out(reinterpret_cast<const char*>(dumped), size_t(size));
  xmlFree(dumped);
  return out;
}

namespace {

// State of the SAX pass; the first failure stops the parser.
struct CheckState {
  const std::string* name = nullptr;
  const SvgLimits* limits = nullptr;
  SvgCheck* check = nullptr;
  xmlParserCtxtPtr parser = nullptr;
  SvgError error = SvgError::kNone;
  std::string what;
  std::string first_error;  // libxml2's first error message
  int first_error_line = 0;
  std::vector<Node> nodes;
  std::vector<int> open;  // the open elements, outermost first
  std::unordered_map<std::string, int> ids;
  size_t path_commands = 0;
  bool saw_root = false;
  bool in_style = false;   // inside a <style> element
  std::string style_text;  // its text so far

  int Line() const { return parser != nullptr ? xmlSAX2GetLineNumber(parser) : 0; }
  void Fail(SvgError code, const std::string& message) {
    if (error != SvgError::kNone) return;
    error = code;
    what = message;
    xmlStopParser(parser);
  }
};

CheckState* StateOf(void* ctx) { return static_cast<CheckState*>(ctx); }

// CSS (a style attribute or a <style> element): escapes and @import are refused, since they
// could hide a property or a resource from these checks; every stroke-dasharray is noted.
void CheckCss(CheckState* st, std::string_view css, const std::string& where) {
  if (css.find('\\') != std::string_view::npos) {
    return st->Fail(SvgError::kUnsafeCss, where + ": a CSS escape (backslash); CSS escapes are not accepted");
  }
  if (FindNoCase(css, "@import") != std::string_view::npos) {
    return st->Fail(SvgError::kUnsafeCss, where + ": CSS @import is not accepted");
  }
  // The value runs to the next ';', '}' or '!' (comments and all: numbers in them only make
  // the estimate more cautious).
  for (size_t at = FindNoCase(css, "dasharray"); at != std::string_view::npos;
       at = FindNoCase(css, "dasharray", at + 1)) {
    const size_t end = css.find_first_of(";}!", at + 9);
    const double pair = MeanDashPair(css.substr(at + 9, end == std::string_view::npos ? end : end - at - 9));
    if (pair > 0 && (st->check->shortest_dash == 0 || pair < st->check->shortest_dash)) {
      st->check->shortest_dash = pair;
    }
  }
}

// A data: URL may only be an href to a PNG, JPEG, GIF or WebP image: any other (an SVG
// document, a stylesheet, a font) would be loaded by librsvg without these checks.
bool AllowedDataUrl(const std::string& attr, std::string_view value) {
  size_t b = 0;
  while (b < value.size() && (value[b] == ' ' || value[b] == '\t' || value[b] == '\n' || value[b] == '\r')) ++b;
  if (attr != "href" || FindNoCase(value, "data:") != b) return false;
  for (const char* type : {"image/png", "image/jpeg", "image/jpg", "image/gif", "image/webp"}) {
    const std::string_view t(type);
    const size_t at = b + 5;
    if (FindNoCase(value.substr(at, t.size()), t) == 0 && at + t.size() < value.size() &&
        (value[at + t.size()] == ';' || value[at + t.size()] == ',')) {
      // One data: URL only.
      return FindNoCase(value, "data:", at) == std::string_view::npos;
    }
  }
  return false;
}

void OnCharacters(void* ctx, const xmlChar* text, int length) {
  CheckState* st = StateOf(ctx);
  if (st->in_style && st->error == SvgError::kNone) st->style_text.append(reinterpret_cast<const char*>(text), size_t(length));
}

void OnProcessingInstruction(void* ctx, const xmlChar* target, const xmlChar* data) {
  CheckState* st = StateOf(ctx);
  if (Str(target) != "xml-stylesheet") return;
  if (FindNoCase(Str(data), "data:") != std::string::npos) {
    return st->Fail(SvgError::kUnsafeCss, "line " + std::to_string(st->Line()) +
                                              ": an xml-stylesheet with a data: URL is not accepted");
  }
  st->check->warnings.push_back("line " + std::to_string(st->Line()) +
                                ": the xml-stylesheet is not loaded (no external files)");
}

void OnEntityDecl(void* ctx, const xmlChar*, int type, const xmlChar*, const xmlChar*, xmlChar*) {
  CheckState* st = StateOf(ctx);
  if (type == XML_EXTERNAL_GENERAL_PARSED_ENTITY || type == XML_EXTERNAL_GENERAL_UNPARSED_ENTITY ||
      type == XML_EXTERNAL_PARAMETER_ENTITY) {
    st->Fail(SvgError::kExternalEntity, "line " + std::to_string(st->Line()) +
                                            ": the DOCTYPE declares an external entity; external entities are "
                                            "never read");
  } else {
    st->Fail(SvgError::kEntityDeclaration, "line " + std::to_string(st->Line()) +
                                               ": the DOCTYPE declares entities; entity declarations are not "
                                               "accepted");
  }
}

void OnReference(void* ctx, const xmlChar* name) {
  CheckState* st = StateOf(ctx);
  st->Fail(SvgError::kEntityDeclaration, "line " + std::to_string(st->Line()) + ": entity reference &" + Str(name) +
                                             "; entities are not expanded");
}

xmlEntityPtr OnGetEntity(void* ctx, const xmlChar* name) {
  OnReference(ctx, name);
  return nullptr;
}

void OnError(void* ctx, xmlErrorPtr e) {
  CheckState* st = StateOf(ctx);
  if (e == nullptr || e->level < XML_ERR_ERROR || !st->first_error.empty()) return;
  st->first_error = e->message != nullptr ? e->message : "error";
  while (!st->first_error.empty() && (st->first_error.back() == '\n' || st->first_error.back() == ' ')) {
    st->first_error.pop_back();
  }
  st->first_error_line = e->line;
}

void OnStartElement(void* ctx, const xmlChar* localname, const xmlChar*, const xmlChar* uri, int, const xmlChar**,
                    int nb_attributes, int, const xmlChar** attributes) {
  CheckState* st = StateOf(ctx);
  if (st->error != SvgError::kNone) return;
  const SvgLimits& limits = *st->limits;
  const int line = st->Line();
  const std::string ns = Str(uri), local = Str(localname);
  if (ns == kXIncludeNamespace || ns == kXIncludeNamespace2003) {
    return st->Fail(SvgError::kXInclude,
                    "line " + std::to_string(line) + ": <" + local + "> is XInclude; XInclude is not processed");
  }
  const int depth = int(st->open.size()) + 1;
  if (depth > limits.max_depth) {
    return st->Fail(SvgError::kTooDeep, "line " + std::to_string(line) + ": elements nested " +
                                            std::to_string(depth) + " deep exceed the limit of " +
                                            std::to_string(limits.max_depth) + " (max_depth)");
  }
  if (st->nodes.size() + 1 > limits.max_elements) {
    return st->Fail(SvgError::kTooManyElements,
                    "more than " + std::to_string(limits.max_elements) + " elements (max_elements)");
  }
  if (!st->saw_root) {
    st->saw_root = true;
    if (local != "svg") return st->Fail(SvgError::kMalformedXml, "the root element is <" + local + ">, not <svg>");
  }
  Node node;
  node.parent = st->open.empty() ? -1 : st->open.back();
  const int index = int(st->nodes.size());
  if (local == "line") st->check->flat_shapes = true;
  if (IsApproximated(local)) st->check->unsupported.push_back(local + " (line " + std::to_string(line) + ")");
  size_t commands = 0;
  for (int a = 0; a < nb_attributes; ++a) {
    const xmlChar** at = attributes + 5 * a;  // localname, prefix, URI, value, end
    const std::string attr = Str(at[0]);
    const std::string value(reinterpret_cast<const char*>(at[3]), size_t(at[4] - at[3]));
    std::string bad;
    if (FindNoCase(value, "data:") != std::string::npos) {
      if (!AllowedDataUrl(attr, value)) {
        return st->Fail(SvgError::kNestedDocument,
                        "line " + std::to_string(line) + ": <" + local + "> " + attr +
                            " holds a data: URL that is not a PNG, JPEG, GIF or WebP image; other embedded "
                            "documents are not accepted");
      }
      st->check->images.push_back({line, value});
    }
    if (attr == "style") {
      CheckCss(st, value, "line " + std::to_string(line));
      if (st->error != SvgError::kNone) return;
    } else if (FindNoCase(attr, "dasharray") != std::string::npos) {
      const double pair = MeanDashPair(value);
      if (pair > 0 && (st->check->shortest_dash == 0 || pair < st->check->shortest_dash)) {
        st->check->shortest_dash = pair;
      }
    }
    if (attr == "id") {
      st->ids.emplace(value, index);
    } else if (attr == "href") {
      if (!value.empty() && value[0] == '#') {
        if (local == "use") node.use_target = value.substr(1);
      } else if (value.rfind("data:", 0) != 0) {
        st->check->warnings.push_back("line " + std::to_string(line) + ": <" + local + "> references \"" +
                                      value.substr(0, 80) + "\", which is not loaded (no external files)");
      }
    } else if (attr == "d" && local == "path") {
      if (!CountPathCommands(value, &commands, &bad, limits.max_path_commands)) {
        return st->Fail(SvgError::kBadPathData, "line " + std::to_string(line) + ": bad path data: " + bad);
      }
      if (!st->check->flat_shapes && commands <= limits.max_path_commands) st->check->flat_shapes = PathIsFlat(value);
    } else if (attr == "points" && (local == "polyline" || local == "polygon")) {
      if (!CountPolylinePoints(value, &commands, &bad)) {
        return st->Fail(SvgError::kBadPathData, "line " + std::to_string(line) + ": bad points: " + bad);
      }
      if (!st->check->flat_shapes) st->check->flat_shapes = PointsAreFlat(value);
    }
  }
  st->path_commands += commands;
  if (st->path_commands > limits.max_path_commands) {
    return st->Fail(SvgError::kTooManyPathCommands, "line " + std::to_string(line) + ": more than " +
                                                        std::to_string(limits.max_path_commands) +
                                                        " path commands (max_path_commands)");
  }
  st->nodes.push_back(std::move(node));
  st->open.push_back(index);
  if (local == "style") {
    st->in_style = true;
    st->style_text.clear();
  }
}

void OnEndElement(void* ctx, const xmlChar* localname, const xmlChar*, const xmlChar*) {
  CheckState* st = StateOf(ctx);
  if (!st->open.empty()) st->open.pop_back();
  if (st->in_style && Str(localname) == "style") {
    st->in_style = false;
    if (st->error == SvgError::kNone) CheckCss(st, st->style_text, "line " + std::to_string(st->Line()) + ": <style>");
    if (st->error == SvgError::kNone && FindNoCase(st->style_text, "data:") != std::string::npos) {
      st->Fail(SvgError::kNestedDocument, "line " + std::to_string(st->Line()) +
                                              ": <style> holds a data: URL; embedded documents are not accepted");
    }
  }
}

}  // namespace

Status CheckSvg(const std::string& bytes, const std::string& name, const SvgLimits& limits,
                SvgCheck* check, SvgError* error) {
  auto fail = [&](SvgError code, const std::string& what) { return SvgFailure(code, name, what, error); };
  if (bytes.size() > limits.max_bytes) {
    return fail(SvgError::kFileTooLarge, std::to_string(bytes.size()) + " bytes exceed the limit of " +
                                             std::to_string(limits.max_bytes) + " bytes (max_bytes)");
  }
  if (bytes.empty()) return fail(SvgError::kMalformedXml, "the file is empty");
  if (bytes.size() > size_t(std::numeric_limits<int>::max())) {
    return fail(SvgError::kFileTooLarge, "the file is over 2 GB");
  }
  xmlInitParser();
  // A pull parse over the whole buffer (linear in its size, unlike the push parser on
  // long attributes). XML_PARSE_HUGE lifts libxml2's 10 MB cap on one attribute (a long
  // path's d): the document is already within max_bytes and every other limit is ours.
  xmlParserCtxtPtr parser = xmlCreateMemoryParserCtxt(bytes.data(), int(bytes.size()));
  if (parser == nullptr) return fail(SvgError::kMalformedXml, "libxml2 cannot read the document");
  xmlSAXHandler sax{};
  sax.initialized = XML_SAX2_MAGIC;
  sax.startElementNs = OnStartElement;
  sax.endElementNs = OnEndElement;
  sax.entityDecl = OnEntityDecl;
  sax.reference = OnReference;
  sax.getEntity = OnGetEntity;
  sax.serror = OnError;
  sax.characters = OnCharacters;
  sax.cdataBlock = OnCharacters;
  sax.processingInstruction = OnProcessingInstruction;
  xmlSAXHandlerPtr original = parser->sax;
  parser->sax = &sax;
  CheckState st;
  st.name = &name;
  st.limits = &limits;
  st.check = check;
  st.parser = parser;
  parser->userData = &st;
  xmlCtxtUseOptions(parser, XML_PARSE_NONET | XML_PARSE_NOWARNING | XML_PARSE_NOERROR | XML_PARSE_HUGE);
  parser->sax = &sax;  // xmlCtxtUseOptions keeps it; set again for clarity
  xmlParseDocument(parser);
  const bool well_formed = parser->wellFormed != 0;
  parser->sax = original;
  parser->userData = nullptr;
  // libxml2 may build a document to hold a DOCTYPE's declarations even for a SAX parse.
  if (parser->myDoc != nullptr) {
    xmlFreeDoc(parser->myDoc);
    parser->myDoc = nullptr;
  }
  xmlFreeParserCtxt(parser);

  if (st.error != SvgError::kNone) return fail(st.error, st.what);
  if (!well_formed || !st.first_error.empty()) {
    if (st.first_error.empty()) st.first_error = "the XML is not well-formed";
    return fail(SvgError::kMalformedXml, "line " + std::to_string(st.first_error_line) + ": " + st.first_error);
  }
  if (!st.saw_root) return fail(SvgError::kMalformedXml, "no <svg> element");
  int cycle_node = -1;
  const int64_t expanded = ExpandedSize(st.nodes, st.ids, limits.max_use_expansion, &cycle_node);
  if (expanded < 0) {
    return fail(SvgError::kUseCycle, "a <use> references itself (directly or through other elements)");
  }
  if (uint64_t(expanded) > limits.max_use_expansion) {
    return fail(SvgError::kUseExpansion, "expanding <use> gives more than " +
                                             std::to_string(limits.max_use_expansion) +
                                             " elements (max_use_expansion)");
  }
  check->elements = st.nodes.size();
  return Status::Ok();
}

}  // namespace sdvi
