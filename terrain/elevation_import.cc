#include "terrain/elevation_import.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace dt {
namespace {

constexpr int kMinPosts = 2;
constexpr int kMaxPosts = kMaxPostsPerSide;  // HeightGrid's limit

void CheckSoil(Material soil) {
  if (!IsValidMaterial(static_cast<uint16_t>(soil)) || soil == Material::kFromGround) {
    throw std::invalid_argument(
        fmt::format("import soil {} is not a soil", static_cast<uint16_t>(soil)));
  }
}

Result<std::vector<uint8_t>> ReadWholeFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return Error{fmt::format("{}: cannot open: {}", path.string(), std::strerror(errno))};
  }
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                             std::istreambuf_iterator<char>());
  if (in.bad()) return Error{fmt::format("{}: read failed", path.string())};
  return bytes;
}

// ---- ESRI ASCII grid ------------------------------------------------------------------------

std::vector<std::string_view> SplitWhitespace(std::string_view line) {
  std::vector<std::string_view> tokens;
  size_t k = 0;
  while (k < line.size()) {
    while (k < line.size() && (line[k] == ' ' || line[k] == '\t')) ++k;
    const size_t start = k;
    while (k < line.size() && line[k] != ' ' && line[k] != '\t') ++k;
    if (k > start) tokens.push_back(line.substr(start, k - start));
  }
  return tokens;
}

std::optional<double> ParseDouble(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  double v = 0.0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  if (ec != std::errc() || end != token.data() + token.size()) return std::nullopt;
  if (!std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<long long> ParseInteger(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  long long v = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  if (ec != std::errc() || end != token.data() + token.size()) return std::nullopt;
  return v;
}

bool LooksNumeric(std::string_view token) {
  const char c = token.front();
  return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.';
}

std::string Lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return out;
}

// Lines split on '\n' with a trailing '\r' removed; line k (0-based) is line k + 1 of the file.
std::vector<std::string_view> SplitLines(std::string_view text) {
  std::vector<std::string_view> lines;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    start = end + 1;
  }
  return lines;
}

struct AscHeader {
  std::optional<long long> ncols, nrows;
  std::optional<double> xll, yll, cellsize, nodata;
};

}  // namespace

