#include "sphfx/core/schema.h"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>

#include "sphfx/core/error.h"

namespace sphfx::schema {

bool Range::contains(double v) const {
  if (minOpen ? !(v > min) : !(v >= min)) return false;
  if (maxOpen ? !(v < max) : !(v <= max)) return false;
  return true;
}

std::string formatNumber(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return fmt::format("{}", v);
}

std::string Range::text() const {
  if (std::isinf(min) && std::isinf(max)) return "any";
  return fmt::format("{}{}, {}{}", minOpen ? "(" : "[", formatNumber(min), formatNumber(max),
                     (maxOpen || std::isinf(max)) ? ")" : "]");
}

std::string describeValue(const Json& value) {
  std::string s = value.dump();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  if (value.is_object()) return "an object " + s;
  if (value.is_array()) return "an array " + s;
  if (value.is_null()) return "null";
  return s;
}

namespace {
size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}
}  // namespace

std::string closestName(const std::string& name, const std::vector<std::string>& candidates) {
  std::string best;
  size_t bestDistance = std::max<size_t>(2, name.size() / 3) + 1;
  for (const auto& c : candidates) {
    const size_t d = editDistance(name, c);
    if (d < bestDistance) {
      bestDistance = d;
      best = c;
    }
  }
  return best;
}

std::string childPath(const std::string& path, const std::string& key) {
  std::string escaped;
  for (char c : key) {
    if (c == '~')
      escaped += "~0";
    else if (c == '/')
      escaped += "~1";
    else
      escaped += c;
  }
  return path + "/" + escaped;
}

std::string childPath(const std::string& path, size_t index) {
  return path + "/" + std::to_string(index);
}

Json readJsonFile(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the " + what + " file");
  try {
    return Json::parse(in, nullptr, true, /*ignore_comments=*/true);
  } catch (const Json::parse_error& e) {
    // nlohmann's text reads "[json.exception.parse_error.101] parse error at line 3, column 5: ...".
    const std::string text = e.what();
    const auto pos = text.find("parse error");
    throw InputError(path + ": invalid JSON: " + (pos == std::string::npos ? text : text.substr(pos)));
  }
}

void throwInputError(const std::string& source, const SchemaError& e) {
  throw InputError(source + ": " + e.path() + ": " + e.message());
}

}  // namespace sphfx::schema
