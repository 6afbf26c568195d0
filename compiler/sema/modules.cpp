#include "sema/modules.h"

#include "graph/utf8.h"
#include "parse/parser.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <sstream>

namespace plant::sema {
namespace fs = std::filesystem;

namespace {

// A module is at most this large: a link to /dev/zero or a stray binary is refused before
// it is read, not read until memory runs out.
constexpr std::uintmax_t kMaxModuleBytes = 16u << 20;



class Loader {
public:
    Loader(std::string stdlib, SourceMap& sm, Sink& sink, const Overlay* overlay, Reuse reuse)
        : stdlib_(std::move(stdlib)), sm_(sm), sink_(sink), overlay_(overlay), reuse_(reuse) {}

    // Returns the module index, or -1 when it could not be loaded (already reported).
    int load(const fs::path& disk, const std::string& display, Span import_span) {
        std::error_code ec;
        fs::path canon = fs::weakly_canonical(disk, ec);
        std::string key = (ec ? disk : canon).string();
        if (auto it = done_.find(key); it != done_.end()) return it->second;
        for (size_t i = 0; i < stack_.size(); ++i) {
            if (stack_[i].key != key) continue;
            auto& d = sink_.report(DiagId::ImportCycle, import_span,
                                   fmt::format("import cycle: '{}' imports itself", display));
            for (size_t j = i; j < stack_.size(); ++j)
                if (stack_[j].span.valid())  // the file being compiled is imported by nothing
                    d.notes.push_back({stack_[j].span, fmt::format("'{}' is imported here", stack_[j].display)});
            return -1;
        }
        std::string text, why;
        const auto buffer = overlay_ ? overlay_->find(key) : Overlay::const_iterator{};
        if (overlay_ && buffer != overlay_->end()) text = buffer->second;
        else if (!read_file(disk, text, why)) {
            if (import_span.valid() && fs::exists(disk, ec))  // there, but a folder or unreadable
                sink_.report(DiagId::FileUnreadable, import_span,
                             fmt::format("cannot read module file '{}'{}", display, why));
            else if (import_span.valid())
                sink_.report(DiagId::ImportNotFound, import_span,
                             fmt::format("cannot find module file '{}'", display));
            else
                sink_.report(DiagId::FileUnreadable, {}, fmt::format("cannot read '{}'{}", display, why));
            return -1;
        }
        // A byte-order mark is not text: columns count from after it.
        if (text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
        const size_t bad = graph::invalid_utf8(text);
        int32_t file = sm_.add(display, std::move(text));
        if (bad != std::string_view::npos) {
            report_invalid_utf8(sm_, file, bad, sink_);
            return -1;
        }
        LoadedModule mod;
        mod.key = key;
        if (const LoadedModule* same = reusable(key, file)) {
            mod.ast = same->ast;
            mod.clean = true;
        } else {
            const size_t before = sink_.all().size();
            mod.ast = std::make_shared<const ast::Module>(parse::parse_module(sm_, file, sink_));
            mod.clean = sink_.all().size() == before;
        }
        stack_.push_back({key, display, import_span});
        for (const auto& imp : mod.ast->imports) {
            auto [path, shown] = locate(imp.module, disk, display);
            int idx = load(path, shown, imp.span);
            if (idx >= 0) mod.imports.push_back(idx);
        }
        stack_.pop_back();
        program_.modules.push_back(std::move(mod));
        int idx = static_cast<int>(program_.modules.size()) - 1;
        done_[key] = idx;
        return idx;
    }

    Program take() { return std::move(program_); }

private:
    // The earlier load's module `key`, when it can stand for file `file` as read now.
    const LoadedModule* reusable(const std::string& key, int32_t file) const {
        if (!reuse_.program || !reuse_.sources) return nullptr;
        for (const LoadedModule& m : reuse_.program->modules) {
            if (m.key != key) continue;
            const int32_t was = m.ast->file;
            if (m.clean && was == file && was < reuse_.sources->size() && reuse_.sources->text(was) == sm_.text(file) &&
                reuse_.sources->name(was) == sm_.name(file))
                return &m;
            return nullptr;
        }
        return nullptr;
    }

    std::pair<fs::path, std::string> locate(const std::string& dotted, const fs::path& from,
                                            const std::string& from_display) {
        std::string rel = dotted;
        for (auto& c : rel)
            if (c == '.') c = '/';
        rel += ".plant";
        if (dotted.rfind("std.", 0) == 0) {
            std::string inner = rel.substr(4);
            return {fs::path(stdlib_) / inner, "std/" + inner};
        }
        fs::path shown = (fs::path(from_display).parent_path() / rel).lexically_normal();
        return {from.parent_path() / rel, shown.generic_string()};
    }

    struct Open {
        std::string key, display;
        Span span;
    };
    std::string stdlib_;
    SourceMap& sm_;
    Sink& sink_;
    const Overlay* overlay_;
    Reuse reuse_;
    Program program_;
    std::map<std::string, int> done_;
    std::vector<Open> stack_;
};

}  // namespace

bool read_file(const fs::path& p, std::string& out, std::string& why) {
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
        why = ": it is a directory";
        return false;
    }
    if (fs::exists(p, ec) && !fs::is_regular_file(p, ec)) {
        why = ": not a regular file";
        return false;
    }
    const std::uintmax_t size = fs::file_size(p, ec);
    if (!ec && size > kMaxModuleBytes) {
        why = fmt::format(": {} bytes, more than the limit of {} MiB", size, kMaxModuleBytes >> 20);
        return false;
    }
    std::ifstream in(p, std::ios::binary);
    if (!in) return false;
    std::ostringstream ss;
    ss << in.rdbuf();
    out = ss.str();
    return true;
}

void report_invalid_utf8(const SourceMap& sources, int32_t file, size_t bad, Sink& sink) {
    const auto byte = static_cast<unsigned char>(sources.text(file)[bad]);
    auto& d = sink.report(DiagId::InvalidText, Span{file, static_cast<uint32_t>(bad), static_cast<uint32_t>(bad + 1)},
                          fmt::format("this file is not valid UTF-8: byte 0x{:02X} here", byte));
    d.notes.push_back({{}, "plant files are UTF-8 text; save it as UTF-8 (a Latin-1 'ä' is one such byte)"});
}

static Program load_program_files(const std::string& root_path, const std::string& stdlib_dir, SourceMap& sources,
                                  Sink& sink, const Overlay* overlay, Reuse reuse) {
    Loader loader(stdlib_dir, sources, sink, overlay, reuse);
    fs::path p(root_path);
    int root = loader.load(p, p.lexically_normal().generic_string(), {});
    Program prog = loader.take();
    prog.root = root;
    return prog;
}

Program load_program(const std::string& root_path, const std::string& stdlib_dir, SourceMap& sources,
                     Sink& sink, const Overlay* overlay, Reuse reuse) {
    Program p = load_program_files(root_path, stdlib_dir, sources, sink, overlay, reuse);
    p.stdlib_dir = stdlib_dir;
    return p;
}

std::string stdlib_module_declaring(const std::string& stdlib_dir, const std::string& name) {
    std::error_code ec;
    if (stdlib_dir.empty() || !fs::is_directory(stdlib_dir, ec)) return {};
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(stdlib_dir, ec))
        if (e.path().extension() == ".plant" && e.is_regular_file(ec)) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    const std::string decl = "object " + name;
    for (const auto& f : files) {
        std::ifstream in(f);
        std::string line;
        while (std::getline(in, line)) {
            const size_t at = line.find_first_not_of(" \t");
            if (at == std::string::npos || line.compare(at, decl.size(), decl) != 0) continue;
            const size_t after = at + decl.size();
            if (after == line.size() || line[after] == ' ' || line[after] == '(' || line[after] == '{')
                return "std." + f.stem().string();
        }
    }
    return {};
}

}  // namespace plant::sema