Result<HeightGrid> ParseAsc(std::string_view text, std::string_view source_name, Material soil) {
  CheckSoil(soil);
  const auto lines = SplitLines(text);
  auto fail = [&](size_t line_index, std::string_view what) -> Error {
    return Error{fmt::format("{}: line {}: {}", source_name, line_index + 1, what)};
  };

  AscHeader h;
  size_t k = 0;
  for (; k < lines.size(); ++k) {
    const auto tokens = SplitWhitespace(lines[k]);
    if (tokens.empty()) continue;
    if (LooksNumeric(tokens[0])) break;  // the first data row
    const std::string key = Lower(tokens[0]);
    if (tokens.size() != 2) {
      return fail(k, fmt::format("header line '{}' must be a key and one value", lines[k]));
    }
    const std::string_view value = tokens[1];
    auto set_int = [&](std::optional<long long>& field) -> Status {
      if (field) return fail(k, fmt::format("{} given twice", key));
      field = ParseInteger(value);
      if (!field) return fail(k, fmt::format("{} = '{}' is not an integer", key, value));
      return Status::Ok();
    };
    auto set_double = [&](std::optional<double>& field) -> Status {
      if (field) return fail(k, fmt::format("{} given twice", key));
      field = ParseDouble(value);
      if (!field) return fail(k, fmt::format("{} = '{}' is not a finite number", key, value));
      return Status::Ok();
    };
    Status s;
    if (key == "ncols") {
      s = set_int(h.ncols);
    } else if (key == "nrows") {
      s = set_int(h.nrows);
    } else if (key == "xllcorner" || key == "xllcenter") {
      s = set_double(h.xll);
    } else if (key == "yllcorner" || key == "yllcenter") {
      s = set_double(h.yll);
    } else if (key == "cellsize") {
      s = set_double(h.cellsize);
    } else if (key == "nodata_value") {
      s = set_double(h.nodata);
    } else {
      return fail(k, fmt::format("unknown header key '{}'", tokens[0]));
    }
    if (!s) return s.error();
  }
  const size_t first_data = k;
  for (auto [name, present] : {std::pair{"ncols", h.ncols.has_value()},
                               {"nrows", h.nrows.has_value()},
                               {"xllcorner (or xllcenter)", h.xll.has_value()},
                               {"yllcorner (or yllcenter)", h.yll.has_value()},
                               {"cellsize", h.cellsize.has_value()}}) {
    if (!present) return fail(first_data, fmt::format("header has no {}", name));
  }
  if (*h.ncols != *h.nrows) {
    return fail(first_data, fmt::format("ncols = {} and nrows = {} differ: the terrain grid is "
                                        "square, so the grid must be too",
                                        *h.ncols, *h.nrows));
  }
  if (*h.ncols < kMinPosts || *h.ncols > kMaxPosts) {
    return fail(first_data,
                fmt::format("ncols = {} is outside [{}, {}]", *h.ncols, kMinPosts, kMaxPosts));
  }
  if (!(*h.cellsize > 0.0)) {
    return fail(first_data, fmt::format("cellsize = {} must be > 0", *h.cellsize));
  }
  const int n = static_cast<int>(*h.ncols);
  const size_t count = static_cast<size_t>(n) * static_cast<size_t>(n);
  // Each value takes at least two characters (a digit and a separator) but the last: refuse
  // before allocating if the text cannot hold the declared grid.
  if (text.size() < 2 * count - 1) {
    return fail(first_data, fmt::format("header declares {} x {} cells but the file has only "
                                        "{} bytes",
                                        n, n, text.size()));
  }

  std::vector<float> posts(count);
  int row = 0;
  for (k = first_data; k < lines.size(); ++k) {
    const auto tokens = SplitWhitespace(lines[k]);
    if (tokens.empty()) continue;
    if (row == n) return fail(k, fmt::format("data after the last of {} rows", n));
    if (tokens.size() != static_cast<size_t>(n)) {
      return fail(
          k, fmt::format("row {} has {} values, expected ncols = {}", row + 1, tokens.size(), n));
    }
    const int j = n - 1 - row;  // the first row is the northernmost
    for (int i = 0; i < n; ++i) {
      const auto v = ParseDouble(tokens[i]);
      if (!v) {
        return fail(k, fmt::format("column {}: '{}' is not a finite number", i + 1, tokens[i]));
      }
      if (h.nodata && *v == *h.nodata) {
        return fail(k, fmt::format("column {}: NODATA value {} (cells without data are refused)",
                                   i + 1, tokens[i]));
      }
      if (std::fabs(*v) > std::numeric_limits<float>::max()) {
        return fail(k,
                    fmt::format("column {}: {} does not fit a float elevation", i + 1, tokens[i]));
      }
      posts[static_cast<size_t>(j) * n + i] = static_cast<float>(*v);
    }
    ++row;
  }
  if (row < n) {
    return fail(lines.empty() ? 0 : lines.size() - 1,
                fmt::format("file ends after {} of {} rows", row, n));
  }
  return HeightGrid(n, *h.cellsize, std::move(posts), soil);
}

Result<HeightGrid> ImportAsc(const std::filesystem::path& path, Material soil) {
  auto bytes = ReadWholeFile(path);
  if (!bytes) return bytes.error();
  const auto& b = bytes.value();
  return ParseAsc(std::string_view(reinterpret_cast<const char*>(b.data()), b.size()),
                  path.string(), soil);
}

// ---- Binary PGM (P5) ------------------------------------------------------------------------

