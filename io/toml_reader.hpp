#pragma once
/// \file
/// Reading TOML tables key by key with errors that name the file, line, column and key.
/// Internal to io/: include it only from the .cpp files that parse scenario files (it
/// brings toml++ in, which is slow to compile).

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "io/budget.hpp"
#include "io/key_catalogue.hpp"
#include "io/scenario.hpp"
#include "io/units.hpp"

namespace cleave::io::toml_reader {

inline std::string format_error(const std::string& file, int line, int column, const std::string& key,
                         const std::string& message) {
  std::string out = file;
  if (line > 0) out += fmt::format(":{}:{}", line, column);
  out += ": ";
  if (!key.empty()) out += fmt::format("key '{}': ", key);
  out += message;
  return out;
}

inline int line_of(const toml::source_region& where) {
  return static_cast<int>(where.begin.line);
}
inline int column_of(const toml::source_region& where) {
  return static_cast<int>(where.begin.column);
}

/// Where a key of a table is written: its name when toml++ recorded it, else its value.
inline const toml::source_region& key_source(const toml::key& key, const toml::node& value) {
  return key.source().begin.line > 0 ? key.source() : value.source();
}

inline bool before(const toml::source_region& a, const toml::source_region& b) {
  return std::pair(a.begin.line, a.begin.column) < std::pair(b.begin.line, b.begin.column);
}

/// "a string", "an integer", ... for "expected X, found Y" messages.
inline std::string_view type_name(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a float";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::date:
      return "a date";
    case toml::node_type::time:
      return "a time";
    case toml::node_type::date_time:
      return "a date-time";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::table:
      return "a table";
    default:
      return "nothing";
  }
}

/// "'a', 'b', 'c'"
template <class Range>
std::string quoted_list(const Range& names) {
  std::string out;
  for (const auto& name : names) {
    if (!out.empty()) out += ", ";
    out += fmt::format("'{}'", name);
  }
  return out;
}

inline bool contains(std::span<const std::string_view> names, std::string_view name) {
  for (std::string_view n : names) {
    if (n == name) return true;
  }
  return false;
}

/// A key of a table and its value.
struct Entry {
  const toml::key* key = nullptr;
  const toml::node* node = nullptr;

  [[nodiscard]] const toml::source_region& where() const { return key_source(*key, *node); }
};

/// The entry of `table` written first in the file among those satisfying `pred(key, node)`;
/// an empty Entry when there is none.
template <class Pred>
Entry first_in_file(const toml::table& table, Pred pred) {
  Entry found;
  for (const auto& [key, node] : table) {
    if (!pred(key.str(), node)) continue;
    if (found.key == nullptr || before(key_source(key, node), found.where())) found = {&key, &node};
  }
  return found;
}

/// A scenario file's whole text; a missing, directory or unreadable file is a ScenarioError
/// naming it.
inline std::string read_scenario_text(const std::filesystem::path& file) {
  const std::string name = file.string();
  // Checked before opening: a FIFO or a device would block or never end.
  if (const std::string problem = input_file_problem(file); !problem.empty())
    throw ScenarioError(name, 0, 0, "",
                        problem == "does not exist" ? "file does not exist"
                                                    : "cannot be read: it " + problem +
                                                          "; cleave reads only regular files");
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  if (in) text << in.rdbuf();
  if (!in) throw ScenarioError(name, 0, 0, "", "file cannot be read");
  return text.str();
}

/// The root table of a scenario's text; a TOML syntax error or a table not among `tables`
/// (`what` names the kind of file in the message) is a ScenarioError with its position.
inline toml::table parse_root(std::string_view text, const std::string& source,
                              std::span<const std::string_view> tables, std::string_view what) {
  toml::table root;
  try {
    root = toml::parse(text, std::string_view(source));
  } catch (const toml::parse_error& e) {
    throw ScenarioError(source, line_of(e.source()), column_of(e.source()), "",
                        fmt::format("TOML syntax error: {}", e.description()));
  }
  const Entry unknown = first_in_file(root, [&](std::string_view key, const toml::node&) {
    return std::find(tables.begin(), tables.end(), key) == tables.end();
  });
  if (unknown.key != nullptr) {
    std::vector<std::string> names(tables.begin(), tables.end());
    throw ScenarioError(source, line_of(unknown.where()), column_of(unknown.where()),
                        std::string(unknown.key->str()),
                        fmt::format("unknown table; {} holds the tables {}", what,
                                    quoted_list(names)));
  }
  return root;
}

