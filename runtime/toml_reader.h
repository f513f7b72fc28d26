// TomlReader: typed, range-checked reads from a TOML table whose errors name file, key and value.
#pragma once

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

namespace dt {

// Reads keys of one table. Every failure throws std::invalid_argument reading
// "<source>: <key path>: <problem> (value <value>)". Finish() refuses keys nobody read, so a typo
// in a config is an error instead of a silently ignored setting; the error suggests the nearest
// key that the table may hold ("unknown key (did you mean \"host\"?)").
//
// `known_keys`, when given, lists every key the table may hold. Then a missing required key is
// reported only after any key outside the list (a mistyped `hots` is named, not `host: missing`),
// and reading a key outside the list is a broken invariant (aborts).
class TomlReader {
 public:
  TomlReader(const toml::table& table, std::string source, std::string path_prefix,
             std::vector<std::string> known_keys = {});

  // Parses text; a syntax error throws naming the source, line and column.
  static toml::table ParseText(std::string_view text, std::string_view source);

  bool Has(std::string_view key) const;

  int64_t Int(std::string_view key, int64_t lo, int64_t hi) const;
  int64_t Int(std::string_view key, int64_t fallback, int64_t lo, int64_t hi) const;
  // Integers are accepted where a real number is expected.
  double Double(std::string_view key, double lo, double hi) const;
  double Double(std::string_view key, double fallback, double lo, double hi) const;
  std::string String(std::string_view key) const;
  std::string String(std::string_view key, std::string fallback) const;
  bool Bool(std::string_view key, bool fallback) const;
  // An array of arrays of numbers ([[1, 2], [3, 4]]), each row of exactly `columns` numbers in
  // [lo, hi]; throws naming the row otherwise.
  std::vector<std::vector<double>> NumberRows(std::string_view key, size_t columns, double lo,
                                              double hi) const;
  // An array of strings, or one string as a one-element list; empty if absent.
  std::vector<std::string> StringList(std::string_view key) const;

  // Sub-tables; `known_keys` as for the constructor.
  TomlReader Table(std::string_view key, std::vector<std::string> known_keys = {}) const;
  std::optional<TomlReader> OptionalTable(std::string_view key,
                                          std::vector<std::string> known_keys = {}) const;
  // An array of tables ([[key]]); empty if absent.
  std::vector<TomlReader> TableArray(std::string_view key,
                                     std::vector<std::string> known_keys = {}) const;

  // Throws if the table holds a key that was never read.
  void Finish() const;
  // Throws for the first key of the table outside known_keys_ (none if they were not given), for
  // a check that must name a typo before a missing key it explains.
  void FailOnUnknownKeys() const;

  // Throws std::invalid_argument with this table's context for `key`.
  [[noreturn]] void Fail(std::string_view key, std::string_view problem) const;
  // Throws naming this table only, for a problem of several keys together.
  [[noreturn]] void FailTable(std::string_view problem) const;
  std::string KeyPath(std::string_view key) const;
  const std::string& source() const { return source_; }

 private:
  const toml::node* Get(std::string_view key) const;
  const toml::node& Require(std::string_view key) const;
  bool Known(std::string_view key) const;
  [[noreturn]] void FailUnknown(std::string_view key) const;

  const toml::table* table_;
  std::string source_;
  std::string prefix_;
  std::vector<std::string> known_;
  mutable std::set<std::string, std::less<>> read_;
};

// A node's value as TOML-like text, for messages.
std::string TomlValueText(const toml::node& node);

// The candidate nearest to `key` by edit distance (insertions, deletions, substitutions and
// swaps of neighbours), if it is close enough to be a likely typo of it (at most 2 edits, fewer
// than the key's length); ties go to the earlier candidate.
std::optional<std::string> NearestKey(std::string_view key,
                                      const std::vector<std::string>& candidates);

}  // namespace dt
