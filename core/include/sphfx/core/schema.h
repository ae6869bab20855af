#pragma once
/// @file schema.h
/// @brief Declarative JSON schemas bound to C++ structs.
///
/// Every parameter is declared once: its JSON name, the struct member it fills, its default, unit, valid
/// range and a one-line description. The same declaration validates input (with JSON paths in errors and
/// "did you mean" for unknown keys), writes the resolved JSON back, and generates the reference docs.

#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sphfx::schema {

using Json = nlohmann::ordered_json;
using Vec3d = std::array<double, 3>;

/// A validation failure at a JSON path ("/fluid/blocks/0/min"). Callers add the file name.
class SchemaError : public std::runtime_error {
 public:
  SchemaError(std::string path, std::string message)
      : std::runtime_error(path + ": " + message), path_(std::move(path)), message_(std::move(message)) {}
  const std::string& path() const { return path_; }
  const std::string& message() const { return message_; }

 private:
  std::string path_;
  std::string message_;
};

/// One row of the generated reference.
struct FieldDoc {
  std::string path;  ///< dotted path, "fluid.blocks[].min"
  std::string type;
  std::string defaultValue;
  std::string unit;
  std::string range;
  std::string description;
};

/// Closed or open numeric interval; infinite ends mean unbounded.
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool minOpen = false;  ///< true: value must be > min
  bool maxOpen = false;  ///< true: value must be < max

  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
  static Range nonNegative() { return {0.0, std::numeric_limits<double>::infinity(), false, false}; }
  static Range closed(double lo, double hi) { return {lo, hi, false, false}; }
  static Range any() { return {}; }
  bool contains(double v) const;
  std::string text() const;
};

/// Short rendering of a JSON value for error messages ("got \"abc\"").
std::string describeValue(const Json& value);
/// Closest candidate within a small edit distance, or empty.
std::string closestName(const std::string& name, const std::vector<std::string>& candidates);
/// Appends a JSON-pointer segment (escaping '~' and '/').
std::string childPath(const std::string& path, const std::string& key);
std::string childPath(const std::string& path, size_t index);
std::string formatNumber(double v);

/// Schema of a JSON object filling a struct S. Build it once (e.g. in a function-local static) with the
/// field declarations below, then read()/write()/document().
template <class S>
class Object {
 public:
  using Check = std::function<void(const S& value, const Json& raw, const std::string& path)>;

  /// A floating point parameter.
  Object& number(std::string name, double S::*member, double def, std::string unit, Range range,
                 std::string description) {
    Field f = makeField(name, "number", formatNumber(def), unit, range.text(), description);
    f.setDefault = [=](S& s) { s.*member = def; };
    f.read = [=](const Json& j, const std::string& path, S& s) { s.*member = readNumber(j, path, range); };
    f.write = [=](const S& s, Json& out) { out[name] = s.*member; };
    fields_.push_back(std::move(f));
    return *this;
  }

  /// An integer parameter.
  Object& integer(std::string name, int S::*member, int def, std::string unit, Range range,
                  std::string description) {
    Field f = makeField(name, "integer", std::to_string(def), unit, range.text(), description);
    f.setDefault = [=](S& s) { s.*member = def; };
    f.read = [=](const Json& j, const std::string& path, S& s) { s.*member = readInteger(j, path, range); };
    f.write = [=](const S& s, Json& out) { out[name] = s.*member; };
    fields_.push_back(std::move(f));
    return *this;
  }

  /// A boolean parameter.
  Object& flag(std::string name, bool S::*member, bool def, std::string description) {
    Field f = makeField(name, "boolean", def ? "true" : "false", "", "", description);
    f.setDefault = [=](S& s) { s.*member = def; };
    f.read = [=](const Json& j, const std::string& path, S& s) {
      if (!j.is_boolean()) throw SchemaError(path, "expected true or false, got " + describeValue(j));
      s.*member = j.get<bool>();
    };
    f.write = [=](const S& s, Json& out) { out[name] = s.*member; };
    fields_.push_back(std::move(f));
    return *this;
  }

