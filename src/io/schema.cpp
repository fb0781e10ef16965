#include "io/schema.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "common/error.hpp"

namespace settle::io {
namespace {

// A value or an assignment as a message shows it: at most `max_bytes`, cut at a character boundary
// (UTF-8) and ended with "...". A 10 MB string or a 1.5-million-number array once filled a single
// line of stderr.
std::string shortened(std::string_view text, std::size_t max_bytes = 80) {
  if (text.size() <= max_bytes) return std::string(text);
  std::size_t cut = max_bytes - 3;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;  // a continuation byte
  return std::string(text.substr(0, cut)) + "...";
}

std::string format_number(double v) {
  // Shortest text that reads back to the same double; TOML needs a '.' or exponent in floats.
  std::string s = fmt::format("{}", v);
  if (std::isfinite(v) && s.find_first_of(".eEn") == std::string::npos) s += ".0";
  if (std::isnan(v)) s = "nan";
  if (std::isinf(v)) s = v > 0 ? "inf" : "-inf";
  return s;
}

std::string leaf_of(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? path : path.substr(dot + 1);
}

// "fluid.density" -> "[fluid] density"; "domain.walls.x" -> "[domain] walls.x"
std::string display_key(std::string_view path) {
  const std::string p(path);
  const auto dot = p.find('.');
  if (dot == std::string::npos) return p;
  return fmt::format("[{}] {}", p.substr(0, dot), p.substr(dot + 1));
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0u : 1u)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

std::optional<Value> value_from_node(const toml::node& node, Kind kind) {
  switch (kind) {
    case Kind::Boolean:
      if (auto v = node.as_boolean()) return Value(v->get());
      return std::nullopt;
    case Kind::Integer:
      if (auto v = node.as_integer()) return Value(v->get());
      return std::nullopt;
    case Kind::Real:
      if (auto v = node.as_floating_point()) return Value(v->get());
      if (auto v = node.as_integer()) return Value(static_cast<double>(v->get()));
      return std::nullopt;
    case Kind::String:
      if (auto v = node.as_string()) return Value(v->get());
      return std::nullopt;
    case Kind::RealArray: {
      const toml::array* array = node.as_array();
      if (!array) return std::nullopt;
      std::vector<double> out;
      for (const toml::node& element : *array) {
        if (auto f = element.as_floating_point())
          out.push_back(f->get());
        else if (auto i = element.as_integer())
          out.push_back(static_cast<double>(i->get()));
        else
          return std::nullopt;
      }
      return Value(std::move(out));
    }
  }
  return std::nullopt;
}

// The tables a case may hold ("fluid", "domain", "domain.walls"): every proper prefix of a
// declared key.
std::vector<std::string> table_paths(const Schema& schema) {
  std::vector<std::string> tables;
  for (const KeySpec& k : schema.keys())
    for (auto dot = k.path.find('.'); dot != std::string::npos; dot = k.path.find('.', dot + 1)) {
      std::string prefix = k.path.substr(0, dot);
      if (std::find(tables.begin(), tables.end(), prefix) == tables.end()) tables.push_back(std::move(prefix));
    }
  return tables;
}

bool is_table_path(const Schema& schema, std::string_view path) {
  const auto tables = table_paths(schema);
  return std::find(tables.begin(), tables.end(), path) != tables.end();
}

// The keys directly under a table, for messages ("x, y, z").
std::string keys_under(const Schema& schema, const std::string& table) {
  std::string keys;
  for (const KeySpec& k : schema.keys())
    if (k.path.rfind(table + ".", 0) == 0) keys += (keys.empty() ? "" : ", ") + k.path.substr(table.size() + 1);
  return keys;
}

std::optional<std::string> suggest_table(const Schema& schema, std::string_view path) {
  std::optional<std::string> best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const std::string& t : table_paths(schema)) {
    const std::size_t d = edit_distance(path, t);
    if (d < best_distance) best_distance = d, best = t;
  }
  if (best_distance <= std::max<std::size_t>(2, path.size() / 3)) return best;
  return std::nullopt;
}

std::string node_text(const toml::node& node) {
  std::ostringstream out;
  node.visit([&](auto&& n) { out << n; });
  return shortened(out.str(), 60);
}

void walk(const toml::table& table, const std::string& prefix, CaseValues& values, std::string_view origin) {
  for (auto&& [key, node] : table) {
    const std::string path = prefix.empty() ? std::string(key.str()) : prefix + "." + std::string(key.str());
    const KeySpec* spec = values.schema().find(path);
    if (!spec && node.is_table()) {
      // An unknown table is refused even when empty: "[flud]" with no keys would otherwise
      // pass silently and leave the user's intended values at their defaults.
      if (!is_table_path(values.schema(), path)) {
        std::string message = fmt::format("{}: unknown table [{}]", origin, path);
        if (auto close = suggest_table(values.schema(), path))
          message += fmt::format(" (did you mean [{}]?)", *close);
        else
          message += "; see `settle schema` for the tables and keys a case may hold";
        throw InputError(message);
      }
      walk(*node.as_table(), path, values, origin);
      continue;
    }
    if (!spec && is_table_path(values.schema(), path)) {
      throw InputError(fmt::format("{}: {} = {}: expected a table with the keys {}", origin, display_key(path),
                                   node_text(node), keys_under(values.schema(), path)));
    }
    if (!spec) {
      std::string message = fmt::format("{}: unknown key {}", origin, display_key(path));
      if (auto close = values.schema().suggest(path))
        message += fmt::format(" (did you mean {}?)", display_key(*close));
      else
        message += fmt::format("; see `settle schema` for the keys a case may hold");
      throw InputError(message);
    }
    auto value = value_from_node(node, spec->kind);
    if (!value)
      throw InputError(
          fmt::format("{}: {} = {}: expected {}", origin, display_key(path), node_text(node), to_string(spec->kind)));
    values.set(path, std::move(*value), origin);
  }
}

}  // namespace

