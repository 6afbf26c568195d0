// The commands of `plant`, one row each (as ninja's tools): the word, one line for
// `plant --help`, and the function that runs it with the words after its name. Each
// command reads its own flags (app/cli.h) and answers its own `--help`. The table is
// made by CMake (app/CMakeLists.txt) from the commands this build has.
#pragma once

#include <string>
#include <vector>

namespace plant::app {

struct Command {
    const char* name;
    const char* summary;
    int (*run)(const std::vector<std::string>& args);
};

// Every command of this build, in the order `plant --help` lists them (commands.cpp.in).
const std::vector<const Command*>& commands();
// Registers the plugin kinds this build has (docs/architecture.md), before anything is
// compiled or loaded.
void register_kinds();

}  // namespace plant::app
