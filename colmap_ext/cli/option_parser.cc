#include "colmap_ext/cli/option_parser.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>

#include <boost/program_options.hpp>

#include "colmap_ext/util/error.h"
#include "colmap_ext/util/logging.h"

namespace po = boost::program_options;

namespace mpmvs {
namespace {

// Long options only, spelled out in full: "--name value" or "--name=value". Without short
// options a negative number ("-1") is a value; without guessing a typo is an error, not
// another option.
constexpr int kStyle = po::command_line_style::allow_long |
                       po::command_line_style::long_allow_next |
                       po::command_line_style::long_allow_adjacent;

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
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
  AddOption(name, {help, "0|1", *value ? "1" : "0", false, false,
                   [value](const std::string& t) { return ParseBool(t, value); }});
}

void OptionParser::Add(const std::string& name, int* value, const std::string& help) {
  AddOption(name, {help, "int", std::to_string(*value), false, false, [value](const std::string& t) {
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
  AddOption(name, {help, "num", FormatNumber(*value), false, false, [value](const std::string& t) {
                     errno = 0;
                     char* end = nullptr;
                     const double v = std::strtod(t.c_str(), &end);
                     if (t.empty() || *end != '\0' || errno != 0 || !std::isfinite(v)) return false;
                     *value = v;
                     return true;
                   }});
}

void OptionParser::Add(const std::string& name, std::string* value, const std::string& help) {
  AddOption(name, {help, "text", *value, false, false, [value](const std::string& t) {
                     *value = t;
                     return true;
                   }});
}

void OptionParser::AddRequired(const std::string& name, std::string* value,
                               const std::string& help) {
  Add(name, value, help);
  options_[name].required = true;
  options_[name].default_text.clear();
}

void OptionParser::AddIgnored(const std::string& name, const std::string& hint) {
  AddOption(name, {hint, "any", "", false, true, [](const std::string&) { return true; }});
}

void OptionParser::Describe(po::options_description* description) const {
  for (const std::string& name : order_) {
    const Option& o = options_.at(name);
    po::typed_value<std::string>* value = po::value<std::string>()->value_name(o.value_name);
    if (!o.default_text.empty()) value->default_value(o.default_text);
    const std::string help = o.required  ? "(required) " + o.help
                             : o.ignored ? "ignored by mp-mvs: " + o.help
                                         : o.help;
    description->add_options()(name.c_str(), value, help.c_str());
  }
}

bool OptionParser::Parse(const std::vector<std::string>& args) {
  po::options_description description;
  Describe(&description);
  description.add_options()("help", "this help");
  // Unknown options and stray words come back unregistered, so the error can name them.
  po::parsed_options parsed(&description);
  try {
    parsed = po::command_line_parser(args)
                 .options(description)
                 .style(kStyle)
                 .allow_unregistered()
                 .run();
  } catch (const po::invalid_command_line_syntax& e) {
    if (e.kind() == po::invalid_syntax::missing_parameter ||
        e.kind() == po::invalid_syntax::empty_adjacent_parameter) {
      throw Error("option " + e.get_option_name() + " needs a value");
    }
    throw Error(e.what());
  } catch (const po::error& e) {
    throw Error(e.what());
  }

  warnings_.clear();
  given_.clear();
  std::map<std::string, int>& count = given_;
  for (const po::option& given : parsed.options) {
    const std::string& name = given.string_key;
    if (name == "help") return false;
    if (name.empty()) {  // a word that is no option
      const std::string& word = given.original_tokens.front();
      if (word == "-h") return false;
      throw Error("unexpected argument '" + word + "' (options are given as --name value)");
    }
    if (given.unregistered) {
      std::string valid;
      for (const std::string& n : order_) {
        if (!options_.at(n).ignored) valid += "\n  --" + n;
      }
      throw Error("unknown option --" + name + ". Valid options:" + valid);
    }
    const Option& option = options_.at(name);
    const std::string& value = given.value.front();
    if (!option.set(value)) throw Error("bad value '" + value + "' for option --" + name);
    if (option.ignored && count[name] == 0) {
      warnings_.push_back("--" + name + " is accepted for COLMAP compatibility but ignored: " +
                          option.help);
    }
    ++count[name];
  }
  for (const std::string& name : order_) {
    const Option& option = options_.at(name);
    if (option.required && !count[name]) throw Error("missing required option --" + name);
    if (!option.ignored && count[name] > 1) {
      warnings_.push_back("--" + name + " is given " + std::to_string(count[name]) +
                          " times; the last value is used");
    }
  }
  for (const auto& callback : on_parsed_) callback(*this);
  return true;
}

std::string OptionParser::Help() const {
  po::options_description description;
  Describe(&description);
  std::ostringstream ss;
  ss << description;
  return ss.str();
}

}  // namespace mpmvs
