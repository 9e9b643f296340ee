// The farfield subcommands. Each add_* registers its options on the root app and returns the
// action to run when that subcommand was given. Actions return the exit status:
// 0 success, 1 failure (bad input, I/O), 2 usage.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "farfield/core/text.hpp"

namespace farfield::cli {

struct Command {
  CLI::App* app;
  std::function<int()> run;
};

void add_generate_commands(CLI::App& root, std::vector<Command>& commands);
void add_import_command(CLI::App& root, std::vector<Command>& commands);
void add_export_command(CLI::App& root, std::vector<Command>& commands);
void add_info_command(CLI::App& root, std::vector<Command>& commands);
void add_path_command(CLI::App& root, std::vector<Command>& commands);
void add_bench_command(CLI::App& root, std::vector<Command>& commands);
void add_bake_command(CLI::App& root, std::vector<Command>& commands);
void add_view_command(CLI::App& root, std::vector<Command>& commands);
void add_analyze_command(CLI::App& root, std::vector<Command>& commands);
void add_techniques_command(CLI::App& root, std::vector<Command>& commands);

// Print "farfield: <message>" on stderr and return the exit status: 1 for what failed on
// the input or the file system, 2 for a command line that is wrong in itself.
int fail(const std::string& message);
int usage_error(const std::string& message);

// A range check for a number option that states its limits as written ("in [1, 179]", not
// CLI11's "1.000000 to 179.000000").
CLI::Validator number_range(double lo, double hi);

}  // namespace farfield::cli
