// farfield techniques [--markdown]: the techniques of this build and their settings, from
// their descriptors (the docs' settings tables are this command's --markdown output).
#include <cstdio>

#include "commands.hpp"
#include "farfield/techniques/technique_descriptor.hpp"

namespace farfield::cli {

void add_techniques_command(CLI::App& root, std::vector<Command>& commands) {
  auto markdown = std::make_shared<bool>(false);
  CLI::App* cmd = root.add_subcommand(
      "techniques",
      "List the techniques and their settings (--set TECHNIQUE.KEY=VALUE on bake, "
      "bench and view): type, range, unit, default, the paper's symbol");
  cmd->add_flag("--markdown", *markdown,
                "One settings table per technique, as in docs/techniques/");
  commands.push_back({cmd, [markdown] {
                        if (!*markdown) {
                          std::fputs(techniques_help().c_str(), stdout);
                          return 0;
                        }
                        for (const TechniqueDescriptor* d : technique_descriptors())
                          std::printf("### %.*s\n\n%s\n", int(d->name.size()), d->name.data(),
                                      settings_table_markdown(*d).c_str());
                        return 0;
                      }});
}

}  // namespace farfield::cli
