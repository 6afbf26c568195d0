#include "lsp/lookup.h"

#include <algorithm>
#include <memory>
#include <variant>

namespace plant::lsp {
namespace {

void collect(const std::vector<ast::Member>& members, Members& out) {
    for (const auto& m : members) {
        if (auto* i = std::get_if<ast::InstanceDecl>(&m)) out.instances.push_back(i);
        else if (auto* p = std::get_if<ast::PortDecl>(&m)) out.ports.push_back(p);
        else if (auto* k = std::get_if<ast::ComponentDecl>(&m)) out.components.push_back(k);
        else if (auto* l = std::get_if<ast::LetDecl>(&m)) out.lets.push_back(l);
        else if (auto* f = std::get_if<std::unique_ptr<ast::ForDecl>>(&m)) collect((*f)->body, out);
        else if (auto* c = std::get_if<std::unique_ptr<ast::IfDecl>>(&m)) {
            collect((*c)->then_body, out);
            collect((*c)->else_body, out);
        }
    }
}

}  // namespace

const ast::ObjectDecl* find_type(const Compilation& c, const std::string& name) {
    for (const auto& m : c.program.modules)
        for (const auto& o : m.ast->objects)
            if (o.name.text == name) return &o;
    return nullptr;
}

Members members_of(const ast::ObjectDecl& o) {
    Members out;
    collect(o.members, out);
    return out;
}

std::string slice(const Compilation& c, const Span& s) {
    if (!s.valid()) return "";
    const std::string& t = c.sources.text(s.file);
    return t.substr(std::min<size_t>(s.begin, t.size()), std::min<size_t>(s.end, t.size()) - std::min<size_t>(s.begin, t.size()));
}

std::string doc_comment(const Compilation& c, const Span& s) {
    const std::string& t = c.sources.text(s.file);
    size_t line_begin = t.rfind('\n', s.begin == 0 ? 0 : s.begin - 1);
    std::vector<std::string> lines;
    while (line_begin != std::string::npos && line_begin > 0) {
        size_t prev = t.rfind('\n', line_begin - 1);
        size_t from = prev == std::string::npos ? 0 : prev + 1;
        std::string line = t.substr(from, line_begin - from);
        size_t first = line.find_first_not_of(" \t\r");
        // Blank lines between the block and the declaration are allowed (`plant fmt` removes them).
        if (first == std::string::npos && lines.empty()) {
            if (prev == std::string::npos) break;
            line_begin = prev;
            continue;
        }
        if (first == std::string::npos || line.compare(first, 3, "///") != 0) break;
        std::string body = line.substr(first + 3);
        if (!body.empty() && body[0] == ' ') body.erase(0, 1);
        lines.insert(lines.begin(), body);
        if (prev == std::string::npos) break;
        line_begin = prev;
    }
    std::string out;
    for (const auto& l : lines) out += l + "\n";
    return out;
}

std::string signature(const Compilation& c, const ast::ObjectDecl& o) {
    std::string sig = (o.is_plant ? "plant " : "object ") + o.name.text;
    if (!o.params.empty()) {
        sig += "(";
        for (size_t i = 0; i < o.params.size(); ++i) {
            const auto& p = o.params[i];
            sig += (i ? ", " : "") + p.name.text + ": " + p.type.text;
            if (p.default_value) sig += " = " + slice(c, p.default_value->span);
        }
        sig += ")";
    }
    return sig;
}

}  // namespace plant::lsp