bool Range::contains(double v) const {
  if (std::isnan(v)) return false;
  const bool above = min_inclusive ? v >= min : v > min;
  const bool below = max_inclusive ? v <= max : v < max;
  return above && below;
}

std::string Range::describe(bool integral) const {
  const auto number = [integral](double v) {
    return integral ? fmt::format("{}", static_cast<long long>(v)) : format_number(v);
  };
  const bool has_min = std::isfinite(min), has_max = std::isfinite(max);
  if (has_min && has_max)
    return fmt::format("in {}{}, {}{}", min_inclusive ? "[" : "(", number(min), number(max), max_inclusive ? "]" : ")");
  if (has_min) return fmt::format("{} {}", min_inclusive ? ">=" : ">", number(min));
  if (has_max) return fmt::format("{} {}", max_inclusive ? "<=" : "<", number(max));
  return "finite";
}

std::string_view to_string(Kind kind) {
  switch (kind) {
    case Kind::Boolean:
      return "a boolean (true or false)";
    case Kind::Integer:
      return "an integer";
    case Kind::Real:
      return "a number";
    case Kind::String:
      return "a string";
    case Kind::RealArray:
      return "an array of numbers";
  }
  return "?";
}

std::string to_toml(const Value& value) {
  struct Visitor {
    std::string operator()(bool b) const { return b ? "true" : "false"; }
    std::string operator()(std::int64_t i) const { return std::to_string(i); }
    std::string operator()(double d) const { return format_number(d); }
    // A TOML basic string: besides '"' and '\', every control character (U+0000-U+001F and
    // U+007F) must be escaped, or the resolved case would not read back (fuzz_case's round-trip
    // check, docs/fuzzing.md). Other bytes are copied: the text came from a TOML parser (UTF-8).
    std::string operator()(const std::string& s) const {
      std::string out = "\"";
      for (char c : s) {
        const auto byte = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\')
          out += std::string{'\\', c};
        else if (c == '\n')
          out += "\\n";
        else if (c == '\t')
          out += "\\t";
        else if (c == '\r')
          out += "\\r";
        else if (byte < 0x20 || byte == 0x7F)
          out += fmt::format("\\u{:04X}", byte);
        else
          out += c;
      }
      return out + "\"";
    }
    std::string operator()(const std::vector<double>& v) const {
      std::string out = "[";
      for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + format_number(v[i]);
      return out + "]";
    }
  };
  return std::visit(Visitor{}, value);
}

