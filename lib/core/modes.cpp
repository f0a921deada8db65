#include "core/modes.h"

#include <iostream>

#include "core/app.h"
#include "core/version.h"

namespace inlight::app {

int list_modes(const std::string& tool, const std::string& description,
               const std::vector<ModeHelp>& modes, const std::string& exit_codes, int argc,
               char** argv) {
    CLI::App app{description, tool};
    std::string examples;
    for (const ModeHelp& m : modes) {
        app.add_subcommand(m.name, m.purpose);
        examples += "\n  " + m.example;
    }
    app.require_subcommand(1);
    app.add_flag_callback(
        "--version",
        [&tool] {
            std::cout << version_line(tool) << "\n";
            throw CLI::Success();
        },
        "Print the version and exit");
    app.footer("Run `" + tool + " <mode> --help` for a mode's options.\nExamples:" + examples +
               "\nExit codes: " + exit_codes);
    if (auto code = parse(app, argc, argv)) return *code;
    return kExitUsage;
}

}  // namespace inlight::app