  /// A free-form string parameter.
  Object& text(std::string name, std::string S::*member, std::string def, std::string description) {
    Field f = makeField(name, "string", "\"" + def + "\"", "", "", description);
    f.setDefault = [=](S& s) { s.*member = def; };
    f.read = [=](const Json& j, const std::string& path, S& s) {
      if (!j.is_string()) throw SchemaError(path, "expected a string, got " + describeValue(j));
      s.*member = j.get<std::string>();
    };
    f.write = [=](const S& s, Json& out) { out[name] = s.*member; };
    fields_.push_back(std::move(f));
    return *this;
  }

  /// A string enum: JSON holds one of the names, the struct holds the matching value.
  template <class E>
  Object& choice(std::string name, E S::*member, E def, std::vector<std::pair<std::string, E>> values,
                 std::string description) {
    auto table = std::make_shared<std::vector<std::pair<std::string, E>>>(std::move(values));
    Field f =
        makeField(name, "enum", "\"" + nameOf(*table, def) + "\"", "", choicesText(*table), description);
    f.setDefault = [=](S& s) { s.*member = def; };
    f.read = [=](const Json& j, const std::string& path, S& s) { s.*member = readChoice(j, path, *table); };
    f.write = [=](const S& s, Json& out) { out[name] = nameOf(*table, s.*member); };
    fields_.push_back(std::move(f));
    return *this;
  }

  /// An array of distinct string-enum values (e.g. the cache's optional attributes).
  template <class E>
  Object& choiceList(std::string name, std::vector<E> S::*member, std::vector<E> def,
                     std::vector<std::pair<std::string, E>> values, std::string description) {
    auto table = std::make_shared<std::vector<std::pair<std::string, E>>>(std::move(values));
    Json defJson = Json::array();
    for (E e : def) defJson.push_back(nameOf(*table, e));
    Field f = makeField(name, "array of enum", defJson.dump(), "", choicesText(*table), description);
    f.setDefault = [=](S& s) { s.*member = def; };
    f.read = [=](const Json& j, const std::string& path, S& s) {
      if (!j.is_array()) throw SchemaError(path, "expected an array of strings, got " + describeValue(j));
      std::vector<E> out;
      for (size_t i = 0; i < j.size(); ++i) {
        E e = readChoice(j[i], childPath(path, i), *table);
        for (E seen : out)
          if (seen == e)
            throw SchemaError(childPath(path, i), "\"" + nameOf(*table, e) + "\" is listed twice");
        out.push_back(e);
      }
      s.*member = std::move(out);
    };
    f.write = [=](const S& s, Json& out) {
      Json arr = Json::array();
      for (E e : s.*member) arr.push_back(nameOf(*table, e));
      out[name] = std::move(arr);
    };
    fields_.push_back(std::move(f));
    return *this;
  }

  /// Any JSON value, kept as is (for values whose meaning another schema decides, e.g. a study's
  /// parameter values that are scene overrides).
  Object& anyJson(std::string name, Json S::*member, Json def, std::string description) {
    Field f = makeField(name, "any JSON", def.dump(), "", "", description);
    f.setDefault = [=](S& s) { s.*member = def; };
    f.read = [=](const Json& j, const std::string&, S& s) { s.*member = j; };
    f.write = [=](const S& s, Json& out) { out[name] = s.*member; };
    fields_.push_back(std::move(f));
    return *this;
  }

