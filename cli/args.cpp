#include "args.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace sdvi::cli {

StatusOr<Args> Args::Parse(const std::vector<std::string>& args, const ArgSpec& spec) {
  Args out;
  for (size_t i = 0; i < args.size(); ++i) {
    std::string a = args[i];
    if (a.size() < 2 || a[0] != '-' || a == "--") {
      out.positional_.push_back(a);
      continue;
    }
    std::optional<std::string> inline_value;
    if (auto eq = a.find('='); a.rfind("--", 0) == 0 && eq != std::string::npos) {
      inline_value = a.substr(eq + 1);
      a = a.substr(0, eq);
    }
    if (spec.flags.count(a)) {
      if (inline_value) return Status(StatusCode::kInvalidArgument, "option " + a + " takes no value");
      out.flags_.insert(a);
    } else if (spec.valued.count(a)) {
      if (inline_value) {
        out.values_[a] = *inline_value;
      } else {
        if (i + 1 >= args.size())
          return Status(StatusCode::kInvalidArgument, "option " + a + " needs a value");
        out.values_[a] = args[++i];
      }
    } else {
      return Status(StatusCode::kInvalidArgument, "unknown option " + a);
    }
  }
  return out;
}

std::optional<std::string> Args::get(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) return std::nullopt;
  return it->second;
}

StatusOr<int> Args::GetInt(const std::string& name, int fallback) const {
  auto v = get(name);
  if (!v) return fallback;
  int out = 0;
  auto [p, ec] = std::from_chars(v->data(), v->data() + v->size(), out);
  if (ec != std::errc() || p != v->data() + v->size())
    return Status(StatusCode::kInvalidArgument, "option " + name + ": expected an integer, got '" + *v + "'");
  return out;
}

StatusOr<double> Args::GetDouble(const std::string& name, double fallback) const {
  auto v = get(name);
  if (!v) return fallback;
  char* end = nullptr;
  double out = std::strtod(v->c_str(), &end);
  if (v->empty() || *end != '\0' || !std::isfinite(out))
    return Status(StatusCode::kInvalidArgument, "option " + name + ": expected a number, got '" + *v + "'");
  return out;
}

int ReportError(const std::string& command, const Status& status) {
  std::fprintf(stderr, "sdvi %s: %s\n", command.c_str(), status.ToString().c_str());
  return status.code() == StatusCode::kInvalidArgument ? 1 : 2;
}

}  // namespace sdvi::cli
