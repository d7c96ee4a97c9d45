#include "rotor_rub_sim/core/yaml_values.hpp"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <regex>

namespace rotor_rub::core {
namespace {

// PyYAML's YAML 1.1 implicit resolvers (yaml/resolver.py), which rosparam uses.
const std::regex& bool_re() {
  static const std::regex re("yes|Yes|YES|no|No|NO|true|True|TRUE|false|False|FALSE|on|On|ON|off|Off|OFF");
  return re;
}
const std::regex& float_re() {
  static const std::regex re(
      "[-+]?(?:[0-9][0-9_]*)\\.[0-9_]*(?:[eE][-+][0-9]+)?"
      "|\\.[0-9][0-9_]*(?:[eE][-+][0-9]+)?"
      "|[-+]?[0-9][0-9_]*(?::[0-5]?[0-9])+\\.[0-9_]*"
      "|[-+]?\\.(?:inf|Inf|INF)"
      "|\\.(?:nan|NaN|NAN)");
  return re;
}
const std::regex& int_re() {
  static const std::regex re(
      "[-+]?0b[0-1_]+"
      "|[-+]?0[0-7_]+"
      "|[-+]?(?:0|[1-9][0-9_]*)"
      "|[-+]?0x[0-9a-fA-F_]+"
      "|[-+]?[1-9][0-9_]*(?::[0-5]?[0-9])+");
  return re;
}
const std::regex& null_re() {
  static const std::regex re("~|null|Null|NULL|");
  return re;
}

std::string without_underscores(const std::string& s) {
  std::string out;
  for (char c : s)
    if (c != '_') out += c;
  return out;
}

// Splits a leading sign off (PyYAML's constructors do the same).
double take_sign(std::string& s) {
  if (!s.empty() && (s[0] == '-' || s[0] == '+')) {
    const double sign = s[0] == '-' ? -1.0 : 1.0;
    s.erase(0, 1);
    return sign;
  }
  return 1.0;
}

// "1:30:15" -> ((1 * 60) + 30) * 60 + 15 (YAML 1.1 sexagesimal).
double sexagesimal(const std::string& s) {
  double v = 0.0;
  std::size_t start = 0;
  for (;;) {
    const std::size_t colon = s.find(':', start);
    const std::string part = s.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
    v = v * 60.0 + std::strtod(part.c_str(), nullptr);
    if (colon == std::string::npos) return v;
    start = colon + 1;
  }
}

std::string float_text(std::string s) {
  s = without_underscores(s);
  const double sign = take_sign(s);
  double v = 0.0;
  if (s == ".inf" || s == ".Inf" || s == ".INF") {
    v = std::numeric_limits<double>::infinity();
  } else if (s == ".nan" || s == ".NaN" || s == ".NAN") {
    v = std::numeric_limits<double>::quiet_NaN();
  } else if (s.find(':') != std::string::npos) {
    v = sexagesimal(s);
  } else {
    v = std::strtod(s.c_str(), nullptr);  // correctly rounded, as Python's float()
  }
  // The shortest text that reads back as the same double (the node prints
  // %.17g; both parse to this double, and a sweep's CSV stays readable).
  char buf[40];
  const auto res = std::to_chars(buf, buf + sizeof buf, sign * v);
  return std::string(buf, res.ptr);
}

std::string int_text(std::string s, const std::string& original, const std::string& where) {
  s = without_underscores(s);
  const double sign = take_sign(s);
  double v = 0.0;  // exact for every value that can pass the 32-bit check
  if ((s == "0b" || s == "0x")) {
    // PyYAML fails on these (int('', base)): rosparam cannot load the file.
    throw YamlError(where + ": '" + original + "' is not a number YAML 1.1 can read; accepted: digits after " + s);
  }
  if (s.size() > 2 && s[0] == '0' && s[1] == 'b') {
    v = static_cast<double>(std::strtoull(s.c_str() + 2, nullptr, 2));
  } else if (s.size() > 2 && s[0] == '0' && s[1] == 'x') {
    v = static_cast<double>(std::strtoull(s.c_str() + 2, nullptr, 16));
  } else if (s.find(':') != std::string::npos) {
    v = sexagesimal(s);
  } else if (s.size() > 1 && s[0] == '0') {
    v = static_cast<double>(std::strtoull(s.c_str(), nullptr, 8));
  } else {
    errno = 0;
    v = static_cast<double>(std::strtoull(s.c_str(), nullptr, 10));
    if (errno == ERANGE) v = std::numeric_limits<double>::infinity();
  }
  v *= sign;
  // rosparam passes parameters over XML-RPC, whose int has 32 bits.
  if (v < std::numeric_limits<std::int32_t>::min() || v > std::numeric_limits<std::int32_t>::max()) {
    throw YamlError(where + ": integer " + original +
                    " is outside the 32-bit range rosparam can pass; accepted: [-2147483648, 2147483647] "
                    "(write it as a float, e.g. 1.0e+10)");
  }
  return std::to_string(static_cast<std::int64_t>(v));
}

std::string where_of(const std::string& path, const YAML::Mark& mark) {
  if (mark.is_null()) return path;
  return path + ":" + std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1);
}

std::string scalar_of(const YAML::Node& node, const std::string& key, const std::string& where) {
  if (node.IsNull()) {
    // A null (`key:`, `~`) has no text rosparam could pass to a key. A "key"
    // holding a colon is most likely `rtol:1.0e-4`, which YAML does not split.
    throw YamlError(where + ": key '" + key + "' has no value" +
                    (key.find(':') != std::string::npos ? " (a key needs a space after its colon: 'key: value')" : ""));
  }
  if (!node.IsScalar()) {
    throw YamlError(where + ": key '" + key + "' has a " + (node.IsMap() ? "mapping" : "nested list") +
                    " as its value; accepted: a scalar (keys are flat: key: value)");
  }
  const std::string& tag = node.Tag();
  bool quoted = false;
  if (tag == "!" || tag == "tag:yaml.org,2002:str") {
    quoted = true;
  } else if (tag == "tag:yaml.org,2002:float" || tag == "tag:yaml.org,2002:int" || tag == "tag:yaml.org,2002:bool") {
    // An explicit core tag: the plain text resolved as usual (PyYAML then
    // converts; the key table parses the same text alike).
  } else if (tag != "?" && !tag.empty()) {
    throw YamlError(where + ": key '" + key + "': tag '" + tag +
                    "' is not accepted; accepted: a plain or quoted scalar");
  }
  try {
    return rosparam_scalar_text(node.Scalar(), quoted, where);
  } catch (const YamlError& e) {
    throw YamlError(std::string(e.what()) + " (key '" + key + "')");
  }
}

}  // namespace

