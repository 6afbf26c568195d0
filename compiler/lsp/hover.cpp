// Hover: what the name under the cursor is. A component kind word or a property name gets
// the registry's description; any other name is looked up in the names sema resolved
// (lsp/symbols.h) and its declaration described: an object type by its signature and `///` comment, a port by direction
// and type, a parameter by type, unit and default, a `let` by its expression, dimension and
// value (with the parameters' defaults), a component's slot by direction and type.
#include "lsp/lookup.h"
#include "lsp/symbols.h"

#include "graph/kinds.h"
#include "sema/schema.h"
#include "sema/value.h"

#include <fmt/format.h>

#include <memory>
#include <variant>

namespace plant::lsp {
namespace {

using nlohmann::json;

json markdown(const std::string& code, const std::string& text) {
    return {{"contents", {{"kind", "markdown"}, {"value", "```plant\n" + code + "\n```" + (text.empty() ? "" : "\n\n" + text)}}}};
}

// The declaration a Target's offset names, and the object type it is written in.
struct Decl {
    const ast::ObjectDecl* owner = nullptr;
    const ast::ObjectDecl* type = nullptr;  // the object type's own name
    const ast::Param* param = nullptr;
    const ast::PortDecl* port = nullptr;
    const ast::InstanceDecl* instance = nullptr;
    const ast::ComponentDecl* component = nullptr;
    const ast::LetDecl* let = nullptr;
    const ast::LogicDecl* logic = nullptr;
    const ast::ForDecl* loop = nullptr;
};

bool find_in(const std::vector<ast::Member>& ms, uint32_t at, Decl& d) {
    for (const auto& m : ms) {
        if (auto* i = std::get_if<ast::InstanceDecl>(&m); i && i->name.span.begin == at) d.instance = i;
        else if (auto* p = std::get_if<ast::PortDecl>(&m); p && p->name.span.begin == at) d.port = p;
        else if (auto* k = std::get_if<ast::ComponentDecl>(&m); k && k->name.span.begin == at) d.component = k;
        else if (auto* l = std::get_if<ast::LetDecl>(&m); l && l->name.span.begin == at) d.let = l;
        else if (auto* g = std::get_if<ast::LogicDecl>(&m); g && g->name.span.begin == at) d.logic = g;
        else if (auto* f = std::get_if<std::unique_ptr<ast::ForDecl>>(&m)) {
            if ((*f)->var.span.begin == at) d.loop = f->get();
            else if (!find_in((*f)->body, at, d)) continue;
        } else if (auto* c = std::get_if<std::unique_ptr<ast::IfDecl>>(&m)) {
            if (!find_in((*c)->then_body, at, d) && !find_in((*c)->else_body, at, d)) continue;
        } else {
            continue;
        }
        return true;
    }
    return false;
}

Decl find_decl(const Compilation& c, const Target& t) {
    Decl d;
    for (const auto& m : c.program.modules) {
        if (m.key != t.file) continue;
        for (const auto& o : m.ast->objects) {
            d.owner = &o;
            if (o.name.span.begin == t.at) d.type = &o;
            for (const auto& p : o.params)
                if (p.name.span.begin == t.at) d.param = &p;
            if (d.type || d.param || find_in(o.members, t.at, d)) return d;
        }
    }
    return {};
}

std::string param_text(const Compilation& c, const ast::Param& p, const ast::ObjectDecl& owner) {
    std::string text = "parameter of " + owner.name.text;
    if (auto dim = units::dim_of_type(p.type.text)) text += "; unit: " + units::si_unit(*dim);
    if (p.default_value) text += "; default: " + slice(c, p.default_value->span);
    return text;
}

struct Types : sema::TypeLookup {
    explicit Types(const Compilation& c) : c_(c) {}
    bool is_object_type(const std::string& name) const override { return find_type(c_, name) != nullptr; }
    const ast::ObjectDecl* object_type(const std::string& name) const override { return find_type(c_, name); }
    const Compilation& c_;
};

// A `let`'s value with every parameter at its default (a parameter without one: 1 of its
// unit), the `let`s before it evaluated in order; None when it needs a loop variable.
sema::Value let_value(const Compilation& c, const ast::ObjectDecl& o, const ast::LetDecl& target) {
    Sink sink;
    Types types(c);
    sema::Evaluator ev(sink, types);
    auto env = std::make_shared<sema::Env>();
    for (const auto& p : o.params) {
        if (p.default_value) env->set(p.name.text, ev.eval(*p.default_value, *env));
        else if (auto dim = units::dim_of_type(p.type.text)) env->set(p.name.text, sema::Value::number(1, *dim, p.span));
    }
    for (const ast::LetDecl* l : members_of(o).lets) {
        if (!l->value) return {};
        sema::Value v = ev.eval(*l->value, *env);
        if (l == &target) return v;
        env->set(l->name.text, v);
    }
    return {};
}

std::string value_text(const sema::Value& v) {
    if (v.kind == sema::Value::Kind::Num)
        return v.dim.none() ? fmt::format("{:g}", v.num) : fmt::format("{:g} {}", v.num, units::si_unit(v.dim));
    if (v.kind == sema::Value::Kind::Bool) return v.boolean ? "true" : "false";
    if (v.kind == sema::Value::Kind::Str) return "\"" + v.str + "\"";
    if (v.kind == sema::Value::Kind::Vec) {
        std::string out = "(";
        for (size_t i = 0; i < v.items.size(); ++i) out += (i ? ", " : "") + value_text(v.items[i]);
        return out + ")";
    }
    return "";
}

json describe_let(const Compilation& c, const ast::ObjectDecl& o, const ast::LetDecl& l) {
    const sema::Value v = let_value(c, o, l);
    std::string text = "let in " + o.name.text;
    if (v.kind != sema::Value::Kind::None) {
        text += "; " + sema::describe(v);
        if (v.kind == sema::Value::Kind::Num && !v.dim.none()) text += " (" + units::si_unit(v.dim) + ")";
        if (const std::string shown = value_text(v); !shown.empty())
            text += "; value" + std::string(o.params.empty() ? "" : " with the parameters' defaults") + ": " + shown;
    }
    return markdown("let " + l.name.text + " = " + (l.value ? slice(c, l.value->span) : ""), text);
}

// A component's slot: a fixed one of its kind, or one its content declares.
json describe_slot(const ast::ComponentDecl& k, const std::string& slot) {
    const std::string where = "of " + k.kind.text + " " + k.name.text;
    if (const sema::KindSpec* spec = sema::find_kind(k.kind.text))
        for (const graph::SlotSpec& s : sema::kind_slots(*spec))
            if (s.name == slot)
                return markdown(fmt::format("{} {}: {}", graph::word(s.dir), s.name, graph::word(s.type)),
                                "slot " + where + (s.doc.empty() ? "" : "; " + std::string(s.doc)));
    const std::string first = slot.substr(0, slot.find('.'));
    const char* what = "slot";
    for (const auto& p : k.places) if (p.name.text == first) what = "place";
    for (const auto& t : k.transitions) if (t.name.text == first) what = "transition";
    for (const auto& a : k.animations) if (a.name.text == first) what = "animation";
    for (const auto& v : k.variants) if (v.name.text == first) what = "variant";
    for (const auto& g : k.children) if (g.name.text == first) what = "child graphics";
    const bool own = first == slot;
    return markdown(slot, std::string(own ? what : "slot") + " " + where + (own ? "" : std::string(" (of its ") + what + " " + first + ")"));
}

json describe_kind(const ast::ComponentDecl& k) {
    const sema::KindSpec* spec = sema::find_kind(k.kind.text);
    if (!spec) return nullptr;
    std::string text = std::string(spec->doc);
    if (!spec->modes.empty()) {
        text += "\n\nmodes:";
        for (const auto& m : spec->modes) text += " `" + std::string(m) + "`";
    }
    if (!spec->props.empty()) {
        text += "\n\nproperties:";
        for (const auto& p : spec->props) text += " `" + std::string(p.name) + "`" + (p.required ? " (required)" : "");
    }
    return markdown(std::string(spec->word) + " component", text);
}

json describe_property(const ast::ComponentDecl& k, const ast::Property& p) {
    const sema::KindSpec* spec = sema::find_kind(k.kind.text);
    const sema::PropSpec* prop = spec ? sema::find_prop(*spec, p.name.text) : nullptr;
    if (!prop) return nullptr;
    std::string text = "property of " + k.kind.text + (prop->required ? " (required)" : "") +
                       (prop->dim.none() ? "" : "; unit: " + units::si_unit(prop->dim));
    if (!prop->doc.empty()) text += "; " + std::string(prop->doc);
    return markdown(std::string(prop->name), text);
}

// A kind word or a property name under the cursor, in `k` or its child graphics.
json on_component(const ast::ComponentDecl& k, size_t offset) {
    if (inside(k.kind.span, offset)) return describe_kind(k);
    for (const auto& p : k.properties)
        if (inside(p.name.span, offset)) return describe_property(k, p);
    for (const auto& child : k.children)
        if (json h = on_component(child, offset); !h.is_null()) return h;
    return nullptr;
}

json on_kinds(const std::vector<ast::Member>& ms, size_t offset) {
    for (const auto& m : ms) {
        json h;
        if (auto* k = std::get_if<ast::ComponentDecl>(&m)) h = on_component(*k, offset);
        else if (auto* f = std::get_if<std::unique_ptr<ast::ForDecl>>(&m)) h = on_kinds((*f)->body, offset);
        else if (auto* c = std::get_if<std::unique_ptr<ast::IfDecl>>(&m)) {
            h = on_kinds((*c)->then_body, offset);
            if (h.is_null()) h = on_kinds((*c)->else_body, offset);
        }
        if (!h.is_null()) return h;
    }
    return nullptr;
}

}  // namespace

json hover(const Compilation& c, const sema::LoadedModule& m, size_t offset) {
    for (const auto& o : m.ast->objects)
        if (json h = on_kinds(o.members, offset); !h.is_null()) return h;
    // An instance's name: its type.
    for (const auto& o : m.ast->objects)
        for (const ast::InstanceDecl* i : members_of(o).instances)
            if (inside(i->name.span, offset)) offset = i->type.span.begin;
    const std::optional<Target> t = target_at(c, m, offset);
    if (!t) return nullptr;
    const Decl d = find_decl(c, *t);
    if (d.type) return markdown(signature(c, *d.type), doc_comment(c, d.type->span));
    if (d.param) return markdown(d.param->name.text + ": " + d.param->type.text, param_text(c, *d.param, *d.owner));
    if (d.port)
        return markdown((d.port->is_input ? "in " : "out ") + d.port->name.text + ": " + d.port->type.text,
                        std::string(d.port->is_input ? "input" : "output") + " port of " + d.owner->name.text);
    if (d.let) return describe_let(c, *d.owner, *d.let);
    if (d.loop) return markdown(d.loop->var.text, "loop variable in " + d.owner->name.text);
    if (d.logic) return markdown("logic " + d.logic->name.text, "logic connector of " + d.owner->name.text + ": a bool output");
    if (d.instance)
        if (const ast::ObjectDecl* type = find_type(c, d.instance->type.text))
            return markdown(d.instance->name.text + ": " + type->name.text, signature(c, *type));
    if (d.component) {
        if (!t->slot.empty()) return describe_slot(*d.component, t->slot);
        const sema::KindSpec* spec = sema::find_kind(d.component->kind.text);
        return markdown(d.component->kind.text + " " + d.component->name.text,
                        spec ? std::string(spec->doc) : "");
    }
    return nullptr;
}

}  // namespace plant::lsp
