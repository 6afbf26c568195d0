#include "sema/modules.h"

#include "parse/parser.h"

#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <sstream>

namespace plant::sema {
namespace fs = std::filesystem;

namespace {

bool read_file(const fs::path& p, std::string& out) {
    std::ifstream in(p, std::ios::binary);
    if (!in) return false;
    std::ostringstream ss;
    ss << in.rdbuf();
    out = ss.str();
    return true;
}

class Loader {
public:
    Loader(std::string stdlib, SourceMap& sm, Sink& sink, const Overlay* overlay)
        : stdlib_(std::move(stdlib)), sm_(sm), sink_(sink), overlay_(overlay) {}

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
        std::string text;
        const auto buffer = overlay_ ? overlay_->find(key) : Overlay::const_iterator{};
        if (overlay_ && buffer != overlay_->end()) text = buffer->second;
        else if (!read_file(disk, text) || fs::is_directory(disk, ec)) {
            if (import_span.valid() && fs::exists(disk, ec))  // there, but a folder or unreadable
                sink_.report(DiagId::FileUnreadable, import_span,
                             fmt::format("cannot read module file '{}'{}", display,
                                         fs::is_directory(disk, ec) ? ": it is a directory" : ""));
            else if (import_span.valid())
                sink_.report(DiagId::ImportNotFound, import_span,
                             fmt::format("cannot find module file '{}'", display));
            else
                sink_.report(DiagId::FileUnreadable, {}, fmt::format("cannot read '{}'", display));
            return -1;
        }
        int32_t file = sm_.add(display, std::move(text));
        LoadedModule mod;
        mod.key = key;
        mod.ast = parse::parse_module(sm_, file, sink_);
        stack_.push_back({key, display, import_span});
        for (const auto& imp : mod.ast.imports) {
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
    Program program_;
    std::map<std::string, int> done_;
    std::vector<Open> stack_;
};

}  // namespace

Program load_program(const std::string& root_path, const std::string& stdlib_dir, SourceMap& sources,
                     Sink& sink, const Overlay* overlay) {
    Loader loader(stdlib_dir, sources, sink, overlay);
    fs::path p(root_path);
    int root = loader.load(p, p.lexically_normal().generic_string(), {});
    Program prog = loader.take();
    prog.root = root;
    return prog;
}

}  // namespace plant::sema