Schema::Schema(std::vector<KeySpec> keys) : keys_(std::move(keys)) {
  for (const KeySpec& k : keys_)
    if (k.default_value && !check_value(k, *k.default_value).empty())
      throw std::logic_error("schema: default of " + k.path + " violates its own declaration");
}

const KeySpec* Schema::find(std::string_view path) const {
  for (const KeySpec& k : keys_)
    if (k.path == path) return &k;
  return nullptr;
}

std::optional<std::string> Schema::suggest(std::string_view path) const {
  std::optional<std::string> best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  const std::string wanted_leaf = leaf_of(std::string(path));
  for (const KeySpec& k : keys_) {
    // A misspelt leaf in the right table, or the right leaf in the wrong table.
    const std::size_t d = std::min(edit_distance(path, k.path),
                                   leaf_of(k.path) == wanted_leaf ? std::size_t{1} : edit_distance(path, k.path));
    if (d < best_distance) best_distance = d, best = k.path;
  }
  const std::size_t allowed = std::max<std::size_t>(2, wanted_leaf.size() / 3);
  if (best_distance <= allowed) return best;
  return std::nullopt;
}

std::string check_value(const KeySpec& spec, const Value& value) {
  const std::string shown = shortened(to_toml(value));
  const auto fail = [&](const std::string& what) {
    return fmt::format("{} = {}: must be {}{}", display_key(spec.path), shown, what,
                       spec.unit.empty() ? "" : fmt::format(" ({})", spec.unit));
  };
  switch (spec.kind) {
    case Kind::Boolean:
      if (!std::holds_alternative<bool>(value)) return fail(std::string(to_string(spec.kind)));
      return "";
    case Kind::Integer: {
      if (!std::holds_alternative<std::int64_t>(value)) return fail(std::string(to_string(spec.kind)));
      const double v = static_cast<double>(std::get<std::int64_t>(value));
      return spec.range.contains(v) ? "" : fail(spec.range.describe(true));
    }
    case Kind::Real: {
      if (!std::holds_alternative<double>(value)) return fail(std::string(to_string(spec.kind)));
      const double v = std::get<double>(value);
      if (!std::isfinite(v)) return fail("finite, " + spec.range.describe());
      return spec.range.contains(v) ? "" : fail(spec.range.describe());
    }
    case Kind::String: {
      if (!std::holds_alternative<std::string>(value)) return fail(std::string(to_string(spec.kind)));
      const auto& s = std::get<std::string>(value);
      if (spec.choices.empty() || std::find(spec.choices.begin(), spec.choices.end(), s) != spec.choices.end())
        return "";
      std::string allowed;
      for (const auto& c : spec.choices) allowed += fmt::format("{}\"{}\"", allowed.empty() ? "" : ", ", c);
      return fail("one of " + allowed);
    }
    case Kind::RealArray: {
      if (!std::holds_alternative<std::vector<double>>(value)) return fail(std::string(to_string(spec.kind)));
      const auto& v = std::get<std::vector<double>>(value);
      if (spec.array_length > 0 && static_cast<int>(v.size()) != spec.array_length)
        return fail(fmt::format("an array of {} numbers", spec.array_length));
      if (v.empty()) return fail("a non-empty array");
      const std::string range = spec.range.describe();
      for (double x : v)
        if (!std::isfinite(x) || !spec.range.contains(x))
          return fail(range == "finite" ? "an array of finite numbers"
                                        : "an array whose elements are finite and " + range);
      return "";
    }
  }
  return "";
}

bool CaseValues::has(std::string_view path) const { return values_.find(path) != values_.end(); }

bool CaseValues::given(std::string_view path) const {
  const auto it = given_.find(path);
  return it != given_.end() && it->second;
}

const KeySpec& CaseValues::spec(std::string_view path) const {
  const KeySpec* s = schema_->find(path);
  if (!s) throw std::logic_error("case: key " + std::string(path) + " is not declared in the schema");
  return *s;
}

