#pragma once
// COLMAP-style command-line options: "--Section.name value" pairs bound to typed fields of
// plain option structs. Unknown options, missing values and bad values are errors that
// list what is valid. Booleans accept 0/1/true/false like COLMAP.
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace mpmvs {

class OptionParser {
 public:
  void Add(const std::string& name, bool* value, const std::string& help = "");
  void Add(const std::string& name, int* value, const std::string& help = "");
  void Add(const std::string& name, double* value, const std::string& help = "");
  void Add(const std::string& name, std::string* value, const std::string& help = "");
  // Must be given on the command line.
  void AddRequired(const std::string& name, std::string* value, const std::string& help = "");
  // Accepted and ignored with one warning (COLMAP options that describe COLMAP's own
  // algorithm); hint names what to use instead.
  void AddIgnored(const std::string& name, const std::string& hint);

  // args exclude the program and command names. Throws Error on unknown options, missing
  // values, unparsable values and missing required options. Returns false when help
  // (-h/--help) was asked for.
  bool Parse(const std::vector<std::string>& args);

  // Warnings produced for ignored options during Parse.
  const std::vector<std::string>& Warnings() const { return warnings_; }
  // One line per option: name, default (current value) and help.
  std::string Help() const;

 private:
  struct Option {
    std::string help;
    std::string default_text;
    bool required = false;
    bool ignored = false;
    std::function<bool(const std::string&)> set;  // false on a bad value
  };
  void AddOption(const std::string& name, Option option);
  std::map<std::string, Option> options_;
  std::vector<std::string> order_;
  std::vector<std::string> warnings_;
};

// Parses "0/1/true/false" (case-insensitive); false on anything else.
bool ParseBool(const std::string& text, bool* value);

}  // namespace mpmvs
