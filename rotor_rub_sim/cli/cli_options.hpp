// The programs' command lines on CLI11 (the tools' and the node's):
// validators whose messages read like the scene keys' ("value 'abc' is not a
// number; accepted: [1, 10000000]"), and one way to end on --help (exit 0)
// and on a usage error (one line, exit 2).
#pragma once

#include <CLI/CLI.hpp>
#include <map>
#include <string>
#include <vector>

namespace rotor_rub::cli {

constexpr int kExitUsage = 2;

// A finite number in [lo, hi] ((lo, hi] when lo_open).
CLI::Validator number_in(double lo, double hi, bool lo_open = false);
// An integer in [lo, hi].
CLI::Validator integer_in(long lo, long hi);
// A shard "I/N" with 0 <= I < N (the sweep's and the bifurcation tool's --shard).
CLI::Validator shard_spec();
// An existing file (CLI::ExistingFile; FILE is the option's type name).
CLI::Validator existing_file();
// A value the scene key `key` accepts (its range or names, from the core's
// key table), with the key table's message when it does not.
CLI::Validator scene_key(const std::string& key);
// --set KEY=VALUE: a scene key and a value it accepts (the key table's
// message when not).
CLI::Validator key_value();
// The description of an option that sets scene key `key`: the key table's
// line (with the unit) and the key's name.
std::string scene_key_description(const std::string& key);

// The tools' --scene FILE (an existing file; required, which the tool
// checks after --help and its listings) and --set KEY=VALUE (repeatable,
// each pair checked against the key table) into path and sets, with these
// descriptions.
void add_scene_options(CLI::App& app, std::string& path, std::vector<std::string>& sets,
                       const std::string& scene_description = "the scene file (flat YAML of scene keys); required",
                       const std::string& set_description = "sets any scene key, repeatable");
// --set's KEY=VALUE pairs as load_scene's overrides (a key given twice: the
// last value).
std::map<std::string, std::string> scene_overrides(const std::vector<std::string>& sets);

// Parses the command line. On --help prints the help on stdout and exits 0;
// on a usage error prints "<tool>: <message> (see <tool> --help)" on
// stderr, one line, and exits 2. Unknown options and stray arguments are
// usage errors.
void parse_or_exit(CLI::App& app, int argc, const char* const* argv);

// For checks after parsing (one option requires another, say): the same
// one-line message and exit status 2.
[[noreturn]] void usage_error(const CLI::App& app, const std::string& message);

}  // namespace rotor_rub::cli