std::string rosparam_scalar_text(const std::string& scalar, bool quoted, const std::string& where) {
  if (quoted) return scalar;
  if (std::regex_match(scalar, bool_re())) {
    const char c = scalar[0];
    return (c == 'y' || c == 'Y' || c == 't' || c == 'T' || scalar == "on" || scalar == "On" || scalar == "ON")
               ? "true"
               : "false";
  }
  if (std::regex_match(scalar, float_re())) return float_text(scalar);
  if (std::regex_match(scalar, int_re())) return int_text(scalar, scalar, where);
  if (std::regex_match(scalar, null_re())) throw YamlError(where + ": a null value ('" + scalar + "') has no value");
  if (scalar.rfind("deg(", 0) == 0 || scalar.rfind("rad(", 0) == 0) {
    throw YamlError(where + ": '" + scalar +
                    "' is a rosparam angle expression, which this reader does not evaluate; accepted: a number");
  }
  return scalar;  // a string to YAML 1.1 (e.g. 1e-6): the key table parses it
}

std::vector<YamlDocument> read_yaml_documents(const std::string& path) {
  std::vector<YAML::Node> roots;
  try {
    roots = YAML::LoadAllFromFile(path);
  } catch (const YAML::BadFile&) {
    throw YamlError("file '" + path + "' cannot be opened");
  } catch (const YAML::ParserException& e) {
    throw YamlError(where_of(path, e.mark) + ": not valid YAML: " + e.msg);
  }
  std::vector<YamlDocument> docs;
  for (const YAML::Node& root : roots) {
    YamlDocument doc;
    if (root.IsNull()) {  // a document of comments only
      docs.push_back(doc);
      continue;
    }
    if (!root.IsMap()) {
      throw YamlError(where_of(path, root.Mark()) + ": expected a mapping of keys to values ('key: value', a space " +
                      "after the colon), got " +
                      (root.IsScalar() ? "the scalar '" + root.Scalar() + "'" : std::string("a list")));
    }
    for (const auto& kv : root) {
      if (!kv.first.IsScalar()) {
        throw YamlError(where_of(path, kv.first.Mark()) + ": a key must be a scalar");
      }
      YamlEntry e;
      e.key = kv.first.Scalar();
      if (e.key == "<<") {
        throw YamlError(where_of(path, kv.first.Mark()) +
                        ": a merge key (<<) is not supported by this reader; write the keys out");
      }
      e.where = where_of(path, kv.second.Mark().is_null() ? kv.first.Mark() : kv.second.Mark());
      for (const auto& seen : doc) {
        if (seen.key == e.key) throw YamlError(where_of(path, kv.first.Mark()) + ": key '" + e.key + "' given twice");
      }
      if (kv.second.IsSequence()) {
        e.is_list = true;
        for (const auto& item : kv.second) {
          e.values.push_back(scalar_of(item, e.key, where_of(path, item.Mark())));
        }
        if (e.values.empty()) throw YamlError(e.where + ": key '" + e.key + "' has an empty list");
      } else {
        e.values.push_back(scalar_of(kv.second, e.key, e.where));
      }
      doc.push_back(std::move(e));
    }
    docs.push_back(std::move(doc));
  }
  if (docs.empty()) docs.emplace_back();
  return docs;
}

}  // namespace rotor_rub::core
