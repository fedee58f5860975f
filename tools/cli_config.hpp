#pragma once
/// Config files for every verb: `glassmap <verb> -c FILE.yaml` reads a flat YAML mapping whose keys are
/// the verb's long option names (positional arguments by their names, flags true/false, vector
/// options as lists); options on the command line override it. `--write-config` prints the
/// effective configuration of the invocation as such a file and exits without running the verb.

#include <CLI/CLI.hpp>
#include <istream>
#include <map>
#include <string>
#include <vector>

namespace glassmap::cli {

/// Default values of options as text, for the commented-out keys --write-config prints.
using OptionDefaults = std::map<const CLI::Option*, std::string>;

/// The config file key of an option: its first long name, else its positional name, else its
/// first short name.
std::string configKey(const CLI::Option& option);

/// Reads a flat YAML mapping of option values for the verb `leaf` as CLI11 config items (with the
/// verb path as parents). Throws Error naming `file` and the line on YAML syntax errors, a
/// document that is not a mapping, unknown or repeated keys, options a file cannot set, and values
/// of the wrong type (lists for single values, non-numbers for numbers, non-booleans for flags).
std::vector<CLI::ConfigItem> readVerbConfig(std::istream& in, const CLI::App& leaf, const std::string& file);

/// The effective configuration of the parsed verb `leaf` as YAML: a header, then per option its
/// help as comments and `key: value`; options not given are written commented out with their
/// default from `defaults` (when known). Reading it back with -c repeats the invocation.
std::string writeVerbConfig(const CLI::App& leaf, const OptionDefaults& defaults = {});

/// Adds -c/--config FILE and --write-config to every verb of `app` (every subcommand without
/// subcommands of its own, nested ones included) and installs the YAML reader on `app`. Call after
/// all verbs are registered and before parsing.
void addConfigOptions(CLI::App& app);

}  // namespace glassmap::cli
