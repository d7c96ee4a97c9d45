// The one YAML reading of the project: scene files, sweep grids and the
// node's template all go through it (yaml-cpp underneath; the header does not
// expose it).
//
// A file means what rosparam makes of it. rosparam reads YAML 1.1 with
// PyYAML's SafeLoader and hands the node typed values, which the node turns
// into text for the key tables (%.17g for a float, decimal for an int,
// "true"/"false" for a bool, a string as it is). A plain scalar here is
// resolved by PyYAML's rules and given that same text, so a scene reads alike
// through `rosparam load` into the node and through the runner:
//   `1.0e+3`, `1_000.0` -> float (the shortest text of that double);  `0x10`, `010` (octal), `1_000` -> int;
//   `yes`, `On`, `FALSE` -> bool;  `1e-6` (no dot: a string to YAML 1.1)
//   -> the text, which the key table parses as a number, as the node does;
//   a quoted scalar -> the string, whatever it looks like.
// Rejected with the file, line and column: an empty or null value, a value
// rosparam cannot pass (an int beyond 32 bits, a mapping where a scalar is
// expected), rosparam's deg()/rad() expressions (not evaluated here), and
// a key given twice (rosparam silently keeps the last).
// Not as rosparam: yaml-cpp gives `! 5` (the non-specific tag) the same tag as
// a quoted '5', so it is read as the string "5" (PyYAML: the int 5); merge
// keys (`<<: *base`) are not expanded by yaml-cpp 0.7 and are rejected.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace rotor_rub::core {

// A YAML file that cannot be read as flat key: value documents.
class YamlError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

struct YamlEntry {
  std::string key;
  std::vector<std::string> values;  // one text per scalar, in rosparam's form
  bool is_list = false;             // written as a YAML sequence (even of one)
  std::string where;                // "file:line:column" of the value
};
using YamlDocument = std::vector<YamlEntry>;  // in file order

// Every document of the file ("---" separated), each a mapping of keys to a
// scalar or a sequence of scalars. An empty file is one empty document.
// Throws YamlError naming the file, line and column.
std::vector<YamlDocument> read_yaml_documents(const std::string& path);

// One scalar's text as rosparam would hand it to the node (see above).
// `quoted` for a quoted or !!str-tagged scalar. Throws YamlError (with
// `where`) for a null, an out-of-range int or a deg()/rad() expression.
std::string rosparam_scalar_text(const std::string& scalar, bool quoted, const std::string& where);

}  // namespace rotor_rub::core
