// `plant`: the command table (app/command.h) and its dispatch. Each command reads its own
// flags and answers its own --help; the table lists the commands this build has
// (commands.cpp, made by CMake from app/commands.cpp.in).
#include "app/command.h"

#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

namespace {

// `plant --help`: one line per command of the table.
std::string usage() {
    std::string s = "plant - compile and run automation plants\n\nusage: plant <command> [options] FILE...\n\ncommands:\n";
    for (const plant::app::Command* c : plant::app::commands()) {
        std::string name = "  " + std::string(c->name);
        name.resize(10, ' ');
        s += name + c->summary + "\n";
    }
    s += "\n`plant COMMAND --help` says what a command does and lists its options.\n";
    return s;
}

int run_command(const std::vector<std::string>& args) {
    plant::app::register_kinds();  // the plugin kinds this program has (docs/architecture.md)
    if (args.empty()) {
        std::cerr << usage();
        return 2;
    }
    if (args[0] == "-h" || args[0] == "--help" || args[0] == "help") {
        std::cout << usage();
        return 0;
    }
    for (const plant::app::Command* c : plant::app::commands())
        if (args[0] == c->name) return c->run({args.begin() + 1, args.end()});
    std::cerr << "plant: error: unknown command '" << args[0] << "'\n(see `plant --help`)\n";
    return 2;
}

}  // namespace

// Whatever escapes a command (a library's exception: a bug of ours, or memory running out)
// is an internal error with its own exit code, never an abort.
int main(int argc, char** argv) {
    try {
        return run_command({argv + 1, argv + argc});
    } catch (const std::exception& e) {
        std::cerr << "plant: internal error: " << e.what() << "\n(please report it, with the input that caused it)\n";
    } catch (...) {
        std::cerr << "plant: internal error: an unknown exception\n";
    }
    return 3;
}