/// An interval a number must lie in.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;

  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true, true}; }
  static Range non_negative() {
    return {0.0, std::numeric_limits<double>::infinity(), false, true};
  }

  [[nodiscard]] bool holds(double v) const {
    return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  /// "> 0", ">= 0" or "in [0, 0.5)"
  [[nodiscard]] std::string describe() const {
    if (std::isinf(hi)) return fmt::format("{} {}", lo_open ? ">" : ">=", lo);
    return fmt::format("in {}{}, {}{}", lo_open ? "(" : "[", lo, hi, hi_open ? ")" : "]");
  }
};

/// How a file's numbers carry units: each key's dimension and the file's length unit, in
/// which bare lengths are written.
struct UnitContext {
  std::span<const KeyDimension> keys;
  double length_unit = 1.0;  ///< metres per bare length
};

/// A number read from the file (in SI where the reader knows units, else as written), with
/// the node it came from for follow-up checks. `node` is null when the key was absent and
/// `value` is its default.
struct Number {
  double value = 0.0;
  const toml::node* node = nullptr;
};

/// One accepted spelling of an enumerated value.
template <class T>
struct Choice {
  std::string name;
  T value;
};

/// Reads the keys of one table, naming the file, position and "table.key" in every error.
/// A reader of an absent optional table finds no keys, so every value takes its default.
class TableReader {
 public:
  /// With `units`, every number of a key the context lists is returned in SI: a bare number
  /// in the file's convention (lengths in its length unit), a string with its unit
  /// ("250 MPa"), or { value = ..., unit = "..." } (a number or an array and one unit).
  TableReader(const std::string& source, std::string name, const toml::table* table,
              const UnitContext* units = nullptr)
      : source_(source), name_(std::move(name)), table_(table), units_(units) {}

  [[nodiscard]] const UnitContext* units() const { return units_; }