  /// An array of strings.
  Object& textList(std::string name, std::vector<std::string> S::*member, std::string description) {
    Field f = makeField(name, "array of strings", "[]", "", "", description);
    f.setDefault = [=](S& s) { (s.*member).clear(); };
    f.read = [=](const Json& j, const std::string& path, S& s) {
      if (!j.is_array()) throw SchemaError(path, "expected an array of strings, got " + describeValue(j));
      std::vector<std::string> out;
      for (size_t i = 0; i < j.size(); ++i) {
        if (!j[i].is_string())
          throw SchemaError(childPath(path, i), "expected a string, got " + describeValue(j[i]));
        out.push_back(j[i].get<std::string>());
      }
      s.*member = std::move(out);
    };
    f.write = [=](const S& s, Json& out) { out[name] = s.*member; };
    fields_.push_back(std::move(f));
    return *this;
  }

  /// A 3-vector of numbers, each component in `range`.
  Object& vec3(std::string name, Vec3d S::*member, Vec3d def, std::string unit, Range range,
               std::string description) {
    Field f = makeField(name, "array of 3 numbers", vecText(def), unit, range.text(), description);
    f.setDefault = [=](S& s) { s.*member = def; };
    f.read = [=](const Json& j, const std::string& path, S& s) {
      if (!j.is_array() || j.size() != 3)
        throw SchemaError(path, "expected an array of 3 numbers, got " + describeValue(j));
      Vec3d v;
      for (size_t i = 0; i < 3; ++i) {
        if (!j[i].is_number())
          throw SchemaError(path, "expected an array of 3 numbers, got " + describeValue(j));
        v[i] = j[i].get<double>();
        if (!std::isfinite(v[i]) || !range.contains(v[i]))
          throw SchemaError(childPath(path, i),
                            "expected a number in " + range.text() + ", got " + describeValue(j[i]));
      }
      s.*member = v;
    };
    f.write = [=](const S& s, Json& out) { out[name] = s.*member; };
    fields_.push_back(std::move(f));
    return *this;
  }

  /// A nested object; absent means all of its defaults.
  template <class C>
  Object& child(std::string name, C S::*member, std::shared_ptr<const Object<C>> schema,
                std::string description) {
    Field f = makeField(name, "object", "{}", "", "", description);
    f.setDefault = [=](S& s) { schema->setDefaults(s.*member); };
    f.read = [=](const Json& j, const std::string& path, S& s) { schema->read(j, path, s.*member); };
    f.write = [=](const S& s, Json& out) { out[name] = schema->write(s.*member); };
    f.document = [=](const std::string& prefix, std::vector<FieldDoc>& docs) {
      schema->document(prefix, docs);
    };
    fields_.push_back(std::move(f));
    return *this;
  }

  /// An optional nested object: absent (or null) means "not set".
  template <class C>
  Object& optionalChild(std::string name, std::optional<C> S::*member,
                        std::shared_ptr<const Object<C>> schema, std::string description) {
    Field f = makeField(name, "object (optional)", "absent", "", "", description);
    f.setDefault = [=](S& s) { (s.*member).reset(); };
    f.read = [=](const Json& j, const std::string& path, S& s) {
      if (j.is_null()) return (s.*member).reset();
      C value;
      schema->read(j, path, value);
      s.*member = std::move(value);
    };
    f.write = [=](const S& s, Json& out) {
      if (s.*member) out[name] = schema->write(*(s.*member));
    };
    f.document = [=](const std::string& prefix, std::vector<FieldDoc>& docs) {
      schema->document(prefix, docs);
    };
    fields_.push_back(std::move(f));
    return *this;
  }

