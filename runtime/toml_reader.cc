#include "runtime/toml_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "base/demand.h"

namespace dt {

TomlReader::TomlReader(const toml::table& table, std::string source, std::string path_prefix,
                       std::vector<std::string> known_keys)
    : table_(&table),
      source_(std::move(source)),
      prefix_(std::move(path_prefix)),
      known_(std::move(known_keys)) {}

toml::table TomlReader::ParseText(std::string_view text, std::string_view source) {
  try {
    return toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw std::invalid_argument(fmt::format("{}:{}:{}: TOML syntax error: {}", source,
                                            e.source().begin.line, e.source().begin.column,
                                            e.description()));
  }
}

std::string TomlValueText(const toml::node& node) {
  std::ostringstream out;
  node.visit([&](const auto& v) { out << v; });
  return out.str();
}

std::optional<std::string> NearestKey(std::string_view key,
                                      const std::vector<std::string>& candidates) {
  // Optimal string alignment distance: Levenshtein plus swaps of neighbours ("hots" -> "host").
  auto distance = [](std::string_view a, std::string_view b) {
    std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
    for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
      for (size_t j = 1; j <= b.size(); ++j) {
        const size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
        d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
        if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
          d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
      }
    }
    return d[a.size()][b.size()];
  };
  std::optional<std::string> best;
  size_t best_distance = 3;  // more than 2 edits is no typo
  for (const std::string& c : candidates) {
    if (c == key) continue;
    const size_t dist = distance(key, c);
    if (dist < best_distance && dist < key.size()) {
      best = c;
      best_distance = dist;
    }
  }
  return best;
}

std::string TomlReader::KeyPath(std::string_view key) const {
  return prefix_.empty() ? std::string(key) : fmt::format("{}.{}", prefix_, key);
}

void TomlReader::Fail(std::string_view key, std::string_view problem) const {
  const toml::node* n = table_->get(key);
  if (n != nullptr) {
    throw std::invalid_argument(
        fmt::format("{}: {}: {} (value {})", source_, KeyPath(key), problem, TomlValueText(*n)));
  }
  throw std::invalid_argument(fmt::format("{}: {}: {}", source_, KeyPath(key), problem));
}

void TomlReader::FailTable(std::string_view problem) const {
  throw std::invalid_argument(
      fmt::format("{}: {}: {}", source_, prefix_.empty() ? "top level" : prefix_, problem));
}

bool TomlReader::Has(std::string_view key) const { return table_->contains(key); }

bool TomlReader::Known(std::string_view key) const {
  return std::find(known_.begin(), known_.end(), key) != known_.end();
}

void TomlReader::FailUnknown(std::string_view key) const {
  // The keys this table may hold: the declared ones, or else the ones read so far.
  const std::vector<std::string> candidates =
      known_.empty() ? std::vector<std::string>(read_.begin(), read_.end()) : known_;
  const std::optional<std::string> nearest = NearestKey(key, candidates);
  Fail(key, nearest ? fmt::format("unknown key (did you mean \"{}\"?)", *nearest) : "unknown key");
}

void TomlReader::FailOnUnknownKeys() const {
  if (known_.empty()) return;
  for (const auto& [k, v] : *table_) {
    if (!Known(k.str())) FailUnknown(k.str());
  }
}

const toml::node* TomlReader::Get(std::string_view key) const {
  const bool known = known_.empty() || Known(key);
  if (!known) {
    std::fprintf(stderr, "TomlReader: %s is read but not among the table's known keys\n",
                 KeyPath(key).c_str());
  }
  DT_DEMAND(known);
  const toml::node* n = table_->get(key);
  if (n != nullptr) read_.emplace(key);
  return n;
}

const toml::node& TomlReader::Require(std::string_view key) const {
  const toml::node* n = Get(key);
  if (n == nullptr) {
    // A required key is missing most often because it is mistyped: name the typo first.
    FailOnUnknownKeys();
    Fail(key, "missing");
  }
  return *n;
}

int64_t TomlReader::Int(std::string_view key, int64_t lo, int64_t hi) const {
  const toml::node& n = Require(key);
  const auto v = n.value_exact<int64_t>();
  if (!v) Fail(key, "expected an integer");
  if (*v < lo || *v > hi) Fail(key, fmt::format("must be in [{}, {}]", lo, hi));
  return *v;
}

int64_t TomlReader::Int(std::string_view key, int64_t fallback, int64_t lo, int64_t hi) const {
  return Has(key) ? Int(key, lo, hi) : fallback;
}

