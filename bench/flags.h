// The benchmarks' flags, on the parser every `plant` command uses (app/cli.h, CLI11): a
// generated `--help`, `--flag=VALUE` and `--flag VALUE`, and a bad value an error that names
// the flag ("plant_bench_bottling: error: --runs: 'x' is not a whole number from 1 to
// 1000", exit code 2), never a silent default. A flag not given keeps the value it had.
#pragma once

#include "app/cli.h"

#include <deque>
#include <functional>
#include <string>
#include <vector>

namespace plant::bench {

// The items of a comma-separated list ("10,50,200"; "" and "10," have an empty one).
std::vector<std::string> comma_items(const std::string& text);

class Flags {
public:
    // `program`: the binary's name (its help's and errors' name); `usage`: the help's usage
    // line after it; `about`: the paragraph after that.
    Flags(const std::string& program, const std::string& usage, const std::string& about);

    // A whole number from lo to hi.
    void whole(const std::string& name, int& v, long lo, long hi, const std::string& help);
    // Whole numbers from lo to hi, separated by commas ("10,50,200"), at least one.
    void wholes(const std::string& name, std::vector<int>& v, long lo, long hi, const std::string& help);
    // A number above 0 (positive) or not below 0 (not negative), finite.
    void positive(const std::string& name, double& v, const std::string& shown, const std::string& help);
    void not_negative(const std::string& name, double& v, const std::string& shown, const std::string& help);
    // Any text, not empty (a path, a folder).
    void text(const std::string& name, std::string& v, const std::string& shown, const std::string& help);
    // One of `choices`.
    void choice(const std::string& name, std::string& v, const std::vector<std::string>& choices,
                const std::string& help);
    // A flag without a value: sets v to `to`.
    void flag(const std::string& name, bool& v, bool to, const std::string& help);
    // A benchmark of what a client costs, in pairs (bench/pairs.h): --runs (pairs), --warmup
    // and --window (simulated seconds; the help gives the values they hold as defaults) and
    // --rows.
    void pairs(int& runs, double& warmup, double& window, bool& rows);
    // The words after the flags: without this, a word is an error.
    void words(std::vector<std::string>& v) { words_ = &v; }

    // Parses the command line. Returns -1 to go on; otherwise the exit code, with the help
    // printed on stdout (0) or the error on stderr (2).
    int parse(int argc, char** argv);
    // An error in the flags' form (after parse, for what only the program can check); returns 2.
    int error(const std::string& message) const;

private:
    // A flag's text, read once the line is parsed: an error message, or empty.
    using Check = std::function<std::string(const std::string&)>;
    struct Value {
        std::string text;
        Check check;
        CLI::Option* option = nullptr;
    };
    void add(const std::string& name, const std::string& shown, const std::string& help, Check check);
    // A finite number above 0, or (zero_too) not below 0.
    void number(const std::string& name, double& v, bool zero_too, const std::string& shown, const std::string& help);

    app::Cli cli_;
    std::deque<Value> values_;  // addresses kept: the parser writes into each text
    std::deque<bool> switches_;
    std::vector<std::string> extra_;
    std::vector<std::string>* words_ = nullptr;
};

}  // namespace plant::bench
