#pragma once
// Strict reading of JSON input files (placement files, experiment configs, user descriptions): every field is
// checked for presence and type, unknown fields are rejected (a misspelt field must not be silently ignored), and
// every error names the source file and the field's path: "<file>: <field.path>: <problem>".

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace softwrist::io {

// Reads one JSON object, field by field, with errors that name the source and the field's path.
class JsonReader {
 public:
  JsonReader(const nlohmann::json& object, std::string source, std::string path)
      : object_(object), source_(std::move(source)), path_(std::move(path)) {
    if (!object_.is_object()) fail("", "must be a JSON object");
  }
  [[noreturn]] void fail(const std::string& key, const std::string& problem) const {
    const std::string field = path_.empty() ? key : (key.empty() ? path_ : path_ + "." + key);
    throw std::runtime_error(fmt::format("{}: {}: {}", source_, field.empty() ? "(top level)" : field, problem));
  }
  bool has(const std::string& key) const { return object_.contains(key); }
  double number(const std::string& key) {
    seen_.insert(key);
    if (!object_.contains(key)) fail(key, "missing");
    const nlohmann::json& value = object_.at(key);
    if (!value.is_number()) fail(key, "must be a number");
    const double number = value.get<double>();
    if (!std::isfinite(number)) fail(key, "must be finite");
    return number;
  }
  double number(const std::string& key, double fallback) {
    return has(key) ? number(key) : (seen_.insert(key), fallback);
  }
  double positive(const std::string& key) {
    const double v = number(key);
    if (!(v > 0.0)) fail(key, fmt::format("must be > 0, got {}", v));
    return v;
  }
  double positive(const std::string& key, double fallback) {
    const double v = number(key, fallback);
    if (!(v > 0.0)) fail(key, fmt::format("must be > 0, got {}", v));
    return v;
  }
  long long integer(const std::string& key) {
    const double value = number(key);
    if (value != std::floor(value) || std::abs(value) > 9.0e15) fail(key, "must be an integer");
    return static_cast<long long>(value);
  }
  long long integer(const std::string& key, long long fallback) {
    return has(key) ? integer(key) : (seen_.insert(key), fallback);
  }
  bool boolean(const std::string& key, bool fallback) {
    seen_.insert(key);
    if (!object_.contains(key)) return fallback;
    if (!object_.at(key).is_boolean()) fail(key, "must be true or false");
    return object_.at(key).get<bool>();
  }
  // A non-empty list of finite numbers.
  std::vector<double> numbers(const std::string& key) {
    const nlohmann::json& list = raw(key);
    if (!list.is_array() || list.empty()) fail(key, "must be a non-empty list of numbers");
    std::vector<double> values;
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (!list[i].is_number() || !std::isfinite(list[i].get<double>())) {
        fail(fmt::format("{}[{}]", key, i), "must be a finite number");
      }
      values.push_back(list[i].get<double>());
    }
    return values;
  }
  double non_negative(const std::string& key, double fallback) {
    const double v = number(key, fallback);
    if (v < 0.0) fail(key, "must be >= 0");
    return v;
  }
  std::string text(const std::string& key) {
    seen_.insert(key);
    if (!object_.contains(key)) fail(key, "missing");
    return text(key, "");
  }
  std::string text(const std::string& key, const std::string& fallback) {
    seen_.insert(key);
    if (!object_.contains(key)) return fallback;
    if (!object_.at(key).is_string()) fail(key, "must be a string");
    return object_.at(key).get<std::string>();
  }
  JsonReader child(const std::string& key) {
    seen_.insert(key);
    if (!object_.contains(key)) fail(key, "missing");
    return JsonReader(object_.at(key), source_, path_.empty() ? key : path_ + "." + key);
  }
  const nlohmann::json& raw(const std::string& key) {
    seen_.insert(key);
    if (!object_.contains(key)) fail(key, "missing");
    return object_.at(key);
  }
  // Rejects keys this reader never asked for: a misspelt field must not be silently ignored.
  void finish() const {
    for (const auto& [key, value] : object_.items()) {
      if (!seen_.contains(key)) fail(key, "unknown field");
    }
  }
  const nlohmann::json& json() const { return object_; }
  const std::string& source() const { return source_; }
  const std::string& path() const { return path_; }

 private:
  const nlohmann::json& object_;
  std::string source_, path_;
  std::set<std::string> seen_;
};

// Parses JSON text; a syntax error becomes "<source>: invalid JSON: <what>".
nlohmann::json parse_json(const std::string& text, const std::string& source);

}  // namespace softwrist::io
