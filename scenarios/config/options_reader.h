#pragma once

// One reader per options struct: ReadOptions binds the keys of one YAML mapping
// to fields of a `FooOptions`, reads each key that is present for its type only
// (a finite number, an integer, true/false, a list of numbers), then runs
// `FooOptions::Validate()`, the one place where the fields' ranges live, and
// reports what it throws as `file:line: key.path: <Validate's message>` at the
// key of the field it names.
//
// Validate() names the field at fault as the first identifier of its message
// that is the name of a bound field, e.g. "WanderOptions.avoid_turn_rate_radps
// must be in (0, 10] rad/s" (identifiers are split at '.', so a struct prefix
// is fine). A message naming no bound field is reported at the mapping itself.
//
//   using Wander = nav::WanderOptions;
//   ReadOptions(r, &wander, {{"cruise_speed_mps", &Wander::cruise_speed_mps},
//                            {"min_avoid_scans", &Wander::min_avoid_scans}});
//   // A key named otherwise than its field, in degrees for a field in radians:
//   ReadOptions(r, &laser, {{"fov_deg", "fov_rad", &sim::LaserScannerOptions::fov_rad,
//   kDegToRad}});
//
// Required keys: RequireKeys(r, {...}) before ReadOptions. Cross-field checks
// belong in Validate() too; checks against other data (a URDF's nominal
// values, a map's node ids) stay in the loader.

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "scenarios/config/yaml_reader.h"

namespace pavilion::scenarios {

namespace options_reader_internal {

// Each reads `key` of `r` into `*value` when present and of the right type
// (numbers finite, ints within int), numbers times `scale`; reports the key and
// leaves `*value` otherwise.
void ReadField(MapReader& r, const std::string& key, double scale, double* value);
void ReadField(MapReader& r, const std::string& key, double scale, int* value);
void ReadField(MapReader& r, const std::string& key, double scale, bool* value);
void ReadField(MapReader& r, const std::string& key, double scale, std::optional<double>* value);
void ReadField(MapReader& r, const std::string& key, double scale, Eigen::Vector2d* value);
void ReadField(MapReader& r, const std::string& key, double scale, Eigen::Vector3d* value);

}  // namespace options_reader_internal

// One key of a mapping bound to a field of `Options` (a double, int, bool,
// std::optional<double>, Eigen::Vector2d or Eigen::Vector3d member).
template <typename Options>
struct OptionField {
  // A key named like its field.
  template <typename T>
  OptionField(const char* key, T Options::*member) : OptionField(key, key, member) {}
  // A key named otherwise: `field` is the name Validate() gives; numbers in the
  // file are multiplied by `scale` (e.g. degrees in the file, radians in the struct).
  template <typename T>
  OptionField(const char* key, const char* field, T Options::*member, double scale = 1.0)
      : key(key),
        field(field),
        read([key = this->key, member, scale](MapReader& r, Options* o) {
          options_reader_internal::ReadField(r, key, scale, &(o->*member));
        }),
        restore([member](Options* o, const Options& from) { o->*member = from.*member; }) {}

  std::string key;
  std::string field;
  std::function<void(MapReader&, Options*)> read;
  std::function<void(Options*, const Options&)> restore;  // the field of `from` into *o
};

namespace options_reader_internal {

// The index in `fields` of the first identifier of `message` that is one of
// them; fields.size() when none is.
std::size_t FieldNamedIn(const std::string& message, const std::vector<std::string>& fields);

// Reports `message` at `key` of `r` (its value's line; the mapping's when absent),
// or at the mapping itself when `key` is empty.
void Report(MapReader& r, const std::string& key, const std::string& message);

}  // namespace options_reader_internal

// Reports each of `keys` that `r` lacks as a required key (ReadOptions reads
// only what is present and leaves the rest at the struct's defaults).
void RequireKeys(MapReader& r, const std::vector<std::string>& keys);

// Reads the bound keys of `r` into `*options` and validates them; returns true
// when Validate() accepted them. Every field Validate() rejects is reported once
// (after a report the field returns to its value on entry, and Validate() runs
// again to find the next). Keys not bound here are left to the caller, and to
// r.Finish() for the unknown-key check.
template <typename Options>
bool ReadOptions(MapReader& r, Options* options,
                 const std::vector<OptionField<std::type_identity_t<Options>>>& fields) {
  namespace internal = options_reader_internal;
  const Options on_entry = *options;
  std::vector<std::string> names;
  for (const auto& f : fields) {
    names.push_back(f.field);
    f.read(r, options);
  }
  std::set<std::size_t> reported;
  for (;;) {
    try {
      options->Validate();
      return reported.empty();
    } catch (const std::invalid_argument& e) {
      const std::size_t k = internal::FieldNamedIn(e.what(), names);
      if (k == fields.size()) {
        internal::Report(r, "", e.what());
        return false;
      }
      // A field that fails again at its entry value fails with another (a
      // relation between fields): it has been reported.
      if (!reported.insert(k).second) return false;
      internal::Report(r, fields[k].key, e.what());
      fields[k].restore(options, on_entry);
    }
  }
}

}  // namespace pavilion::scenarios
