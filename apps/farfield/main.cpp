// farfield: the command-line tool. Parses arguments, calls the library, maps the outcome to
// an exit status (DESIGN.md, "Command line").
#include <cstdio>
#include <exception>

#include "commands.hpp"

namespace farfield::cli {

int fail(const std::string& message) {
  std::fprintf(stderr, "farfield: %s\n", message.c_str());
  return 1;
}

}  // namespace farfield::cli

int main(int argc, char** argv) {
  using namespace farfield::cli;
  CLI::App app{
      "farfield: interactive walkthroughs of very large 3D environments.\n"
      "Import or generate a scene, inspect it; see README.md for the full workflow."};
  app.name("farfield");
  app.require_subcommand(1);
  app.set_version_flag("--version", "farfield 0.1.0");
  std::vector<Command> commands;
  add_generate_commands(app, commands);
  add_import_command(app, commands);
  add_info_command(app, commands);
  add_path_command(app, commands);
  add_bake_command(app, commands);
  add_bench_command(app, commands);
  add_view_command(app, commands);
  add_analyze_command(app, commands);
  add_techniques_command(app, commands);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);  // prints the message
    std::fprintf(stderr, "Run 'farfield --help' (or 'farfield COMMAND --help') for usage.\n");
    return 2;
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
