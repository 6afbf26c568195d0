// Compiles plant source text from a test: writes it to a temporary file first.
#pragma once

#include "compiler.h"

#include <filesystem>
#include <fstream>
#include <string>

namespace plant::test {

inline std::string temp_plant(const std::string& name, const std::string& text) {
    auto dir = std::filesystem::temp_directory_path() / "plant_unit_tests";
    std::filesystem::create_directories(dir);
    auto path = dir / name;
    std::ofstream(path) << text;
    return path.string();
}

inline void compile_text(const std::string& text, Compilation& c, const std::string& name = "t.plant") {
    CompileOptions opts;
    opts.stdlib_dir = PLANT_STDLIB_DIR;
    compile_file(temp_plant(name, text), opts, c);
}

inline bool has_code(const Compilation& c, std::string_view code) {
    for (const auto& d : c.sink.all())
        if (info(d.id).code == code) return true;
    return false;
}

}  // namespace plant::test
