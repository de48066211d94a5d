#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "scenarios/config/input_error.h"

namespace pavilion::scenarios {

// Collects the diagnostics of one YAML file while a loader walks it, so that a
// file with several problems reports all of them at once.
class YamlDocument {
 public:
  // Parses `path`; a file that cannot be read or parsed becomes a diagnostic and
  // root() is then null.
  explicit YamlDocument(std::string path);
  // Wraps an already parsed node (used for --set overrides and tests).
  YamlDocument(std::string path, YAML::Node root);

  const std::string& path() const { return path_; }
  const YAML::Node& root() const { return root_; }
  YAML::Node& mutable_root() { return root_; }

  void Error(const YAML::Node& at, const std::string& key_path, const std::string& message);
  bool ok() const { return diagnostics_.empty(); }
  const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }
  // Throws InputError with every diagnostic when there is any.
  void ThrowIfErrors() const;

 private:
  std::string path_;
  YAML::Node root_;
  std::vector<Diagnostic> diagnostics_;
};

// Reads one YAML mapping: typed, range-checked fields with defaults (the fields
// of an options struct go through ReadOptions, options_reader.h, whose ranges
// are the struct's Validate()), and at
// Finish() an error for every key that no one asked for (unknown keys are
// errors). A node that is not a mapping reports one error and reads as empty.
class MapReader {
 public:
  MapReader(YamlDocument* doc, YAML::Node node, std::string path);

  bool valid() const { return valid_; }
  bool Has(const std::string& key) const;
  std::string PathOf(const std::string& key) const;
  const YAML::Node& node() const { return node_; }
  const std::string& path() const { return path_; }  // this mapping's key path

  // Raw child node (marks the key as known); null if absent (error if required).
  YAML::Node Child(const std::string& key, bool required = false);

  // A finite number in [lo, hi]; `default_value` when absent and not required.
  double Number(const std::string& key, double default_value, double lo, double hi);
  std::optional<double> RequiredNumber(const std::string& key, double lo, double hi);
  std::int64_t Integer(const std::string& key, std::int64_t default_value, std::int64_t lo,
                       std::int64_t hi);
  bool Bool(const std::string& key, bool default_value);
  std::string String(const std::string& key, const std::string& default_value);
  std::optional<std::string> RequiredString(const std::string& key);
  // One of `choices`.
  std::string Choice(const std::string& key, const std::vector<std::string>& choices,
                     const std::string& default_value, bool required = false);
  // A fixed-length list of finite numbers; nullopt (with an error if required) when bad.
  std::optional<std::vector<double>> Numbers(const std::string& key, std::size_t size,
                                             bool required);

  // Reports every key that was not read. Call once, after reading all fields.
  void Finish();

  YamlDocument* doc() const { return doc_; }

 private:
  YamlDocument* doc_;
  YAML::Node node_;
  std::string path_;
  bool valid_ = false;
  std::set<std::string> read_;
};

// The key path of item i of a list: "list[i]".
std::string IndexPath(const std::string& list, std::size_t i);

// Calls fn(reader, i) for every item of the list under `key` of `parent` (absent
// or null: none; an error unless `required`), each read as a mapping whose
// unknown keys are reported after fn returns. A non-list is one error.
template <typename Fn>
void ForEachMapping(YamlDocument* doc, MapReader& parent, const std::string& key, bool required,
                    Fn fn) {
  YAML::Node list = parent.Child(key, required);
  if (!list.IsDefined() || list.IsNull()) return;
  const std::string path = parent.PathOf(key);
  if (!list.IsSequence()) {
    doc->Error(list, path, "expected a list");
    return;
  }
  for (std::size_t i = 0; i < list.size(); ++i) {
    MapReader r(doc, list[i], IndexPath(path, i));
    if (!r.valid()) continue;
    fn(r, i);
    r.Finish();
  }
}

// A finite number from a scalar node; reports an error and returns nullopt otherwise.
std::optional<double> ReadNumber(YamlDocument* doc, const YAML::Node& node,
                                 const std::string& path);
// A list of `size` finite numbers (any size when size == 0).
std::optional<std::vector<double>> ReadNumbers(YamlDocument* doc, const YAML::Node& node,
                                               const std::string& path, std::size_t size);

// Applies a `key.path=value` override to a parsed document: mapping keys by name,
// sequence items by index ("bodies.0.mass_kg=3"); the value is parsed as YAML.
// Only existing keys may be replaced unless `allow_new_keys`, which also creates
// missing mappings on the way (the loader then rejects keys it does not know). Throws InputError
// naming the override when the path does not exist.
void ApplyOverride(YAML::Node root, const std::string& assignment, bool allow_new_keys);

}  // namespace pavilion::scenarios