  [[nodiscard]] const toml::table* table() const { return table_; }
  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] const std::string& source() const { return source_; }

  [[noreturn]] void fail(const toml::source_region& where, std::string_view key,
                         const std::string& message) const {
    throw ScenarioError(source_, line_of(where), column_of(where), name_ + "." + std::string(key),
                        message);
  }
  [[noreturn]] void fail(const toml::node& node, std::string_view key,
                         const std::string& message) const {
    fail(node.source(), key, message);
  }
  /// An error about the whole table: positioned at its header, naming the table.
  [[noreturn]] void fail_table(const std::string& message) const {
    const toml::source_region& where = table_->source();
    throw ScenarioError(source_, line_of(where), column_of(where), name_, message);
  }
  /// An error about a key that is not there: positioned at the table's header.
  [[noreturn]] void fail_absent(std::string_view key, const std::string& message) const {
    if (table_ != nullptr) fail(table_->source(), key, message);
    throw ScenarioError(source_, 1, 1, name_ + "." + std::string(key), message);
  }

  /// Rejects the first key (in file order) not among `accepted`, listing the accepted keys.
  /// Every table's list passes here, so a KeyCatalogue alive on the thread records it.
  void reject_unknown(std::span<const std::string_view> accepted) const {
    if (KeyCatalogue* catalogue = KeyCatalogue::current())
      catalogue->record(
          {source_, name_, std::vector<std::string>(accepted.begin(), accepted.end())});
    reject_unknown_keys(accepted);
  }

 private:
  void reject_unknown_keys(std::span<const std::string_view> accepted) const {
    if (table_ == nullptr) return;
    const Entry bad = first_in_file(
        *table_, [&](std::string_view key, const toml::node&) { return !contains(accepted, key); });
    if (bad.key == nullptr) return;
    fail(bad.where(), bad.key->str(),
         fmt::format("unknown key in [{}]; accepted keys: {}", name_, quoted_list(accepted)));
  }

 public:
  [[nodiscard]] const toml::node* find(std::string_view key) const {
    return table_ != nullptr ? table_->get(key) : nullptr;
  }

  /// The number at `key` (an integer or a float, or with a unit: see the constructor),
  /// finite and within `range`. Absent: the fallback (in SI where units are known), or an
  /// error when there is none.
  [[nodiscard]] Number number(std::string_view key, const Range& range,
                              std::optional<double> fallback = std::nullopt) const {
    const toml::node* node = find(key);
    if (node == nullptr) {
      if (!fallback) fail_absent(key, "missing required key");
      return {*fallback, nullptr};
    }
    if (const auto* table = node->as_table()) {
      const std::string unit = unit_of_table(*table, key);
      const toml::node* value = table->get("value");
      if (value->as_array() != nullptr) fail(*value, key, "expected one number, found an array");
      if (value->as_string() != nullptr)
        fail(*value, key,
             fmt::format("the unit is given once, as unit = \"{}\"; expected a number", unit));
      return {checked_number(*value, key, range, "", &unit), node};
    }
    return {checked_number(*node, key, range, ""), node};
  }

  /// The value at `node` as the file wrote it, for messages: "1.5", "\"0.6 mm\"".
  [[nodiscard]] static std::string written(const toml::node& node) {
    if (const auto* i = node.as_integer()) return fmt::format("{}", i->get());
    if (const auto* f = node.as_floating_point()) return fmt::format("{}", f->get());
    if (const auto* s = node.as_string()) return fmt::format("\"{}\"", s->get());
    if (const auto* t = node.as_table()) {
      const toml::node* v = t->get("value");
      const toml::node* u = t->get("unit");
      if (v != nullptr && u != nullptr && u->as_string() != nullptr)
        return fmt::format("{} {}", written(*v), u->as_string()->get());
    }
    return std::string(type_name(node));
  }

  /// A number element or value: type, unit, finiteness and range, `what` prefixing the
  /// message. `unit`: the unit of an enclosing { value, unit } table.
  [[nodiscard]] double checked_number(const toml::node& node, std::string_view key,
                                      const Range& range, const std::string& what,
                                      const std::string* unit = nullptr) const {
    const KeyDimension* dim =
        units_ != nullptr ? find_key_dimension(units_->keys, name_, key) : nullptr;
    double value = 0.0;
    bool bare = true;
    if (const auto* i = node.as_integer()) {
      value = static_cast<double>(i->get());
    } else if (const auto* f = node.as_floating_point()) {
      value = f->get();
    } else if (const auto* text = node.as_string(); text != nullptr && units_ != nullptr) {
      value = quantity(node, key, text->get(), dim, what);
      bare = false;
    } else {
      fail(node, key,
           fmt::format("{}expected a number (integer or float){}, found {}", what,
                       units_ != nullptr && dim != nullptr ? " or a string with its unit" : "",
                       type_name(node)));
    }
    if (!std::isfinite(value)) {
      fail(node, key, fmt::format("{}expected a finite number, found {}", what, value));
    }
    if (bare && unit != nullptr) {
      value = quantity(node, key, fmt::format("{} {}", value, *unit), dim, what);
    } else if (bare && dim != nullptr) {
      // A bare number in the file's convention: SI, lengths in its length unit.
      if (dim->length_power == 1) value = value * units_->length_unit;
      if (dim->length_power == -1) value = value / units_->length_unit;
    }
    if (!range.holds(value)) {
      const std::string shown =
          unit != nullptr ? fmt::format("{} {}", written(node), *unit) : written(node);
      fail(node, key, fmt::format("{}must be {}, found {}", what, range.describe(), shown));
    }
    return value;
  }

  /// An array of exactly `count` numbers, each within `range` (with units: each element a
  /// number or a string with its unit, or { value = [...], unit = "..." }).
  [[nodiscard]] std::vector<double> numbers(std::string_view key, std::size_t count,
                                            const Range& range) const {
    const toml::node* node = find(key);
    if (node == nullptr) fail_absent(key, "missing required key");
    std::optional<std::string> unit;
    const toml::node* values = node;
    if (const auto* table = node->as_table(); table != nullptr && units_ != nullptr) {
      unit = unit_of_table(*table, key);
      values = table->get("value");
    }
    const auto* array = values->as_array();
    if (array == nullptr) {
      fail(*values, key,
           fmt::format("expected an array of {} numbers, found {}", count, type_name(*values)));
    }
    if (array->size() != count) {
      fail(*values, key,
           fmt::format("expected an array of {} numbers, found {} elements", count, array->size()));
    }
    std::vector<double> out;
    for (std::size_t i = 0; i < count; ++i) {
      const toml::node& e = *array->get(i);
      if (unit && e.as_string() != nullptr)
        fail(e, key,
             fmt::format("element {}: the unit is given once, as unit = \"{}\"; expected a number",
                         i + 1, *unit));
      out.push_back(checked_number(e, key, range, fmt::format("element {}: ", i + 1),
                                   unit ? &*unit : nullptr));
    }
    return out;
  }

  /// The integer at `key`, at least `min` and at most `max`; absent: `fallback`.
  [[nodiscard]] std::int64_t integer(std::string_view key, std::int64_t min, std::int64_t fallback,
                                     std::int64_t max = std::numeric_limits<std::int64_t>::max()) const {
    const toml::node* node = find(key);
    if (node == nullptr) return fallback;
    const auto* i = node->as_integer();
    if (i == nullptr) {
      fail(*node, key, fmt::format("expected an integer, found {}", type_name(*node)));
    }
    if (i->get() < min) {
      fail(*node, key, fmt::format("must be >= {}, found {}", min, i->get()));
    }
    if (i->get() > max) {
      fail(*node, key, fmt::format("must be <= {}, found {}", max, i->get()));
    }
    return i->get();
  }
  /// The same for an `int` setting: values beyond INT_MAX are errors, not wrapped around.
  [[nodiscard]] int int_integer(std::string_view key, int min, int fallback) const {
    return static_cast<int>(integer(key, min, fallback, std::numeric_limits<int>::max()));
  }

  /// The boolean at `key`; absent: `fallback`.
  [[nodiscard]] bool boolean(std::string_view key, bool fallback) const {
    const toml::node* node = find(key);
    if (node == nullptr) return fallback;
    const auto* b = node->as_boolean();
    if (b == nullptr) fail(*node, key, fmt::format("expected true or false, found {}", type_name(*node)));
    return b->get();
  }
  /// The string at `key`; absent: `fallback`, or an error when there is none.
  [[nodiscard]] std::string string(std::string_view key,
                                   std::optional<std::string> fallback = std::nullopt) const {
    const toml::node* node = find(key);
    if (node == nullptr) {
      if (!fallback) fail_absent(key, "missing required key");
      return *fallback;
    }
    const auto* s = node->as_string();
    if (s == nullptr) {
      fail(*node, key, fmt::format("expected a string, found {}", type_name(*node)));
    }
    return s->get();
  }

  /// The string at `key` looked up among `choices`; absent: `fallback`, or an error when
  /// there is none. Unknown spellings are errors listing the accepted ones.
  template <class T>
  [[nodiscard]] T choose(std::string_view key, const std::vector<Choice<T>>& choices,
                         std::optional<T> fallback = std::nullopt) const {
    const toml::node* node = find(key);
    if (node == nullptr && fallback) return *fallback;
    const std::string text = string(key);
    for (const auto& choice : choices) {
      if (choice.name == text) return choice.value;
    }
    std::vector<std::string> names;
    for (const auto& choice : choices) names.push_back(choice.name);
    fail(*node, key, fmt::format("unknown value '{}'; accepted: {}", text, quoted_list(names)));
  }

 private:
  /// "250 MPa" at `key` in SI; a key without a dimension, a malformed text or a unit of
  /// another dimension is an error naming the key's dimension.
  [[nodiscard]] double quantity(const toml::node& node, std::string_view key,
                                const std::string& text, const KeyDimension* dim,
                                const std::string& what) const {
    if (dim == nullptr) {
      fail(node, key, fmt::format("{}is a plain number, without a unit; found \"{}\"", what, text));
    }
    try {
      return parse_quantity(text, dim->dimension);
    } catch (const UnitError& e) {
      fail(node, key, fmt::format("{}{}", what, e.what()));
    }
  }

  /// The unit of { value = ..., unit = "..." } at `key` (units known, both keys there).
  [[nodiscard]] std::string unit_of_table(const toml::table& table, std::string_view key) const {
    static constexpr std::string_view kValueUnit[] = {"value", "unit"};
    const TableReader t(source_, name_ + "." + std::string(key), &table);
    if (units_ == nullptr || find_key_dimension(units_->keys, name_, key) == nullptr) {
      fail(table, key, fmt::format("expected a number, found {}", type_name(table)));
    }
    t.reject_unknown_keys(kValueUnit);  // a { value, unit } pair, not a table of the format
    if (table.get("value") == nullptr)
      t.fail_absent("value", "missing required key: the number(s)");
    return t.string("unit");
  }

  const std::string& source_;
  std::string name_;
  const toml::table* table_;
  const UnitContext* units_ = nullptr;
};

}  // namespace cleave::io::toml_reader
