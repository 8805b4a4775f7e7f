#include "colmap_ext/util/json_writer.h"

#include <cmath>
#include <cstdio>

#include "colmap_ext/util/error.h"

namespace mpmvs {

std::string JsonQuote(const std::string& text) {
  std::string out = "\"";
  for (const char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof(buf), "\\u%04x", c);
          out += buf;
        } else {
          out += ch;
        }
    }
  }
  return out + "\"";
}

void JsonWriter::Indent() {
  out_ += "\n";
  out_.append(2 * first_.size(), ' ');
}

void JsonWriter::BeforeValue() {
  if (after_key_) {
    after_key_ = false;
    return;
  }
  if (!first_.empty()) {
    if (object_.back()) throw Error("JsonWriter: value inside an object needs a key");
    if (!first_.back()) out_ += ",";
    first_.back() = false;
    Indent();
  }
}

JsonWriter& JsonWriter::Key(const std::string& key) {
  if (first_.empty() || !object_.back() || after_key_) throw Error("JsonWriter: misplaced key");
  if (!first_.back()) out_ += ",";
  first_.back() = false;
  Indent();
  out_ += JsonQuote(key) + ": ";
  after_key_ = true;
  return *this;
}

JsonWriter& JsonWriter::BeginObject() {
  BeforeValue();
  out_ += "{";
  first_.push_back(true);
  object_.push_back(true);
  return *this;
}

JsonWriter& JsonWriter::EndObject() {
  if (first_.empty() || !object_.back()) throw Error("JsonWriter: EndObject without object");
  const bool empty = first_.back();
  first_.pop_back();
  object_.pop_back();
  if (!empty) Indent();
  out_ += "}";
  return *this;
}

JsonWriter& JsonWriter::BeginArray() {
  BeforeValue();
  out_ += "[";
  first_.push_back(true);
  object_.push_back(false);
  return *this;
}

JsonWriter& JsonWriter::EndArray() {
  if (first_.empty() || object_.back()) throw Error("JsonWriter: EndArray without array");
  const bool empty = first_.back();
  first_.pop_back();
  object_.pop_back();
  if (!empty) Indent();
  out_ += "]";
  return *this;
}

JsonWriter& JsonWriter::String(const std::string& value) {
  BeforeValue();
  out_ += JsonQuote(value);
  return *this;
}

JsonWriter& JsonWriter::Number(double value) {
  BeforeValue();
  if (!std::isfinite(value)) {
    out_ += "null";
  } else {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.10g", value);
    out_ += buf;
  }
  return *this;
}

JsonWriter& JsonWriter::Int(int64_t value) {
  BeforeValue();
  out_ += std::to_string(value);
  return *this;
}

JsonWriter& JsonWriter::Bool(bool value) {
  BeforeValue();
  out_ += value ? "true" : "false";
  return *this;
}

JsonWriter& JsonWriter::Null() {
  BeforeValue();
  out_ += "null";
  return *this;
}

JsonWriter& JsonWriter::NumberArray(const std::string& key, const std::vector<double>& values) {
  Key(key).BeginArray();
  for (double v : values) Number(v);
  return EndArray();
}

std::string JsonWriter::str() const {
  if (!first_.empty()) throw Error("JsonWriter: unclosed object or array");
  return out_ + "\n";
}

}  // namespace mpmvs
