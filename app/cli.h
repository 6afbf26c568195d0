// The one argument parser of every command (CLI11, a Debian package): a command declares its
// flags here with their help, and gets `--help` generated from them, `--flag VALUE` and
// `--flag=VALUE`, and errors in the project's form ("plant run: error: --for needs a value",
// exit code 2) instead of CLI11's own.
#pragma once

#include <CLI/CLI.hpp>

#include <iosfwd>
#include <map>
#include <string>
#include <vector>

namespace plant::app {

class Cli {
public:
    // `command`: "run" (its help's and errors' name: "plant run"); `usage`: the line after
    // "usage: plant run "; `about`: the paragraph after it; `footer`: lines after the flags.
    Cli(std::string command, std::string usage, std::string about, std::string footer = {});

    // A flag that takes a value; `needs` is what its error says when the value is missing
    // ("--set needs NAME=VALUE"), `shown` the value's name in the help ("--for 10s").
    CLI::Option* value(const std::string& names, std::string& v, const std::string& help, const std::string& shown,
                       const std::string& needs = "a value");
    // The same, repeatable: every occurrence in order.
    CLI::Option* values(const std::string& names, std::vector<std::string>& v, const std::string& help,
                        const std::string& shown, const std::string& needs = "a value");
    CLI::Option* flag(const std::string& names, bool& v, const std::string& help);
    // A flag that may take a value after '=' only (`--modbus`, `--modbus=csv`): `v` is
    // `plain` without one.
    CLI::Option* flag_value(const std::string& names, std::string& v, const std::string& plain, const std::string& help,
                            const std::string& shown);
    // The words after the flags (FILE...).
    void positionals(std::vector<std::string>& v);
    // How errors start: "plant run" (the default: "plant " + command), and whether a usage
    // error ends with "(see `plant --help`)"-style advice naming `help_of`.
    void errors_as(std::string prefix, std::string help_of);
    // What the help's usage line names: "plant run" (the default: "plant " + command); a
    // program of its own (a benchmark) names itself.
    void usage_as(std::string name) { name_ = std::move(name); }
    void unknown_word(std::string word) { unknown_ = std::move(word); }  // "option" or "flag"

    // Parses `args` (the words after the command's name). Returns -1 to go on; otherwise
    // the exit code, with --help printed on `out` (0) or the error on `err` (2).
    int parse(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
    // A usage error in this command's form; returns 2.
    int usage_error(std::ostream& err, const std::string& message) const;
    std::string help() const;

    CLI::App& app() { return app_; }
    const CLI::App& app() const { return app_; }

private:
    std::string command_, usage_, about_, footer_, prefix_, help_of_, name_, unknown_ = "option";
    std::map<std::string, std::string> needs_;  // a flag's name -> what it needs
    CLI::App app_;
};

// An integer from `text` (digits, after a '-' at most), whole and within [lo, hi]; false otherwise.
bool whole_number(const std::string& text, long lo, long hi, long& v);

}  // namespace plant::app
