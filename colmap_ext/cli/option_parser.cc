#include "colmap_ext/cli/option_parser.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
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

// An INI project file as COLMAP reads it: "[Section]" headers, "key = value" lines, '#'
// comments; a key under [Section] is the option Section.key.
po::parsed_options ParseProjectFile(const std::string& path, const po::options_description& description) {
  std::ifstream file(path);
  if (!file) throw Error("cannot read the project file " + path + " (--project_path)");
  try {
    return po::parse_config_file(file, description, /*allow_unregistered=*/true);
  } catch (const po::error& e) {
    throw Error(path + ": " + e.what());
  }
}

// A finite number, the whole text (strtod: leading blanks are skipped, trailing ones are not).
bool ParseNumber(const std::string& text, double* value) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno != 0 || !std::isfinite(v)) return false;
  *value = v;
  return true;
}

}  // namespace

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const size_t b = item.find_first_not_of(" \t");
    const size_t e = item.find_last_not_of(" \t");
    if (b != std::string::npos) items.push_back(item.substr(b, e - b + 1));
  }
  return items;
}

bool ParseBool(const std::string& text, bool* value) {
  const std::string t = Lower(text);
  if (t == "1" || t == "true" || t == "yes" || t == "on") {
    *value = true;
    return true;
  }
  if (t == "0" || t == "false" || t == "no" || t == "off") {
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
  AddOption(name, {help, "num", FormatNumber(*value), false, false,
                   [value](const std::string& t) { return ParseNumber(t, value); }});
}

void OptionParser::Add(const std::string& name, std::vector<double>* value, const std::string& help) {
  std::string default_text;
  for (double v : *value) default_text += (default_text.empty() ? "" : ",") + FormatNumber(v);
  AddOption(name, {help, "num,num,...", default_text, false, false, [value](const std::string& t) {
                     std::vector<double> numbers;
                     for (const std::string& item : SplitList(t)) {
                       double v;
                       if (!ParseNumber(item, &v)) return false;
                       numbers.push_back(v);
                     }
                     if (numbers.empty()) return false;
                     *value = std::move(numbers);
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

std::vector<OptionParser::GivenOption> OptionParser::GivenOptions(const po::parsed_options& parsed) {
  std::vector<GivenOption> given;
  for (const po::option& o : parsed.options) {
    given.push_back({o.string_key, o.value.empty() ? "" : o.value.front(),
                     o.original_tokens.empty() ? "" : o.original_tokens.front(), o.unregistered});
  }
  return given;
}

void OptionParser::AddProjectFile(const std::string& name, std::string* path, const std::string& help) {
  Add(name, path, help);
  project_file_option_ = name;
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
  const std::vector<GivenOption> command_line = GivenOptions(parsed);
  for (const GivenOption& g : command_line) {
    if (g.name == "help" || (g.name.empty() && g.word == "-h")) return false;
  }
  // The project file first: the command line overrides it.
  std::string project_file;
  for (const GivenOption& g : command_line) {
    if (!project_file_option_.empty() && g.name == project_file_option_) project_file = g.value;
  }
  std::map<std::string, int> in_file, on_command_line;
  if (!project_file.empty()) {
    if (!Apply(GivenOptions(ParseProjectFile(project_file, description)), project_file, &in_file)) return false;
  }
  if (!Apply(command_line, "", &on_command_line)) return false;
  for (const std::string& name : order_) {
    const Option& option = options_.at(name);
    given_[name] = in_file[name] + on_command_line[name];
    if (option.required && !given_[name]) throw Error("missing required option --" + name);
    if (option.ignored) {
      if (given_[name]) {
        warnings_.push_back("--" + name + " is accepted for COLMAP compatibility but ignored: " + option.help);
      }
      continue;
    }
    if (on_command_line[name] > 1) {
      warnings_.push_back("--" + name + " is given " + std::to_string(on_command_line[name]) +
                          " times; the last value is used");
    }
    if (in_file[name] > 1) {
      warnings_.push_back(name + " is given " + std::to_string(in_file[name]) + " times in " + project_file +
                          "; the last value is used");
    }
  }
  for (const auto& callback : on_parsed_) callback(*this);
  return true;
}

bool OptionParser::Apply(const std::vector<GivenOption>& given, const std::string& file, std::map<std::string, int>* count) {
  const std::string where = file.empty() ? "" : " in " + file;
  for (const GivenOption& g : given) {
    if (g.name == "help") return false;
    if (g.name.empty()) {  // a word that is no option
      if (g.word == "-h") return false;
      throw Error("unexpected argument '" + g.word + "' (options are given as --name value)");
    }
    if (g.unregistered || (!file.empty() && g.name == project_file_option_)) {
      std::string valid;
      for (const std::string& n : order_) {
        if (!options_.at(n).ignored) valid += "\n  --" + n;
      }
      throw Error("unknown option --" + g.name + where + ". Valid options:" + valid);
    }
    const Option& option = options_.at(g.name);
    if (!option.set(g.value)) throw Error("bad value '" + g.value + "' for option --" + g.name + where);
    ++(*count)[g.name];
  }
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
