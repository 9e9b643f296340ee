// farfield: the command-line tool. Parses arguments, calls the library, maps the outcome to
// an exit status (DESIGN.md, "Command line").
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "commands.hpp"
#include "farfield/core/mpi_world.hpp"

namespace farfield::cli {

int fail(const std::string& message) {
  std::fprintf(stderr, "farfield: %s\n", message.c_str());
  return 1;
}

int usage_error(const std::string& message) {
  std::fprintf(stderr, "farfield: %s\n", message.c_str());
  return 2;
}

CLI::Validator number_range(double lo, double hi) {
  const std::string limits = "[" + number_text(lo) + ", " + number_text(hi) + "]";
  return CLI::Validator(
      [lo, hi, limits](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !(v >= lo && v <= hi))
          return "'" + text + "' is not a number in " + limits;
        return {};
      },
      "in " + limits);
}

namespace {

// The first word that is not an option: the subcommand, if the user named one.
std::string first_word(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (argv[i][0] != '-') return argv[i];
  return "";
}

const CLI::App* named_command(const CLI::App& app, const std::string& word) {
  for (const CLI::App* sub : app.get_subcommands({}))
    if (sub->check_name(word)) return sub;
  return nullptr;
}

std::string command_names(const CLI::App& app) {
  std::string names;
  for (const CLI::App* sub : app.get_subcommands({}))
    names += (names.empty() ? "" : ", ") + sub->get_name();
  return names;
}

}  // namespace

}  // namespace farfield::cli

int main(int argc, char** argv) {
  using namespace farfield::cli;
  // Under mpirun, the MPI job (bakes spread over ranks); nothing of MPI otherwise.
  if (auto ok = farfield::MpiWorld::start(&argc, &argv); !ok) return fail(ok.error().message);
  struct LeaveMpi {
    ~LeaveMpi() { farfield::MpiWorld::stop(); }
  } leave_mpi;
  CLI::App app{
      "farfield: interactive walkthroughs of very large 3D environments.\n"
      "Import or generate a scene, inspect it; see README.md for the full workflow."};
  app.name("farfield");
  app.require_subcommand(1);
  app.set_version_flag("--version", "farfield 0.1.0");
  std::vector<Command> commands;
  add_generate_commands(app, commands);
  add_import_command(app, commands);
  add_export_command(app, commands);
  add_info_command(app, commands);
  add_path_command(app, commands);
  add_bake_command(app, commands);
  add_bench_command(app, commands);
  add_view_command(app, commands);
  add_analyze_command(app, commands);
  add_techniques_command(app, commands);

  // CLI11 would say only "A subcommand is required".
  const std::string word = first_word(argc, argv);
  const CLI::App* command = named_command(app, word);
  if (!word.empty() && !command)
    return usage_error("unknown command '" + word + "' (commands: " + command_names(app) +
                       "; farfield --help)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    const std::string help =
        command ? "farfield " + command->get_name() + " --help" : "farfield --help";
    return usage_error(std::string(e.what()) + " (" + help + ")");
  }
  try {
    for (const Command& command : commands) {
      if (command.app->parsed()) return command.run();
    }
  } catch (const std::bad_alloc&) {
    return fail("out of memory");
  } catch (const std::exception& e) {
    return fail(e.what());
  }
  return 2;
}
