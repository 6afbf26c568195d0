// What formatting must not change: a file's compiled graph (its text form), its AST and
// its diagnostics' codes. Source positions are left out (the AST's `@line:col`, the
// graph's `src=file:line:col`): they say where the text was written, and formatting
// moves text; everything else must be the same byte for byte. Shared by the golden runner (the
// tests/golden/fmt cases) and tests/unit/fmt (every shipped plant file).
#pragma once

#include "ast/print.h"
#include "compiler.h"
#include "graph/text.h"

#include <sstream>
#include <string>

namespace plant::testing {

// The graph's text with every ` src=FILE:LINE:COL` written ` src=`.
inline std::string without_sources(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (size_t i = 0; i < text.size();) {
        if (text.compare(i, 5, " src=") == 0) {
            out += " src=";
            i += 5;
            while (i < text.size() && text[i] != ' ' && text[i] != '\n') ++i;
        } else {
            out += text[i++];
        }
    }
    return out;
}

// `overlay`: texts read instead of the files on disk (by canonical path).
inline std::string compiled_form(const std::string& path, const sema::Overlay* overlay) {
    CompileOptions opts;
    opts.stdlib_dir = default_stdlib_dir();
    opts.require_plant = false;
    opts.overlay = overlay;
    Compilation c;
    compile_file(path, opts, c);
    std::ostringstream out;
    for (const auto& d : c.sink.sorted()) out << "diagnostic " << info(d.id).code << "\n";
    for (const auto& m : c.program.modules) {
        std::ostringstream ast;
        ast::print(m.ast, c.sources, ast);
        std::istringstream lines(ast.str());
        for (std::string l; std::getline(lines, l);) out << l.substr(0, l.rfind("  @")) << "\n";
    }
    if (c.ok()) out << without_sources(graph::to_text(c.graph));
    return out.str();
}

// The text without its blanks: formatting may change only those.
inline std::string without_blanks(const std::string& s) {
    std::string out;
    for (char ch : s)
        if (ch != ' ' && ch != '\t' && ch != '\n' && ch != '\r') out += ch;
    return out;
}

}  // namespace plant::testing
