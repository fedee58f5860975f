#pragma once
/// Shared plumbing of the glassmap command: verb registration, output helpers.

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace glassmap::cli {

/// A verb adds its subcommand to the app. `order` sorts verbs in --help.
using Register = std::function<void(CLI::App& app)>;

/// Registers a verb at static initialisation; use one per cmd_<verb>.cpp:
///   static const cli::Registrar reg(20, [](CLI::App& app) { ... });
struct Registrar {
  Registrar(int order, Register fn);
};

/// Calls every registered verb's Register in order.
void registerAll(CLI::App& app);

/// True when stderr is a terminal (progress is shown only then).
bool stderrIsTerminal();

/// Peak resident memory of this process [bytes].
std::size_t peakMemoryBytes();

}  // namespace glassmap::cli
