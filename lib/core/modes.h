// core/modes.h: the top-level command line of a tool made of modes (subcommands such as
// `calibrate geometry`, `bundle pack`, `render trace`), when no mode is given.
#pragma once

#include <string>
#include <vector>

namespace inlight::app {

/// One mode of a tool, as its top-level --help lists it.
struct ModeHelp {
    std::string name;     ///< the subcommand word
    std::string purpose;  ///< one line (the mode's own --help description)
    std::string example;  ///< one command line
};

/// Parses a command line that named no mode: --help lists the modes and their examples, then
/// `exit_codes` ("0 ok, 1 ..."); --version prints the tool's version line. Returns the exit
/// code: 0 after --help or --version, kExitUsage otherwise (CLI11's message printed).
int list_modes(const std::string& tool, const std::string& description,
               const std::vector<ModeHelp>& modes, const std::string& exit_codes, int argc,
               char** argv);

}  // namespace inlight::app