const Value& CaseValues::value(std::string_view path) const {
  spec(path);
  const auto it = values_.find(path);
  if (it == values_.end()) throw InputError(fmt::format("{} is required here but not given", display_key(path)));
  return it->second;
}

double CaseValues::real(std::string_view path) const { return std::get<double>(value(path)); }
std::int64_t CaseValues::integer(std::string_view path) const { return std::get<std::int64_t>(value(path)); }
bool CaseValues::boolean(std::string_view path) const { return std::get<bool>(value(path)); }
const std::string& CaseValues::string(std::string_view path) const { return std::get<std::string>(value(path)); }
const std::vector<double>& CaseValues::reals(std::string_view path) const {
  return std::get<std::vector<double>>(value(path));
}

void CaseValues::set(std::string_view path, Value v, std::string_view origin, bool user_given) {
  const KeySpec* s = schema_->find(path);
  if (!s) {
    std::string message = fmt::format("{}: unknown key {}", origin, display_key(path));
    if (auto close = schema_->suggest(path)) message += fmt::format(" (did you mean {}?)", display_key(*close));
    throw InputError(message);
  }
  // Integers are accepted where reals are declared (TOML writes 1000 for 1000.0).
  if (s->kind == Kind::Real && std::holds_alternative<std::int64_t>(v))
    v = static_cast<double>(std::get<std::int64_t>(v));
  if (const std::string error = check_value(*s, v); !error.empty())
    throw InputError(fmt::format("{}: {}", origin, error));
  values_.insert_or_assign(std::string(path), std::move(v));
  given_.insert_or_assign(std::string(path), user_given);
}

CaseValues parse_case(const Schema& schema, std::string_view toml_text, std::string_view origin) {
  CaseValues values(schema);
  for (const KeySpec& k : schema.keys())
    if (k.default_value) values.set(k.path, *k.default_value, "schema default", false);
  toml::table table;
  try {
    table = toml::parse(toml_text, origin);
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    throw InputError(fmt::format("{}:{}:{}: TOML syntax error: {}", origin, where.line, where.column, e.description()));
  }
  walk(table, "", values, origin);
  return values;
}

namespace {
bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
}  // namespace

std::string override_key(std::string_view assignment) {
  const auto eq = assignment.find('=');
  std::string path(assignment.substr(0, eq == std::string_view::npos ? 0 : eq));
  path.erase(std::remove_if(path.begin(), path.end(), is_space), path.end());
  return path;
}

void apply_override(CaseValues& values, std::string_view assignment) {
  const std::string shown = shortened(assignment);  // the assignment as messages quote it
  const auto eq = assignment.find('=');
  const std::string path = override_key(assignment);
  if (eq == std::string_view::npos || path.empty())
    throw InputError(fmt::format("--set {}: expected key=value, e.g. --set fluid.density=1000", shown));
  const Schema& schema = values.schema();
  const KeySpec* spec = schema.find(path);
  if (!spec && is_table_path(schema, path)) {
    const std::string keys = keys_under(schema, path);
    throw InputError(fmt::format("--set {}: {} is a table; set its keys ({}) one at a time, e.g. --set {}.{}=...",
                                 shown, path, keys, path, keys.substr(0, keys.find(','))));
  }
  if (!spec) {
    // Dotted names here: that is how a key is written on the command line.
    std::string message = fmt::format("--set: unknown key {}", path);
    if (auto close = schema.suggest(path))
      message += fmt::format(" (did you mean {}?)", *close);
    else
      message += "; see `settle schema` for the keys a case may hold";
    throw InputError(message);
  }
  const std::string_view text = assignment.substr(eq + 1);
  if (std::all_of(text.begin(), text.end(), is_space))
    throw InputError(fmt::format("--set {}: no value after '='; expected {}", shown, to_string(spec->kind)));
  const std::string document = "v = " + std::string(text);
  toml::table table;
  try {
    table = toml::parse(std::string_view(document), std::string_view("--set"));
  } catch (const toml::parse_error& e) {
    if (spec->kind == Kind::String)
      throw InputError(fmt::format("--set {}: not a TOML value; a string needs double quotes, e.g. --set '{}=\"{}\"'",
                                   shown, path, shortened(text)));
    throw InputError(fmt::format("--set {}: the value is not valid TOML ({}); expected {}", shown, e.description(),
                                 to_string(spec->kind)));
  }
  // "--set 'a=1\nb=2'" parses as two keys: only one value may follow the '='.
  if (table.size() != 1) throw InputError(fmt::format("--set {}: expected a single value after '='", shown));
  auto value = value_from_node(*table.get("v"), spec->kind);
  if (!value) throw InputError(fmt::format("--set {}: expected {} for {}", shown, to_string(spec->kind), path));
  values.set(path, std::move(*value), "--set");
}

