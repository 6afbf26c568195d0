// Compiles plant source text from a test: writes it to a temporary file first.
// ctest runs test cases as parallel processes, so each process gets its own folder.
#pragma once

#include "paths.h"
#include "compiler.h"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

namespace plant::test {

// This process's scratch folder, removed when the process exits.
inline const std::filesystem::path& scratch_dir() {
    struct Scratch {
        std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("plant_unit_tests_" + std::to_string(::getpid()));
        Scratch() { std::filesystem::create_directories(dir); }
        ~Scratch() {
            std::error_code ec;
            std::filesystem::remove_all(dir, ec);
        }
    };
    static const Scratch scratch;
    return scratch.dir;
}

inline std::string temp_plant(const std::string& name, const std::string& text) {
    auto path = scratch_dir() / name;
    std::filesystem::create_directories(path.parent_path());
    std::ofstream(path) << text;
    return path.string();
}

// `overrides` are `--set NAME=VALUE` values for the plant's parameters.
// Compiles a plant file of this checkout (path relative to its root) with its stdlib.
inline void compile_repo_file(const std::string& path, Compilation& c) {
    CompileOptions opts;
    opts.stdlib_dir = PLANT_STDLIB_DIR;
    compile_file(std::string(PLANT_SOURCE_DIR) + "/" + path, opts, c);
}

inline void compile_text(const std::string& text, Compilation& c, const std::string& name = "t.plant",
                         const std::vector<std::string>& overrides = {}) {
    CompileOptions opts;
    opts.stdlib_dir = PLANT_STDLIB_DIR;
    opts.overrides = overrides;
    compile_file(temp_plant(name, text), opts, c);
}

// Plant source text compiled (as compile_text), required to compile: its diagnostics are
// shown when it does not.
inline graph::Graph compiled_text(const std::string& text, const std::string& name) {
    Compilation c;
    compile_text(text, c, name);
    INFO(render_all_text(c.sink.all(), c.sources));
    REQUIRE(c.ok());
    return std::move(c.graph);
}

// A file's whole content ("" when it cannot be read).
inline std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline bool has_code(const Compilation& c, std::string_view code) {
    for (const auto& d : c.sink.all())
        if (info(d.id).code == code) return true;
    return false;
}

}  // namespace plant::test
