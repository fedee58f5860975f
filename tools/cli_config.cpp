#include "cli_config.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <iostream>
#include <memory>
#include <sstream>
#include <utility>

#include "glassmap/core/error.hpp"

namespace glassmap::cli {
namespace {

/// The verb path of `leaf` below the root app, e.g. {"eval", "cells"}.
std::vector<std::string> verbPath(const CLI::App& leaf) {
  std::vector<std::string> path;
  for (const CLI::App* a = &leaf; a->get_parent() != nullptr; a = a->get_parent())
    path.insert(path.begin(), a->get_name());
  return path;
}

std::string verbName(const CLI::App& leaf) {
  std::string name = "glassmap";
  for (const std::string& p : verbPath(leaf)) name += " " + p;
  return name;
}

bool isFlag(const CLI::Option& o) { return o.get_expected_min() == 0; }
bool isList(const CLI::Option& o) { return !isFlag(o) && o.get_items_expected_max() > 1; }

/// CLI11's type name without the validators' descriptions: INT, UINT, FLOAT, BOOLEAN, TEXT, ...
std::string typeFamily(const CLI::Option& o) {
  const std::string t = o.get_type_name();
  return t.substr(0, t.find(':'));
}

/// Options a config file may set (the help flags and -c/--write-config excluded).
bool settable(const CLI::App& leaf, const CLI::Option* o) {
  return o != nullptr && o != leaf.get_help_ptr() && o != leaf.get_help_all_ptr() && o->get_configurable();
}

/// The option `key` names, found the way CLI11 finds config keys: --key, -k, then positional.
const CLI::Option* findOption(const CLI::App& leaf, const std::string& key) {
  if (key.empty() || key.front() == '-') return nullptr;
  const CLI::Option* op = leaf.get_option_no_throw("--" + key);
  if (op == nullptr && key.size() == 1) op = leaf.get_option_no_throw("-" + key);
  if (op == nullptr) op = leaf.get_option_no_throw(key);
  return op;
}

std::string keyList(const CLI::App& leaf) {
  std::string keys;
  for (const CLI::Option* o : leaf.get_options()) {
    if (!settable(leaf, o)) continue;
    keys += (keys.empty() ? "" : ", ") + configKey(*o);
  }
  return keys;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool isBoolWord(const std::string& v) {
  static const char* const words[] = {"true", "false", "yes", "no", "on", "off", "1", "0"};
  const std::string l = lower(v);
  return std::any_of(std::begin(words), std::end(words), [&](const char* w) { return l == w; });
}

/// What a value of `o` must look like, for error messages.
std::string expectation(const CLI::Option& o) {
  if (isFlag(o)) return "true or false";
  const std::string family = typeFamily(o);
  if (family == "INT") return "an integer";
  if (family == "UINT") return "a non-negative integer";
  if (family == "FLOAT") return "a number";
  if (family == "BOOLEAN") return "true or false";
  return "a value";
}

/// Whether `v` converts to the type of `o` (flags: a boolean word); text always does.
bool valueFits(const CLI::Option& o, const std::string& v) {
  if (isFlag(o)) return isBoolWord(v);
  const std::string family = typeFamily(o);
  if (family == "INT") {
    std::int64_t x = 0;
    return CLI::detail::lexical_cast(v, x);
  }
  if (family == "UINT") {
    std::uint64_t x = 0;
    return !v.empty() && v.front() != '-' && CLI::detail::lexical_cast(v, x);
  }
  if (family == "FLOAT") {
    double x = 0;
    return CLI::detail::lexical_cast(v, x);
  }
  if (family == "BOOLEAN") return isBoolWord(v);
  return true;
}

/// 1-based line of a node, `fallback` when yaml-cpp has no mark for it (null values).
std::size_t lineOf(const YAML::Node& n, std::size_t fallback) {
  const YAML::Mark m = n.Mark();
  return m.is_null() || m.line < 0 ? fallback : static_cast<std::size_t>(m.line) + 1;
}

std::string yamlScalar(const std::string& s) {
  YAML::Emitter e;
  e << s;
  return e.c_str();
}

/// The value a given flag's key must hold to give its current result (true or false).
std::string flagValue(const CLI::Option& o, const std::string& key) {
  const std::string& result = o.results().back();
  for (const char* v : {"true", "false"}) {
    try {
      if (o.get_flag_value(key, v) == result) return v;
    } catch (const CLI::Error&) {
      // flag overrides disabled: only the flag's own value is accepted
    }
  }
  return yamlScalar(result);
}

/// State shared by the options added to the verbs and the YAML reader installed on the root app.
struct ConfigState {
  CLI::App* root = nullptr;
  std::vector<std::string> files;   ///< -c files in command-line order
  std::size_t loaded = 0;           ///< files read so far (CLI11 reads the last one first)
  const CLI::App* write = nullptr;  ///< the verb given --write-config
  OptionDefaults defaults;
};

/// CLI11 config formatter: the YAML of the verb being parsed.
class YamlVerbConfig : public CLI::Config {
 public:
  explicit YamlVerbConfig(std::shared_ptr<ConfigState> state) : state_(std::move(state)) {}

  std::string to_config(const CLI::App* app, bool, bool, std::string) const override {
    return writeVerbConfig(*app, state_->defaults);
  }

  std::vector<CLI::ConfigItem> from_config(std::istream& in) const override {
    std::string file = "config file";
    if (state_->loaded < state_->files.size()) file = state_->files[state_->files.size() - 1 - state_->loaded++];
    const CLI::App* leaf = state_->root;
    while (!leaf->get_subcommands().empty()) leaf = leaf->get_subcommands().front();
    // As a FileError, CLI11 reports it after --help has had its say.
    if (leaf == state_->root) throw CLI::FileError(file + ": a config file belongs to a verb: glassmap VERB -c FILE");
    try {
      return readVerbConfig(in, *leaf, file);
    } catch (const Error& e) {
      throw CLI::FileError(e.what());
    }
  }

 private:
  std::shared_ptr<ConfigState> state_;
};

void collectVerbs(CLI::App& app, std::vector<CLI::App*>& verbs) {
  for (CLI::App* sub : app.get_subcommands({})) {
    if (sub->get_name().empty()) continue;  // option groups
    const auto named = sub->get_subcommands([](CLI::App* a) { return !a->get_name().empty(); });
    if (named.empty())
      verbs.push_back(sub);
    else
      collectVerbs(*sub, verbs);
  }
}

}  // namespace

std::string configKey(const CLI::Option& option) { return option.get_single_name(); }

std::vector<CLI::ConfigItem> readVerbConfig(std::istream& in, const CLI::App& leaf, const std::string& file) {
  YAML::Node doc;
  try {
    doc = YAML::Load(in);
  } catch (const YAML::Exception& e) {  // syntax, undefined aliases, ...
    throw Error("YAML syntax: " + e.msg, file, e.mark.is_null() || e.mark.line < 0 ? 0 : e.mark.line + 1);
  }
  if (!doc || doc.IsNull()) return {};
  if (!doc.IsMap())
    throw Error("expected a mapping of option names to values ('key: value' lines)", file, lineOf(doc, 0));

  const std::vector<std::string> parents = verbPath(leaf);
  std::vector<CLI::ConfigItem> items;
  std::map<const CLI::Option*, std::pair<std::string, std::size_t>> seen;  // option -> key, line
  for (const auto& kv : doc) {
    const YAML::Node& k = kv.first;
    const YAML::Node& v = kv.second;
    const std::size_t key_line = lineOf(k, 0);
    if (!k.IsScalar()) throw Error("expected an option name as key", file, key_line);
    const std::string key = k.Scalar();
    const CLI::Option* op = findOption(leaf, key);
    if (op == nullptr || op == leaf.get_help_ptr() || op == leaf.get_help_all_ptr())
      throw Error("unknown key for '" + verbName(leaf) + "'; keys are its long option names: " + keyList(leaf), file,
                  key_line, key);
    if (!op->get_configurable()) throw Error("cannot be set in a config file", file, key_line, key);
    if (const auto it = seen.find(op); it != seen.end())
      throw Error("given twice (as '" + it->second.first + "' on line " + std::to_string(it->second.second) + ")", file,
                  key_line, key);
    seen[op] = {key, key_line};

    const std::size_t value_line = lineOf(v, key_line);
    CLI::ConfigItem item;
    item.parents = parents;
    item.name = key;
    if (!v || v.IsNull())
      throw Error("no value; expected " + expectation(*op) + (typeFamily(*op) == "TEXT" ? " (\"\" for none)" : ""),
                  file, key_line, key);
    if (v.IsMap()) throw Error("expected " + expectation(*op) + ", got a mapping", file, value_line, key);
    if (v.IsSequence()) {
      if (!isList(*op))
        throw Error("expected a single value (" + expectation(*op) + "), got a list", file, value_line, key);
      for (const YAML::Node& e : v) {
        if (!e.IsScalar()) throw Error("list elements must be single values", file, lineOf(e, value_line), key);
        if (!valueFits(*op, e.Scalar()))
          throw Error("expected " + expectation(*op) + ", got '" + e.Scalar() + "'", file, lineOf(e, value_line), key);
        item.inputs.push_back(e.Scalar());
      }
      if (item.inputs.empty()) continue;  // an empty list leaves the default
    } else {
      if (!valueFits(*op, v.Scalar()))
        throw Error("expected " + expectation(*op) + ", got '" + v.Scalar() + "'", file, value_line, key);
      item.inputs.push_back(v.Scalar());
    }
    items.push_back(std::move(item));
  }
  return items;
}

std::string writeVerbConfig(const CLI::App& leaf, const OptionDefaults& defaults) {
  const std::string name = verbName(leaf);
  std::ostringstream out;
  out << "# " << name << ": the effective configuration of a run; '" << name << " -c FILE.yaml' repeats it.\n"
      << "# Keys are the long option names (the command line overrides them); keys commented out were\n"
      << "# not given and show their defaults.\n";
  for (const CLI::Option* o : leaf.get_options()) {
    if (!settable(leaf, o)) continue;
    const std::string key = configKey(*o);
    out << "\n";
    std::istringstream help(o->get_description());
    for (std::string line; std::getline(help, line);) out << "# " << line << "\n";
    if (o->count() == 0) {
      std::string value;
      if (isFlag(*o)) {
        value = "false";
      } else if (const auto it = defaults.find(o); it != defaults.end() && !it->second.empty()) {
        value = yamlScalar(it->second);
      } else if (typeFamily(*o) == "TEXT") {
        value = "\"\"";
      }
      out << "# " << key << ":" << (value.empty() ? "" : " " + value) << "\n";
    } else if (isFlag(*o)) {
      out << key << ": " << flagValue(*o, key) << "\n";
    } else if (isList(*o)) {
      out << key << ":\n";
      for (const std::string& r : o->results()) out << "  - " << yamlScalar(r) << "\n";
    } else {
      out << key << ": " << yamlScalar(o->results().back()) << "\n";
    }
  }
  return out.str();
}

void addConfigOptions(CLI::App& app) {
  auto state = std::make_shared<ConfigState>();
  state->root = &app;
  app.config_formatter(std::make_shared<YamlVerbConfig>(state));
  // CLI11 reads config files only through the root app: the verbs' -c hands its file over here.
  app.set_config("--verb-config")->group("")->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);

