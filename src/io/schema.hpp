#pragma once
// The case-file schema machinery: every key a case may hold is declared once, with its type,
// default, allowed range or choices, unit and a one-line doc (see case_schema.cpp for the
// declaration itself). The reader checks a TOML file against it, the resolved-case writer and the
// user guide's key table are generated from it.
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace settle::io {

enum class Kind { Boolean, Integer, Real, String, RealArray };

using Value = std::variant<bool, std::int64_t, double, std::string, std::vector<double>>;

/// Allowed interval for a number (and for each element of a number array).
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_inclusive = true;
  bool max_inclusive = true;
  bool contains(double v) const;
  /// e.g. "> 0.0", "in (0.5, 2.0]"; with `integral`, bounds without a decimal point ("in [1, 50]").
  std::string describe(bool integral = false) const;
};

/// One key of the case file. `path` is the dotted TOML path ("fluid.density",
/// "domain.walls.x"). A key without a default is optional: absent means "not given", and the
/// code that needs it checks for it (for example `particle.diameter` only for some shapes).
struct KeySpec {
  std::string path;
  Kind kind = Kind::Real;
  std::optional<Value> default_value;
  std::string unit;
  std::string doc;
  Range range;
  std::vector<std::string> choices;  ///< allowed strings (Kind::String); empty = any
  int array_length = 0;              ///< required length (Kind::RealArray); 0 = any non-empty
};

std::string_view to_string(Kind kind);
/// Renders a value as TOML (numbers with round-trip precision).
std::string to_toml(const Value& value);

/// The set of declared keys, in declaration order.
class Schema {
 public:
  explicit Schema(std::vector<KeySpec> keys);
  const std::vector<KeySpec>& keys() const { return keys_; }
  /// nullptr when `path` is not declared.
  const KeySpec* find(std::string_view path) const;
  /// The declared key closest to `path` by edit distance, if close enough to be a likely typo.
  std::optional<std::string> suggest(std::string_view path) const;

 private:
  std::vector<KeySpec> keys_;
};

/// Checks one value against its declaration; returns an error text ("" when valid) that names
/// the key, the value and what is allowed.
std::string check_value(const KeySpec& spec, const Value& value);

/// The values of a case after checking: every declared key with a default is present.
class CaseValues {
 public:
  explicit CaseValues(const Schema& schema) : schema_(&schema) {}
  const Schema& schema() const { return *schema_; }

  bool has(std::string_view path) const;
  /// True when the user's file set the key (as opposed to the default).
  bool given(std::string_view path) const;
  double real(std::string_view path) const;
  std::int64_t integer(std::string_view path) const;
  bool boolean(std::string_view path) const;
  const std::string& string(std::string_view path) const;
  const std::vector<double>& reals(std::string_view path) const;
  const Value& value(std::string_view path) const;

  /// Sets a value after checking it against the schema; throws settle::InputError naming
  /// `origin` (a file or "--set") on an undeclared key or an invalid value.
  void set(std::string_view path, Value value, std::string_view origin, bool user_given = true);

 private:
  const KeySpec& spec(std::string_view path) const;
  const Schema* schema_;
  std::map<std::string, Value, std::less<>> values_;
  std::map<std::string, bool, std::less<>> given_;
};

/// Applies the defaults of `schema`, then the keys of TOML text `toml_text` (from `origin`,
/// used in messages). Unknown keys, wrong types and values out of range are InputErrors that
/// name the origin, the key, the value and what is allowed (with a "did you mean" for typos).
CaseValues parse_case(const Schema& schema, std::string_view toml_text, std::string_view origin);

/// Applies one "key=value" override (command line --set); the value is parsed as TOML.
void apply_override(CaseValues& values, std::string_view assignment);

/// The key of an override as apply_override reads it: the text before '=', blanks dropped ("" when
/// there is no '=').
std::string override_key(std::string_view assignment);

/// Writes every key (defaults included) as TOML, grouped by table, with each key's doc and unit
/// as a comment.
std::string write_resolved_toml(const CaseValues& values);

/// `resolved_text` (write_resolved_toml's output and anything after it) with the line of `path`
/// written anew from `values`, every other byte kept: a restart that changes run.end_time keeps
/// which keys the first run took by default (parsing the text back would mark every key given).
std::string rewrite_resolved_value(std::string_view resolved_text, const CaseValues& values, std::string_view path);

/// The key table of the user guide, as Markdown.
std::string schema_markdown(const Schema& schema);

}  // namespace settle::io