  /// An array of objects with between minCount and maxCount entries.
  template <class C>
  Object& list(std::string name, std::vector<C> S::*member, std::shared_ptr<const Object<C>> schema,
               size_t minCount, size_t maxCount, std::string description) {
    // Built with += : GCC 12 warns falsely (-Wrestrict) on chains of string temporaries here.
    std::string range = "[";
    range += std::to_string(minCount);
    range += ", ";
    range += maxCount == std::numeric_limits<size_t>::max() ? std::string("inf") : std::to_string(maxCount);
    range += "] entries";
    Field f = makeField(name, "array of objects", "[]", "", range, description);
    f.setDefault = [=](S& s) { (s.*member).clear(); };
    f.read = [=](const Json& j, const std::string& path, S& s) {
      if (!j.is_array()) throw SchemaError(path, "expected an array of objects, got " + describeValue(j));
      if (j.size() < minCount || j.size() > maxCount)
        throw SchemaError(path, "expected " + range + ", got " + std::to_string(j.size()));
      std::vector<C> out(j.size());
      for (size_t i = 0; i < j.size(); ++i) schema->read(j[i], childPath(path, i), out[i]);
      s.*member = std::move(out);
    };
    f.write = [=](const S& s, Json& out) {
      Json arr = Json::array();
      for (const C& c : s.*member) arr.push_back(schema->write(c));
      out[name] = std::move(arr);
    };
    f.document = [=](const std::string& prefix, std::vector<FieldDoc>& docs) {
      schema->document(prefix + "[]", docs);
    };
    fields_.push_back(std::move(f));
    return *this;
  }

  /// Makes the field declared last apply only when `applies` holds (e.g. "radius" for spheres, a
  /// method's parameter group for that method): the resolved JSON leaves it out otherwise, and a value
  /// the input gives for it is an error, since nothing reads it. `note` ends its description in the
  /// docs, in parentheses ("box", "only when solver.method is \"dfsph\"").
  Object& onlyWhen(std::function<bool(const S&)> applies, std::string note) {
    fields_.back().applies = std::move(applies);
    fields_.back().doc.description += " (" + note + ")";
    fields_.back().note = std::move(note);
    return *this;
  }

  /// A cross-field check run after all fields are read. `raw` is the input object, so a check can tell
  /// a value the user gave from a default.
  Object& check(Check c) {
    checks_.push_back(std::move(c));
    return *this;
  }

  void setDefaults(S& s) const {
    for (const Field& f : fields_) f.setDefault(s);
  }

  /// Validates `j` and fills `out`. Throws SchemaError naming the JSON path of the first problem.
  void read(const Json& j, const std::string& path, S& out) const {
    if (!j.is_object())
      throw SchemaError(path.empty() ? "/" : path, "expected an object, got " + describeValue(j));
    std::vector<std::string> names;
    for (const Field& f : fields_) names.push_back(f.name);
    for (auto it = j.begin(); it != j.end(); ++it) {
      bool known = false;
      for (const auto& n : names) known = known || n == it.key();
      if (known) continue;
      std::string msg = "unknown key \"" + it.key() + "\"";
      const std::string near = closestName(it.key(), names);
      msg += near.empty() ? " (valid keys: " + joinNames(names) + ")" : " (did you mean \"" + near + "\"?)";
      throw SchemaError(childPath(path, it.key()), msg);
    }
    for (const Field& f : fields_) {
      auto it = j.find(f.name);
      if (it == j.end())
        f.setDefault(out);
      else
        f.read(*it, childPath(path, f.name), out);
    }
    for (const Check& c : checks_) c(out, j, path);
    for (const Field& f : fields_)
      if (f.applies && !f.applies(out) && j.contains(f.name))
        throw SchemaError(childPath(path, f.name),
                          "not read with these settings (" + f.note + "); remove it");
  }

  /// The resolved JSON: every field, defaults filled in.
  Json write(const S& s) const {
    Json out = Json::object();
    for (const Field& f : fields_)
      if (!f.applies || f.applies(s)) f.write(s, out);
    return out;
  }

  /// Reference rows for every field, nested ones included, under `prefix`.
  void document(const std::string& prefix, std::vector<FieldDoc>& docs) const {
    for (const Field& f : fields_) {
      FieldDoc d = f.doc;
      d.path = prefix.empty() ? f.name : prefix + "." + f.name;
      docs.push_back(d);
      if (f.document) f.document(d.path, docs);
    }
  }

