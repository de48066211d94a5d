#include "scenarios/config/options_reader.h"

#include <cctype>

namespace pavilion::scenarios::options_reader_internal {
namespace {

bool IsIdentifierChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
}

}  // namespace

void ReadField(MapReader& r, const std::string& key, double scale, double* value) {
  if (!r.Has(key)) {
    r.Child(key);  // known, absent: the default holds
    return;
  }
  if (auto v = ReadNumber(r.doc(), r.Child(key), r.PathOf(key))) *value = *v * scale;
}

void ReadField(MapReader& r, const std::string& key, double /*scale*/, int* value) {
  YAML::Node child = r.Child(key);
  if (!child.IsDefined()) return;
  int v;
  if (!child.IsScalar() || !YAML::convert<int>::decode(child, v)) {
    r.doc()->Error(child, r.PathOf(key), "expected an integer");
    return;
  }
  *value = v;
}

void ReadField(MapReader& r, const std::string& key, double /*scale*/, bool* value) {
  *value = r.Bool(key, *value);
}

void ReadField(MapReader& r, const std::string& key, double scale, std::optional<double>* value) {
  if (!r.Has(key)) {
    r.Child(key);
    return;
  }
  if (auto v = ReadNumber(r.doc(), r.Child(key), r.PathOf(key))) *value = *v * scale;
}

void ReadField(MapReader& r, const std::string& key, double scale, Eigen::Vector2d* value) {
  if (auto v = r.Numbers(key, 2, false)) *value = Eigen::Vector2d((*v)[0], (*v)[1]) * scale;
}

void ReadField(MapReader& r, const std::string& key, double scale, Eigen::Vector3d* value) {
  if (auto v = r.Numbers(key, 3, false)) {
    *value = Eigen::Vector3d((*v)[0], (*v)[1], (*v)[2]) * scale;
  }
}

std::size_t FieldNamedIn(const std::string& message, const std::vector<std::string>& fields) {
  for (std::size_t begin = 0; begin < message.size();) {
    if (!IsIdentifierChar(message[begin])) {
      ++begin;
      continue;
    }
    std::size_t end = begin;
    while (end < message.size() && IsIdentifierChar(message[end])) ++end;
    const std::string word = message.substr(begin, end - begin);
    for (std::size_t k = 0; k < fields.size(); ++k) {
      if (fields[k] == word) return k;
    }
    begin = end;
  }
  return fields.size();
}

void Report(MapReader& r, const std::string& key, const std::string& message) {
  if (key.empty()) {
    r.doc()->Error(r.node(), r.path(), message);
    return;
  }
  YAML::Node child = r.Child(key);
  r.doc()->Error(child.IsDefined() ? child : r.node(), r.PathOf(key), message);
}

}  // namespace pavilion::scenarios::options_reader_internal

namespace pavilion::scenarios {

void RequireKeys(MapReader& r, const std::vector<std::string>& keys) {
  for (const std::string& key : keys) {
    if (!r.Has(key)) r.Child(key, true);
  }
}

}  // namespace pavilion::scenarios