double TomlReader::Double(std::string_view key, double lo, double hi) const {
  const toml::node& n = Require(key);
  double v = 0.0;
  if (auto d = n.value_exact<double>()) {
    v = *d;
  } else if (auto i = n.value_exact<int64_t>()) {
    v = static_cast<double>(*i);
  } else {
    Fail(key, "expected a number");
  }
  if (!std::isfinite(v) || v < lo || v > hi) Fail(key, fmt::format("must be in [{}, {}]", lo, hi));
  return v;
}

double TomlReader::Double(std::string_view key, double fallback, double lo, double hi) const {
  return Has(key) ? Double(key, lo, hi) : fallback;
}

std::vector<std::vector<double>> TomlReader::NumberRows(std::string_view key, size_t columns,
                                                        double lo, double hi) const {
  const toml::array* rows = Require(key).as_array();
  if (rows == nullptr) Fail(key, "expected an array of arrays of numbers");
  std::vector<std::vector<double>> out;
  for (size_t i = 0; i < rows->size(); ++i) {
    const toml::array* row = (*rows)[i].as_array();
    if (row == nullptr || row->size() != columns) {
      Fail(key, fmt::format("row {} must be an array of {} numbers", i, columns));
    }
    std::vector<double> values;
    for (size_t k = 0; k < row->size(); ++k) {
      const toml::node& n = (*row)[k];
      double v = 0.0;
      if (auto d = n.value_exact<double>()) {
        v = *d;
      } else if (auto j = n.value_exact<int64_t>()) {
        v = static_cast<double>(*j);
      } else {
        Fail(key, fmt::format("row {} item {} is not a number", i, k));
      }
      if (!std::isfinite(v) || v < lo || v > hi) {
        Fail(key, fmt::format("row {} item {} = {} must be in [{}, {}]", i, k, v, lo, hi));
      }
      values.push_back(v);
    }
    out.push_back(std::move(values));
  }
  return out;
}

std::string TomlReader::String(std::string_view key) const {
  const toml::node& n = Require(key);
  const auto v = n.value_exact<std::string>();
  if (!v) Fail(key, "expected a string");
  return *v;
}

std::string TomlReader::String(std::string_view key, std::string fallback) const {
  return Has(key) ? String(key) : fallback;
}

bool TomlReader::Bool(std::string_view key, bool fallback) const {
  if (!Has(key)) return fallback;
  const auto v = Require(key).value_exact<bool>();
  if (!v) Fail(key, "expected true or false");
  return *v;
}

std::vector<std::string> TomlReader::StringList(std::string_view key) const {
  std::vector<std::string> out;
  const toml::node* n = Get(key);
  if (n == nullptr) return out;
  if (auto one = n->value_exact<std::string>()) {
    out.push_back(*one);
    return out;
  }
  const toml::array* a = n->as_array();
  if (a == nullptr) Fail(key, "expected a string or an array of strings");
  for (const toml::node& e : *a) {
    const auto v = e.value_exact<std::string>();
    if (!v) Fail(key, "expected a string or an array of strings");
    out.push_back(*v);
  }
  return out;
}

TomlReader TomlReader::Table(std::string_view key, std::vector<std::string> known_keys) const {
  const toml::table* t = Require(key).as_table();
  if (t == nullptr) Fail(key, "expected a table");
  return TomlReader(*t, source_, KeyPath(key), std::move(known_keys));
}

std::optional<TomlReader> TomlReader::OptionalTable(std::string_view key,
                                                    std::vector<std::string> known_keys) const {
  if (!Has(key)) return std::nullopt;
  return Table(key, std::move(known_keys));
}

std::vector<TomlReader> TomlReader::TableArray(std::string_view key,
                                               std::vector<std::string> known_keys) const {
  std::vector<TomlReader> out;
  const toml::node* n = Get(key);
  if (n == nullptr) return out;
  const toml::array* a = n->as_array();
  if (a == nullptr) Fail(key, "expected an array of tables ([[" + KeyPath(key) + "]])");
  for (size_t i = 0; i < a->size(); ++i) {
    const toml::table* t = (*a)[i].as_table();
    if (t == nullptr) Fail(key, fmt::format("element {} is not a table", i));
    out.emplace_back(*t, source_, fmt::format("{}[{}]", KeyPath(key), i), known_keys);
  }
  return out;
}

void TomlReader::Finish() const {
  for (const auto& [k, v] : *table_) {
    if (read_.count(k.str()) == 0) FailUnknown(k.str());
  }
}

}  // namespace dt
