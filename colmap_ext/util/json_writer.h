#pragma once
// Minimal streaming JSON writer for result files (scores, scene descriptions): objects,
// arrays, strings, numbers, booleans; indented output; non-finite numbers become null.
#include <cstdint>
#include <string>
#include <vector>

namespace mpmvs {

class JsonWriter {
 public:
  JsonWriter& BeginObject();
  JsonWriter& EndObject();
  JsonWriter& BeginArray();
  JsonWriter& EndArray();
  // Inside an object: the next value's key.
  JsonWriter& Key(const std::string& key);
  JsonWriter& String(const std::string& value);
  JsonWriter& Number(double value);
  JsonWriter& Int(int64_t value);
  JsonWriter& Bool(bool value);
  JsonWriter& Null();

  // Shorthands for key + value.
  JsonWriter& Field(const std::string& key, const std::string& value) { return Key(key).String(value); }
  JsonWriter& Field(const std::string& key, const char* value) { return Key(key).String(value); }
  JsonWriter& Field(const std::string& key, double value) { return Key(key).Number(value); }
  JsonWriter& Field(const std::string& key, int value) { return Key(key).Int(value); }
  JsonWriter& Field(const std::string& key, int64_t value) { return Key(key).Int(value); }
  JsonWriter& Field(const std::string& key, bool value) { return Key(key).Bool(value); }
  JsonWriter& NumberArray(const std::string& key, const std::vector<double>& values);

  // The document; throws Error when objects/arrays are still open.
  std::string str() const;

 private:
  void BeforeValue();
  void Indent();
  std::string out_;
  std::vector<bool> first_;   // per open container: no element written yet
  std::vector<bool> object_;  // per open container: object (true) or array
  bool after_key_ = false;
};

// JSON string literal with escapes.
std::string JsonQuote(const std::string& text);

}  // namespace mpmvs
