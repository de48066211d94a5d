#include "scenarios/config/yaml_reader.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <utility>

namespace pavilion::scenarios {
namespace {

int LineOf(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) {
    return node.IsDefined() && node.Mark().line >= 0 ? node.Mark().line + 1 : 0;
  }
  return node.Mark().line >= 0 ? node.Mark().line + 1 : 0;
}

// Finds a mapping key without inserting it (non-const operator[] would).
YAML::Node Lookup(const YAML::Node& map, const std::string& key) {
  for (const auto& kv : map) {
    if (kv.first.IsScalar() && kv.first.Scalar() == key) return kv.second;
  }
  return YAML::Node(YAML::NodeType::Undefined);
}

std::string Join(const std::vector<std::string>& items) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + items[i];
  return out;
}

// A deep copy of `node` without source marks: a value parsed from a --set
// override has lines of its own one-line text, which are not lines of the file.
YAML::Node WithoutMarks(const YAML::Node& node) {
  YAML::Node out;
  switch (node.Type()) {
    case YAML::NodeType::Scalar:
      out = YAML::Node(node.Scalar());
      break;
    case YAML::NodeType::Sequence:
      out = YAML::Node(YAML::NodeType::Sequence);
      for (const auto& item : node) out.push_back(WithoutMarks(item));
      break;
    case YAML::NodeType::Map:
      out = YAML::Node(YAML::NodeType::Map);
      for (const auto& kv : node) out[WithoutMarks(kv.first)] = WithoutMarks(kv.second);
      break;
    default:
      return YAML::Node(YAML::NodeType::Null);
  }
  out.SetTag(node.Tag());
  return out;
}

}  // namespace

YamlDocument::YamlDocument(std::string path) : path_(std::move(path)) {
  std::ifstream in(path_);
  if (!in) {
    diagnostics_.push_back({path_, 0, "", "cannot open file"});
    return;
  }
  std::stringstream text;
  text << in.rdbuf();
  try {
    root_ = YAML::Load(text.str());
  } catch (const YAML::Exception& e) {
    diagnostics_.push_back(
        {path_, e.mark.line >= 0 ? e.mark.line + 1 : 0, "", "malformed YAML: " + e.msg});
    root_ = YAML::Node();
  }
}

YamlDocument::YamlDocument(std::string path, YAML::Node root)
    : path_(std::move(path)), root_(std::move(root)) {}

void YamlDocument::Error(const YAML::Node& at, const std::string& key_path,
                         const std::string& message) {
  diagnostics_.push_back({path_, LineOf(at), key_path, message});
}

void YamlDocument::ThrowIfErrors() const {
  if (!diagnostics_.empty()) throw InputError(diagnostics_);
}

std::optional<double> ReadNumber(YamlDocument* doc, const YAML::Node& node,
                                 const std::string& path) {
  if (!node.IsScalar()) {
    doc->Error(node, path, "expected a number");
    return std::nullopt;
  }
  double value;
  if (!YAML::convert<double>::decode(node, value)) {
    doc->Error(node, path, "expected a number, got '" + node.Scalar() + "'");
    return std::nullopt;
  }
  if (!std::isfinite(value)) {
    doc->Error(node, path, "must be a finite number, got '" + node.Scalar() + "'");
    return std::nullopt;
  }
  return value;
}

std::optional<std::vector<double>> ReadNumbers(YamlDocument* doc, const YAML::Node& node,
                                               const std::string& path, std::size_t size) {
  if (!node.IsSequence() || (size > 0 && node.size() != size)) {
    doc->Error(node, path,
               size > 0 ? "expected a list of " + std::to_string(size) + " numbers"
                        : "expected a list of numbers");
    return std::nullopt;
  }
  std::vector<double> values;
  bool ok = true;
  for (std::size_t i = 0; i < node.size(); ++i) {
    auto v = ReadNumber(doc, node[i], path + "[" + std::to_string(i) + "]");
    if (v) {
      values.push_back(*v);
    } else {
      ok = false;
    }
  }
  if (!ok) return std::nullopt;
  return values;
}

MapReader::MapReader(YamlDocument* doc, YAML::Node node, std::string path)
    : doc_(doc), node_(std::move(node)), path_(std::move(path)) {
  valid_ = node_.IsMap();
  if (!valid_) doc_->Error(node_, path_.empty() ? "(top level)" : path_, "expected a mapping");
}

bool MapReader::Has(const std::string& key) const {
  return valid_ && Lookup(node_, key).IsDefined();
}