  std::vector<CLI::App*> verbs;
  collectVerbs(app, verbs);
  for (CLI::App* verb : verbs) {
    for (CLI::Option* o : verb->get_options()) {
      const std::string shown = o->get_default_str();
      if (!shown.empty()) {
        state->defaults[o] = shown;
        continue;
      }
      o->capture_default_str();  // the bound variable's value now, before parsing
      state->defaults[o] = o->get_default_str();
      o->default_str(shown);  // keep --help as the verb wrote it
    }
    if (verb->get_option_no_throw("--config") == nullptr) {
      const std::string names = verb->get_option_no_throw("-c") == nullptr ? "-c,--config" : "--config";
      verb->add_option_function<std::string>(
              names,
              [state](const std::string& file) {
                state->files.push_back(file);
                state->root->get_config_ptr()->add_result(file);
              },
              "YAML file of option values: keys are the long option names (positional arguments by\n"
              "name), flags true/false, repeated options as lists; the command line overrides it")
          ->type_name("FILE.yaml")
          ->trigger_on_parse()
          ->configurable(false);
    }
    if (verb->get_option_no_throw("--write-config") == nullptr) {
      verb->add_flag_callback(
              "--write-config", [state, verb] { state->write = verb; },
              "print the effective configuration (every option, defaults commented out) as YAML for -c\n"
              "and exit without running")
          ->configurable(false);
    }
  }
  // Runs after the config file and the requirements, before the verb's own callback.
  app.parse_complete_callback([state] {
    if (state->write == nullptr) return;
    std::cout << writeVerbConfig(*state->write, state->defaults) << std::flush;
    throw CLI::Success();
  });
}

}  // namespace glassmap::cli
