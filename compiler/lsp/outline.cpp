// The outline of a file: one DocumentSymbol per object type and plant, with its members
// as children. Ranges are the declarations' spans; the selection range is the name.
#include "lsp/protocol.h"
#include "lsp/symbols.h"

#include <variant>

namespace plant::lsp {
namespace {

using nlohmann::json;

// The LSP's SymbolKind numbers we use.
enum Kind {
    kModule = 2, kClass = 5, kMethod = 6, kProperty = 7, kField = 8, kInterface = 11,
    kFunction = 12, kConstant = 14, kArray = 18, kObject = 19, kEnumMember = 22, kOperator = 25
};

class Outline {
public:
    explicit Outline(const Compilation& c) : c_(c) {}

    json object(const ast::ObjectDecl& o) {
        json children = json::array();
        for (const auto& p : o.params)
            children.push_back(symbol(p.name.text, p.type.text, kProperty, p.span, p.name.span));
        members(o.members, children);
        return symbol(o.name.text, o.is_plant ? "plant" : "object", o.is_plant ? kModule : kClass, o.span,
                      o.name.span, std::move(children));
    }

private:
    std::string text(const Span& s) const {
        if (!s.valid()) return "";
        const std::string& t = c_.sources.text(s.file);
        if (s.begin >= t.size()) return "";
        return t.substr(s.begin, std::min<size_t>(s.end, t.size()) - s.begin);
    }

    json symbol(const std::string& name, const std::string& detail, Kind kind, const Span& range, Span selection,
                json children = json::array()) const {
        // The selection must lie inside the range (clients check it).
        if (!selection.valid() || selection.file != range.file || selection.begin < range.begin || selection.end > range.end)
            selection = range;
        json s = {{"name", name.empty() ? "?" : name}, {"detail", detail}, {"kind", kind},
                  {"range", range_of(c_.sources, range)}, {"selectionRange", range_of(c_.sources, selection)}};
        if (!children.empty()) s["children"] = std::move(children);
        return s;
    }

    json component(const ast::ComponentDecl& k) const {
        json children = json::array();
        for (const auto& p : k.places) children.push_back(symbol(p.name.text, "place", kEnumMember, p.span, p.name.span));
        for (const auto& t : k.transitions)
            children.push_back(symbol(t.name.text, "transition", kMethod, t.span, t.name.span));
        for (const auto& child : k.children) children.push_back(component(child));
        const std::string detail = k.kind.text + (k.mode ? ": " + k.mode->text : "");
        return k.name.text.empty() ? symbol(k.kind.text, detail, kField, k.span, k.kind.span, std::move(children))
                                   : symbol(k.name.text, detail, kField, k.span, k.name.span, std::move(children));
    }

    void members(const std::vector<ast::Member>& ms, json& out) {
        for (const auto& m : ms) {
            if (auto* p = std::get_if<ast::PortDecl>(&m)) {
                out.push_back(symbol(p->name.text, (p->is_input ? "in " : "out ") + p->type.text, kInterface, p->span,
                                     p->name.span));
            } else if (auto* l = std::get_if<ast::LetDecl>(&m)) {
                out.push_back(symbol(l->name.text, "let", kConstant, l->span, l->name.span));
            } else if (auto* i = std::get_if<ast::InstanceDecl>(&m)) {
                std::string name = i->name.text;
                if (i->index) {
                    name += '[';
                    name += text(i->index->span);
                    name += ']';
                }
                out.push_back(symbol(name, i->type.text, kObject, i->span, i->name.span));
            } else if (auto* k = std::get_if<ast::ComponentDecl>(&m)) {
                out.push_back(component(*k));
            } else if (auto* g = std::get_if<ast::LogicDecl>(&m)) {
                out.push_back(symbol(g->name.text, "logic", kFunction, g->span, g->name.span));
            } else if (auto* f = std::get_if<ast::FlowDecl>(&m)) {
                const std::string name = f->name ? f->name->text : text(f->from.span) + " -> " + text(f->to.span);
                out.push_back(symbol(name, "flow", kOperator, f->span, f->name ? f->name->span : f->from.span));
            } else if (auto* loop = std::get_if<std::unique_ptr<ast::ForDecl>>(&m)) {
                const ast::ForDecl& fd = **loop;
                json body = json::array();
                members(fd.body, body);
                const std::string over = fd.to ? text(fd.from->span) + " .. " + text(fd.to->span)
                                               : (fd.from ? text(fd.from->span) : "");
                out.push_back(symbol("for " + fd.var.text, "in " + over, kArray, fd.span, fd.var.span, std::move(body)));
            } else if (auto* cond = std::get_if<std::unique_ptr<ast::IfDecl>>(&m)) {
                const ast::IfDecl& d = **cond;
                json body = json::array();
                members(d.then_body, body);
                members(d.else_body, body);
                out.push_back(symbol("if " + (d.cond ? text(d.cond->span) : ""), "if", kArray, d.span,
                                     d.cond ? d.cond->span : d.span, std::move(body)));
            }
        }
    }

    const Compilation& c_;
};

}  // namespace

json document_symbols(const Compilation& c, const sema::LoadedModule& m) {
    json out = json::array();
    Outline outline(c);
    for (const auto& o : m.ast->objects) out.push_back(outline.object(o));
    return out;
}

}  // namespace plant::lsp
