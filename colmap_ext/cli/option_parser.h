#pragma once
// COLMAP-style command-line options: "--Section.name value" (or "--Section.name=value")
// pairs bound to typed fields of plain option structs, parsed with Boost.Program_options
// like COLMAP's own option manager. Unknown options, missing values and bad values are
// errors that name the option; booleans accept 1|0, true|false, yes|no, on|off like COLMAP.
// A project file (COLMAP's --project_path) gives options as INI lines: top-level keys are
// options without a section ("workspace_path = dense"), keys under [Section] are
// --Section.key.
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace boost {
namespace program_options {
class options_description;
template <class charT>
class basic_parsed_options;
}  // namespace program_options
}  // namespace boost

namespace mpmvs {

// Comma-separated list ("a, b,c"), items trimmed, empty items dropped.
std::vector<std::string> SplitList(const std::string& text);

class OptionParser {
 public:
  void Add(const std::string& name, bool* value, const std::string& help = "");
  void Add(const std::string& name, int* value, const std::string& help = "");
  void Add(const std::string& name, double* value, const std::string& help = "");
  void Add(const std::string& name, std::string* value, const std::string& help = "");
  // Comma-separated numbers ("0.01, 0.02"; SplitList), at least one.
  void Add(const std::string& name, std::vector<double>* value, const std::string& help = "");
  // Must be given on the command line.
  void AddRequired(const std::string& name, std::string* value, const std::string& help = "");
  // Accepted and ignored with one warning (COLMAP options that describe COLMAP's own
  // algorithm); hint names what to use instead.
  void AddIgnored(const std::string& name, const std::string& hint);
  // --name FILE reads options from an INI project file before the command line, so that
  // options given on the command line override the file's (COLMAP instead ignores the
  // command line when --project_path is given). Unknown keys and bad values are errors
  // naming the file.
  void AddProjectFile(const std::string& name, std::string* path, const std::string& help = "");

  // args exclude the program and command names. Throws Error on unknown options, missing
  // values, unparsable values and missing required options. Returns false when help
  // (-h/--help) was asked for. An option given twice takes its last value, with a warning.
  bool Parse(const std::vector<std::string>& args);

  // Called at the end of every successful Parse, in the order added (e.g. to apply a preset
  // to the options not given); may throw Error.
  void OnParsed(std::function<void(const OptionParser&)> callback) { on_parsed_.push_back(std::move(callback)); }
  // Whether the last Parse saw the option on the command line or in the project file.
  bool Given(const std::string& name) const {
    const auto it = given_.find(name);
    return it != given_.end() && it->second > 0;
  }

  // Warnings of the last Parse: ignored options and options given more than once.
  const std::vector<std::string>& Warnings() const { return warnings_; }
  // One entry per option: name, default (current value) and help.
  std::string Help() const;

 private:
  struct Option {
    std::string help;          // for an ignored option: its hint
    std::string value_name;    // shown in the help: "int", "0|1", ...
    std::string default_text;  // shown in the help when not empty
    bool required = false;
    bool ignored = false;
    std::function<bool(const std::string&)> set;  // false on a bad value
  };
  void AddOption(const std::string& name, Option option);
  // The options in the order they were added; every value is taken as text and converted
  // by Option::set, so the accepted forms are exactly ours (not lexical_cast's).
  void Describe(boost::program_options::options_description* description) const;
  // One option as given: its name ("" for a stray word), value, and the word as typed.
  struct GivenOption {
    std::string name;
    std::string value;
    std::string word;
    bool unregistered = false;
  };
  static std::vector<GivenOption> GivenOptions(const boost::program_options::basic_parsed_options<char>& parsed);
  // Sets the options given in one place (the command line, or the project file `file`);
  // false when help was asked for. Counts each option in *count.
  bool Apply(const std::vector<GivenOption>& given, const std::string& file, std::map<std::string, int>* count);

  std::map<std::string, Option> options_;
  std::vector<std::string> order_;
  std::vector<std::string> warnings_;
  std::map<std::string, int> given_;
  std::vector<std::function<void(const OptionParser&)>> on_parsed_;
  std::string project_file_option_;  // AddProjectFile's name, "" if none
};

// Parses 1|0, true|false, yes|no, on|off (case-insensitive, as COLMAP's Boost options);
// false on anything else.
bool ParseBool(const std::string& text, bool* value);

}  // namespace mpmvs
