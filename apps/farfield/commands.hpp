// The farfield subcommands. Each add_* registers its options on the root app and returns the
// action to run when that subcommand was given. Actions return the exit status:
// 0 success, 1 failure (bad input, I/O), 2 usage.
#pragma once

#include <functional>
#include <vector>

#include <CLI/CLI.hpp>

namespace farfield::cli {

struct Command {
  CLI::App* app;
  std::function<int()> run;
};

void add_generate_commands(CLI::App& root, std::vector<Command>& commands);
void add_import_command(CLI::App& root, std::vector<Command>& commands);
void add_info_command(CLI::App& root, std::vector<Command>& commands);
void add_path_command(CLI::App& root, std::vector<Command>& commands);
void add_bench_command(CLI::App& root, std::vector<Command>& commands);
void add_bake_command(CLI::App& root, std::vector<Command>& commands);
void add_view_command(CLI::App& root, std::vector<Command>& commands);
void add_analyze_command(CLI::App& root, std::vector<Command>& commands);
void add_techniques_command(CLI::App& root, std::vector<Command>& commands);

// Prints "farfield: <message>" on stderr and returns 1.
int fail(const std::string& message);

}  // namespace farfield::cli