namespace {

bool IsPgmSpace(uint8_t c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

// Reads one header number preceded by whitespace and comments; `pos` moves past its digits.
Result<long long> PgmHeaderNumber(std::span<const uint8_t> bytes, size_t& pos,
                                  std::string_view what, std::string_view source_name) {
  const size_t before = pos;
  while (pos < bytes.size()) {
    if (IsPgmSpace(bytes[pos])) {
      ++pos;
    } else if (bytes[pos] == '#') {
      while (pos < bytes.size() && bytes[pos] != '\n' && bytes[pos] != '\r') ++pos;
    } else {
      break;
    }
  }
  if (pos == before) {
    return Error{
        fmt::format("{}: byte {}: expected whitespace before the {}", source_name, pos, what)};
  }
  if (pos >= bytes.size()) {
    return Error{fmt::format("{}: byte {}: file ends before the {}", source_name, pos, what)};
  }
  if (bytes[pos] < '0' || bytes[pos] > '9') {
    return Error{fmt::format("{}: byte {}: expected the {} (a decimal number), found byte 0x{:02x}",
                             source_name, pos, what, bytes[pos])};
  }
  const size_t start = pos;
  long long v = 0;
  while (pos < bytes.size() && bytes[pos] >= '0' && bytes[pos] <= '9') {
    v = v * 10 + (bytes[pos] - '0');
    if (v > 1'000'000) {
      return Error{fmt::format("{}: byte {}: {} is too large", source_name, start, what)};
    }
    ++pos;
  }
  return v;
}

}  // namespace

Result<HeightGrid> ParsePgm(std::span<const uint8_t> bytes, std::string_view source_name,
                            const PgmImportOptions& options) {
  CheckSoil(options.soil);
  if (!std::isfinite(options.spacing_m) || options.spacing_m <= 0.0) {
    throw std::invalid_argument(
        fmt::format("PGM spacing_m = {} must be finite and > 0", options.spacing_m));
  }
  if (!std::isfinite(options.metres_per_level) || options.metres_per_level <= 0.0) {
    throw std::invalid_argument(
        fmt::format("PGM metres_per_level = {} must be finite and > 0", options.metres_per_level));
  }
  if (!std::isfinite(options.base_elevation_m)) {
    throw std::invalid_argument(
        fmt::format("PGM base_elevation_m = {} must be finite", options.base_elevation_m));
  }
  auto fail = [&](size_t offset, std::string_view what) -> Error {
    return Error{fmt::format("{}: byte {}: {}", source_name, offset, what)};
  };
  if (bytes.size() < 2 || bytes[0] != 'P' || bytes[1] != '5') {
    if (bytes.size() >= 2 && bytes[0] == 'P' && bytes[1] == '2') {
      return fail(0, "plain (ASCII) PGM 'P2' is not supported; convert to binary 'P5'");
    }
    return fail(0, "not a binary PGM: the file must start with 'P5'");
  }
  size_t pos = 2;
  const size_t width_at = pos;
  auto width = PgmHeaderNumber(bytes, pos, "width", source_name);
  if (!width) return width.error();
  const size_t height_at = pos;
  auto height = PgmHeaderNumber(bytes, pos, "height", source_name);
  if (!height) return height.error();
  const size_t maxval_at = pos;
  auto maxval = PgmHeaderNumber(bytes, pos, "maxval", source_name);
  if (!maxval) return maxval.error();
  if (width.value() != height.value()) {
    return fail(height_at, fmt::format("width {} and height {} differ: the terrain grid is "
                                       "square, so the image must be too",
                                       width.value(), height.value()));
  }
  if (width.value() < kMinPosts || width.value() > kMaxPosts) {
    return fail(width_at,
                fmt::format("width {} is outside [{}, {}]", width.value(), kMinPosts, kMaxPosts));
  }
  if (maxval.value() < 1 || maxval.value() > 65535) {
    return fail(maxval_at, fmt::format("maxval {} is outside [1, 65535]", maxval.value()));
  }
  // Exactly one whitespace byte separates maxval from the raster.
  if (pos >= bytes.size() || !IsPgmSpace(bytes[pos])) {
    return fail(pos, "expected one whitespace byte after maxval");
  }
  ++pos;
  const int n = static_cast<int>(width.value());
  const size_t bytes_per_sample = maxval.value() < 256 ? 1 : 2;
  const size_t count = static_cast<size_t>(n) * static_cast<size_t>(n);
  const size_t raster_bytes = count * bytes_per_sample;
  const size_t available = bytes.size() - pos;
  if (available < raster_bytes) {
    return fail(bytes.size(), fmt::format("file is truncated: the {} x {} raster needs {} bytes "
                                          "from byte {}, only {} present",
                                          n, n, raster_bytes, pos, available));
  }
  if (available > raster_bytes) {
    return fail(pos + raster_bytes,
                fmt::format("{} unexpected bytes after the raster", available - raster_bytes));
  }
  std::vector<float> posts(count);
  for (size_t k = 0; k < count; ++k) {
    const size_t at = pos + k * bytes_per_sample;
    const unsigned level =
        bytes_per_sample == 1 ? bytes[at] : (unsigned{bytes[at]} << 8) | bytes[at + 1];
    if (level > maxval.value()) {
      return fail(at, fmt::format("sample {} exceeds maxval {}", level, maxval.value()));
    }
    const double y_m = options.base_elevation_m + level * options.metres_per_level;
    if (!(std::fabs(y_m) <= std::numeric_limits<float>::max())) {
      return fail(at, fmt::format("sample {} gives elevation {} m, which does not fit a float",
                                  level, y_m));
    }
    const size_t row = k / n;  // the first row is the northernmost
    const size_t i = k % n;
    const size_t j = static_cast<size_t>(n) - 1 - row;
    posts[j * n + i] = static_cast<float>(y_m);
  }
  return HeightGrid(n, options.spacing_m, std::move(posts), options.soil);
}

Result<HeightGrid> ImportPgm(const std::filesystem::path& path, const PgmImportOptions& options) {
  auto bytes = ReadWholeFile(path);
  if (!bytes) return bytes.error();
  return ParsePgm(bytes.value(), path.string(), options);
}

}  // namespace dt