std::string MapReader::PathOf(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

YAML::Node MapReader::Child(const std::string& key, bool required) {
  read_.insert(key);
  if (!valid_) return YAML::Node(YAML::NodeType::Undefined);
  YAML::Node child = Lookup(node_, key);
  if (!child.IsDefined() && required) doc_->Error(node_, PathOf(key), "required key is missing");
  return child;
}

std::optional<double> MapReader::RequiredNumber(const std::string& key, double lo, double hi) {
  YAML::Node child = Child(key, true);
  if (!child.IsDefined()) return std::nullopt;
  auto v = ReadNumber(doc_, child, PathOf(key));
  if (v && (*v < lo || *v > hi)) {
    std::ostringstream msg;
    msg << "must be in [" << lo << ", " << hi << "], got " << *v;
    doc_->Error(child, PathOf(key), msg.str());
    return std::nullopt;
  }
  return v;
}

double MapReader::Number(const std::string& key, double default_value, double lo, double hi) {
  if (!Has(key)) {
    read_.insert(key);
    return default_value;
  }
  return RequiredNumber(key, lo, hi).value_or(default_value);
}

std::int64_t MapReader::Integer(const std::string& key, std::int64_t default_value, std::int64_t lo,
                                std::int64_t hi) {
  YAML::Node child = Child(key);
  if (!child.IsDefined()) return default_value;
  std::int64_t value;
  if (!child.IsScalar() || !YAML::convert<std::int64_t>::decode(child, value)) {
    doc_->Error(child, PathOf(key), "expected an integer");
    return default_value;
  }
  if (value < lo || value > hi) {
    doc_->Error(child, PathOf(key),
                "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                    std::to_string(value));
    return default_value;
  }
  return value;
}

bool MapReader::Bool(const std::string& key, bool default_value) {
  YAML::Node child = Child(key);
  if (!child.IsDefined()) return default_value;
  bool value;
  if (!child.IsScalar() || !YAML::convert<bool>::decode(child, value)) {
    doc_->Error(child, PathOf(key), "expected true or false");
    return default_value;
  }
  return value;
}

std::optional<std::string> MapReader::RequiredString(const std::string& key) {
  YAML::Node child = Child(key, true);
  if (!child.IsDefined()) return std::nullopt;
  if (!child.IsScalar()) {
    doc_->Error(child, PathOf(key), "expected a string");
    return std::nullopt;
  }
  return child.Scalar();
}

std::string MapReader::String(const std::string& key, const std::string& default_value) {
  if (!Has(key)) {
    read_.insert(key);
    return default_value;
  }
  return RequiredString(key).value_or(default_value);
}

std::string MapReader::Choice(const std::string& key, const std::vector<std::string>& choices,
                              const std::string& default_value, bool required) {
  std::optional<std::string> value =
      required ? RequiredString(key) : std::optional<std::string>(String(key, default_value));
  if (!value) return default_value;
  for (const auto& c : choices) {
    if (c == *value) return *value;
  }
  doc_->Error(Child(key), PathOf(key),
              "must be one of " + Join(choices) + ", got '" + *value + "'");
  return default_value;
}

std::optional<std::vector<double>> MapReader::Numbers(const std::string& key, std::size_t size,
                                                      bool required) {
  YAML::Node child = Child(key, required);
  if (!child.IsDefined()) return std::nullopt;
  return ReadNumbers(doc_, child, PathOf(key), size);
}

void MapReader::Finish() {
  if (!valid_) return;
  for (const auto& kv : node_) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : "?";
    if (!read_.contains(key)) doc_->Error(kv.first, PathOf(key), "unknown key");
  }
}

void ApplyOverride(YAML::Node root, const std::string& assignment, bool allow_new_keys) {
  const auto fail = [&](const std::string& message) {
    throw InputError(Diagnostic{"--set", 0, assignment, message});
  };
  const std::size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) fail("expected key.path=value");
  const std::string path = assignment.substr(0, eq);
  YAML::Node value;
  try {
    value = WithoutMarks(YAML::Load(assignment.substr(eq + 1)));
  } catch (const YAML::Exception& e) {
    fail("value is not valid YAML: " + e.msg);
  }
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
  YAML::Node node = root;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const std::string& part = parts[i];
    const bool last = i + 1 == parts.size();
    if (node.IsSequence()) {
      std::size_t index;
      try {
        index = std::stoul(part);
      } catch (const std::exception&) {
        fail("'" + part + "' is not an index into a list");
      }
      if (index >= node.size()) fail("index " + part + " is past the end of the list");
      if (last) {
        node[index] = value;
        return;
      }
      node.reset(node[index]);
    } else if (node.IsMap()) {
      const bool exists = Lookup(node, part).IsDefined();
      if (!exists && !allow_new_keys) fail("no key '" + part + "' here");
      if (!exists && !last) node[part] = YAML::Node(YAML::NodeType::Map);
      if (last) {
        node[part] = value;
        return;
      }
      node.reset(node[part]);
    } else {
      fail("'" + part + "' is below a plain value");
    }
  }
}

std::string IndexPath(const std::string& list, std::size_t i) {
  return list + "[" + std::to_string(i) + "]";
}

}  // namespace pavilion::scenarios