namespace {

// A key's table and its name inside it: nested tables (domain.walls.x) are written with dotted
// keys inside their top-level table.
std::pair<std::string, std::string> table_and_key(const std::string& path) {
  const auto dot = path.find('.');
  if (dot == std::string::npos) return {std::string(), path};
  return {path.substr(0, dot), path.substr(dot + 1)};
}

std::string resolved_line(const CaseValues& values, const KeySpec& k) {
  return fmt::format("{} = {}  # {}{}{}\n", table_and_key(k.path).second, to_toml(values.value(k.path)),
                     k.unit.empty() ? "" : "[" + k.unit + "] ", k.doc, values.given(k.path) ? "" : " (default)");
}

}  // namespace

std::string write_resolved_toml(const CaseValues& values) {
  std::string out;
  std::string current_table = "\x01";
  for (const KeySpec& k : values.schema().keys()) {
    if (!values.has(k.path)) continue;
    const std::string table = table_and_key(k.path).first;
    if (table != current_table) {
      out += fmt::format("{}[{}]\n", out.empty() ? "" : "\n", table);
      current_table = table;
    }
    out += resolved_line(values, k);
  }
  return out;
}

std::string rewrite_resolved_value(std::string_view resolved_text, const CaseValues& values, std::string_view path) {
  const KeySpec* spec = values.schema().find(path);
  if (!spec || !values.has(path)) throw std::logic_error(fmt::format("rewrite_resolved_value: no value of {}", path));
  const auto [table, key] = table_and_key(spec->path);
  const std::string header = fmt::format("[{}]\n", table);
  const std::size_t table_at = resolved_text.rfind(header, 0) == 0 ? 0 : resolved_text.find("\n" + header);
  if (table_at == std::string_view::npos)
    throw std::logic_error(fmt::format("rewrite_resolved_value: no table [{}] in the resolved case", table));
  const std::size_t line_at = resolved_text.find("\n" + key + " = ", table_at + 1);
  const std::size_t next_table = resolved_text.find("\n[", table_at + 1);
  if (line_at == std::string_view::npos || line_at > next_table)
    throw std::logic_error(fmt::format("rewrite_resolved_value: no line of {} in the resolved case", path));
  const std::size_t line_end = resolved_text.find('\n', line_at + 1);
  std::string out(resolved_text.substr(0, line_at + 1));
  out += resolved_line(values, *spec);
  if (line_end != std::string_view::npos) out += resolved_text.substr(line_end + 1);
  return out;
}

std::string schema_markdown(const Schema& schema) {
  std::string out = "| key | type | default | allowed | unit | meaning |\n| --- | --- | --- | --- | --- | --- |\n";
  for (const KeySpec& k : schema.keys()) {
    std::string allowed;
    if (!k.choices.empty()) {
      for (const auto& c : k.choices) allowed += fmt::format("{}`{}`", allowed.empty() ? "" : ", ", c);
    } else if (k.kind == Kind::Real || k.kind == Kind::Integer || k.kind == Kind::RealArray) {
      allowed = k.range.describe(k.kind == Kind::Integer);
      if (k.kind == Kind::RealArray && k.array_length > 0)
        allowed = fmt::format("{} numbers, each {}", k.array_length, allowed);
    }
    const std::string default_text = k.default_value ? fmt::format("`{}`", to_toml(*k.default_value)) : "(none)";
    out += fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", display_key(k.path), to_string(k.kind), default_text,
                       allowed, k.unit, k.doc);
  }
  return out;
}

}  // namespace settle::io