 private:
  struct Field {
    std::string name;
    FieldDoc doc;
    std::function<void(S&)> setDefault;
    std::function<void(const Json&, const std::string&, S&)> read;
    std::function<void(const S&, Json&)> write;
    std::function<void(const std::string&, std::vector<FieldDoc>&)> document;
    std::function<bool(const S&)> applies;  ///< empty: always
    std::string note;                       ///< when it applies (onlyWhen)
  };

  static Field makeField(const std::string& name, std::string type, std::string def, std::string unit,
                         std::string range, std::string description) {
    Field f;
    f.name = name;
    f.doc = FieldDoc{
        name, std::move(type), std::move(def), std::move(unit), std::move(range), std::move(description)};
    return f;
  }

  static double readNumber(const Json& j, const std::string& path, const Range& range) {
    if (!j.is_number()) throw SchemaError(path, "expected a number, got " + describeValue(j));
    const double v = j.get<double>();
    if (!std::isfinite(v) || !range.contains(v))
      throw SchemaError(path, "expected a number in " + range.text() + ", got " + describeValue(j));
    return v;
  }

  static int readInteger(const Json& j, const std::string& path, const Range& range) {
    if (!j.is_number_integer()) throw SchemaError(path, "expected an integer, got " + describeValue(j));
    const auto v = j.get<int64_t>();
    if (!range.contains(double(v)) || v < std::numeric_limits<int>::min() ||
        v > std::numeric_limits<int>::max())
      throw SchemaError(path, "expected an integer in " + range.text() + ", got " + describeValue(j));
    return int(v);
  }

  template <class E>
  static E readChoice(const Json& j, const std::string& path,
                      const std::vector<std::pair<std::string, E>>& table) {
    if (!j.is_string())
      throw SchemaError(path, "expected one of " + choicesText(table) + ", got " + describeValue(j));
    const auto s = j.get<std::string>();
    std::vector<std::string> names;
    for (const auto& [n, e] : table) {
      if (n == s) return e;
      names.push_back(n);
    }
    std::string msg = "expected one of " + choicesText(table) + ", got " + describeValue(j);
    const std::string near = closestName(s, names);
    if (!near.empty()) msg += " (did you mean \"" + near + "\"?)";
    throw SchemaError(path, msg);
  }

  template <class E>
  static std::string nameOf(const std::vector<std::pair<std::string, E>>& table, E e) {
    for (const auto& [n, v] : table)
      if (v == e) return n;
    return "?";
  }

  template <class E>
  static std::string choicesText(const std::vector<std::pair<std::string, E>>& table) {
    std::string out;
    for (const auto& [n, v] : table) out += (out.empty() ? "" : ", ") + ("\"" + n + "\"");
    return out;
  }

  static std::string vecText(const Vec3d& v) {
    return "[" + formatNumber(v[0]) + ", " + formatNumber(v[1]) + ", " + formatNumber(v[2]) + "]";
  }

  static std::string joinNames(const std::vector<std::string>& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
  }

  std::vector<Field> fields_;
  std::vector<Check> checks_;
};

/// Reads a JSON file (comments allowed). `what` names the document in errors ("scene", "study").
/// @throws sphfx::InputError naming the file for an unreadable file or a syntax error (with line/column).
Json readJsonFile(const std::string& path, const std::string& what);

/// Thrown as sphfx::InputError "SOURCE: /json/path: message" (declared here to keep schema.h light).
[[noreturn]] void throwInputError(const std::string& source, const SchemaError& e);

/// Validates `raw` with `schema`. @throws sphfx::InputError "SOURCE: /json/path: what was expected".
template <class S>
S readDocument(const Object<S>& schema, const Json& raw, const std::string& source) {
  S value;
  try {
    schema.read(raw, "", value);
  } catch (const SchemaError& e) {
    throwInputError(source, e);
  }
  return value;
}

/// Convenience: a shared, immutable schema built by `build`.
template <class S, class Fn>
std::shared_ptr<const Object<S>> makeSchema(Fn&& build) {
  auto o = std::make_shared<Object<S>>();
  build(*o);
  return o;
}

}  // namespace sphfx::schema
