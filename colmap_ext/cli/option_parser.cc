#include "colmap_ext/cli/option_parser.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "colmap_ext/util/error.h"

namespace mpmvs {
namespace {

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string FormatDouble(double v) {
  std::ostringstream ss;
  ss << v;
  return ss.str();
}

}  // namespace

bool ParseBool(const std::string& text, bool* value) {
  const std::string t = Lower(text);
  if (t == "1" || t == "true") {
    *value = true;
    return true;
  }
  if (t == "0" || t == "false") {
    *value = false;
    return true;
  }
  return false;
}

void OptionParser::AddOption(const std::string& name, Option option) {
  if (!options_.count(name)) order_.push_back(name);
  options_[name] = std::move(option);
}

void OptionParser::Add(const std::string& name, bool* value, const std::string& help) {
  AddOption(name, {help, *value ? "1" : "0", false, false,
                   [value](const std::string& t) { return ParseBool(t, value); }});
}

void OptionParser::Add(const std::string& name, int* value, const std::string& help) {
  AddOption(name, {help, std::to_string(*value), false, false, [value](const std::string& t) {
                     errno = 0;
                     char* end = nullptr;
                     const long v = std::strtol(t.c_str(), &end, 10);
                     if (t.empty() || *end != '\0' || errno != 0 || v < INT32_MIN || v > INT32_MAX)
                       return false;
                     *value = static_cast<int>(v);
                     return true;
                   }});
}

void OptionParser::Add(const std::string& name, double* value, const std::string& help) {
  AddOption(name, {help, FormatDouble(*value), false, false, [value](const std::string& t) {
                     errno = 0;
                     char* end = nullptr;
                     const double v = std::strtod(t.c_str(), &end);
                     if (t.empty() || *end != '\0' || errno != 0 || !std::isfinite(v)) return false;
                     *value = v;
                     return true;
                   }});
}

void OptionParser::Add(const std::string& name, std::string* value, const std::string& help) {
  AddOption(name, {help, *value, false, false, [value](const std::string& t) {
                     *value = t;
                     return true;
                   }});
}

void OptionParser::AddRequired(const std::string& name, std::string* value,
                               const std::string& help) {
  Add(name, value, help);
  options_[name].required = true;
}

void OptionParser::AddIgnored(const std::string& name, const std::string& hint) {
  AddOption(name, {"ignored by mp-mvs: " + hint, "", false, true,
                   [](const std::string&) { return true; }});
}

bool OptionParser::Parse(const std::vector<std::string>& args) {
  std::map<std::string, bool> seen;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "-h" || arg == "--help") return false;
    if (arg.rfind("--", 0) != 0) {
      throw Error("unexpected argument '" + arg + "' (options are given as --name value)");
    }
    std::string name = arg.substr(2);
    std::string value;
    bool has_value = false;
    const size_t eq = name.find('=');
    if (eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
      has_value = true;
    }
    auto it = options_.find(name);
    if (it == options_.end()) {
      std::string valid;
      for (const auto& n : order_) {
        if (!options_.at(n).ignored) valid += "\n  --" + n;
      }
      throw Error("unknown option --" + name + ". Valid options:" + valid);
    }
    if (!has_value) {
      if (i + 1 >= args.size()) throw Error("option --" + name + " needs a value");
      value = args[++i];
    }
    if (!it->second.set(value)) {
      throw Error("bad value '" + value + "' for option --" + name);
    }
    if (it->second.ignored) {
      warnings_.push_back("--" + name + " is accepted for COLMAP compatibility but ignored: " +
                          it->second.help.substr(std::string("ignored by mp-mvs: ").size()));
    }
    seen[name] = true;
  }
  for (const auto& n : order_) {
    if (options_.at(n).required && !seen.count(n)) {
      throw Error("missing required option --" + n);
    }
  }
  return true;
}

std::string OptionParser::Help() const {
  std::ostringstream ss;
  for (const auto& n : order_) {
    const Option& o = options_.at(n);
    ss << "  --" << n;
    if (o.required) {
      ss << " (required)";
    } else if (!o.ignored) {
      ss << " (default: " << o.default_text << ")";
    }
    if (!o.help.empty()) ss << "\n      " << o.help;
    ss << "\n";
  }
  return ss.str();
}

}  // namespace mpmvs
