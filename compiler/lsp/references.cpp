// Find references: every name in the parsed modules is resolved to a Target (the
// declaration it stands for), by the same walk for the name under the cursor and for its
// uses. A name in an expression is a loop variable, a `let` before it in an enclosing
// body, or a parameter of the object it is written in; a named argument `speed = v` names
// the parameter of the type called. Dotted paths resolve as the compiler reads them: a segment names an instance, a
// port, a component or a logic connector of the object it is written in, an instance's
// type is where the next segment is looked up, and what follows a component is a slot of
// it. A cast `(p as T)` and a source's pooled objects `store[i]` continue in their type.
#include "lsp/protocol.h"
#include "lsp/symbols.h"

#include <map>
#include <set>
#include <utility>
#include <variant>
#include <vector>

namespace plant::lsp {
namespace {

using nlohmann::json;

struct Occurrence {
    Span span;
    Target target;
    bool declaration = false;
};

// A member a path segment can name.
struct Named {
    const ast::InstanceDecl* instance = nullptr;
    const ast::ComponentDecl* component = nullptr;
    Span name;  // its declared name
};

class Walker {
public:
    explicit Walker(const Compilation& c) {
        for (const auto& m : c.program.modules) {
            file_key_[m.ast->file] = m.key;
            for (const auto& o : m.ast->objects)
                if (!o.is_plant) types_.try_emplace(o.name.text, &o);
        }
    }

    // Every occurrence in module `m`.
    void walk(const sema::LoadedModule& m, std::vector<Occurrence>& out) {
        out_ = &out;
        for (const auto& o : m.ast->objects) {
            if (!o.is_plant) add(o.name.span, declared(o.name.span), true);
            values_.clear();
            for (const auto& p : o.params) declare(p.name);
            for (const auto& p : o.params) {
                expr(p.default_value.get());
                expr(p.constraint.get());
            }
            members(o.members, o);
        }
    }

private:
    Target declared(const Span& name, std::string slot = "") const {
        auto it = file_key_.find(name.file);
        return {it == file_key_.end() ? "" : it->second, name.begin, std::move(slot)};
    }

    void add(const Span& span, Target t, bool declaration = false) {
        if (span.valid() && !t.file.empty()) out_->push_back({span, std::move(t), declaration});
    }

    const ast::ObjectDecl* type(const std::string& name) const {
        auto it = types_.find(name);
        return it == types_.end() ? nullptr : it->second;
    }

    void type_use(const std::string& name, const Span& span) {
        if (const ast::ObjectDecl* t = type(name)) add(span, declared(t->name.span));
    }

    // A parameter, `let` or loop variable: in scope from here to the end of its body.
    void declare(const ast::Ident& name) {
        add(name.span, declared(name.span), true);
        values_.emplace_back(name.text, declared(name.span));
    }

    // The arguments of a call of type `callee` (an instance or `Bottle(mass = 20 g)`).
    void args(const std::vector<ast::Arg>& as, const std::string& callee) {
        const ast::ObjectDecl* t = type(callee);
        for (const auto& a : as) {
            if (a.name && t)
                for (const auto& p : t->params)
                    if (p.name.text == a.name->text) add(a.name->span, declared(p.name.span));
            expr(a.value.get());
        }
    }

    void expr(const ast::Expr* e) {
        if (!e) return;
        if (e->kind == ast::ExprKind::Name) {
            for (auto it = values_.rbegin(); it != values_.rend(); ++it)
                if (it->first == e->text) {
                    add({e->span.file, e->span.begin, e->span.begin + uint32_t(e->text.size())}, it->second);
                    break;
                }
        }
        if (e->kind == ast::ExprKind::Call) args(e->args, e->text);
        expr(e->index.get());
        for (const auto& k : e->kids) expr(k.get());
    }

    void placement(const std::optional<ast::Placement>& p) {
        if (!p) return;
        expr(p->at.get());
        rotations(p->rotations);
    }
    void rotations(const std::vector<ast::Rotation>& rs) {
        for (const auto& r : rs) {
            expr(r.axis_vec.get());
            expr(r.angle.get());
        }
    }

    // The members of `o` a path can name, through its `for`s and `if`s.
    const std::map<std::string, Named>& scope(const ast::ObjectDecl& o) {
        auto [it, fresh] = scopes_.try_emplace(&o);
        if (fresh) fill(o.members, it->second);
        return it->second;
    }
    static void fill(const std::vector<ast::Member>& ms, std::map<std::string, Named>& out) {
        for (const auto& m : ms) {
            if (auto* i = std::get_if<ast::InstanceDecl>(&m)) out.try_emplace(i->name.text, Named{i, nullptr, i->name.span});
            else if (auto* p = std::get_if<ast::PortDecl>(&m)) out.try_emplace(p->name.text, Named{nullptr, nullptr, p->name.span});
            else if (auto* k = std::get_if<ast::ComponentDecl>(&m)) {
                if (!k->name.text.empty()) out.try_emplace(k->name.text, Named{nullptr, k, k->name.span});
            } else if (auto* l = std::get_if<ast::LogicDecl>(&m)) out.try_emplace(l->name.text, Named{nullptr, nullptr, l->name.span});
            else if (auto* f = std::get_if<std::unique_ptr<ast::ForDecl>>(&m)) fill((*f)->body, out);
            else if (auto* c = std::get_if<std::unique_ptr<ast::IfDecl>>(&m)) {
                fill((*c)->then_body, out);
                fill((*c)->else_body, out);
            }
        }
    }

    // The type a source issues: the callee of its `object` property.
    const ast::ObjectDecl* issued_type(const ast::ComponentDecl& k) const {
        if (k.kind.text != "source") return nullptr;
        for (const auto& p : k.properties)
            if (p.name.text == "object" && p.value) return type(p.value->text);
        return nullptr;
    }

    void path(const ast::Path& p, const ast::ObjectDecl* in) {
        if (p.cast_base) {
            path(*p.cast_base, in);
            type_use(p.cast_type.text, p.cast_type.span);
            in = type(p.cast_type.text);
        }
        std::optional<Target> component;  // set once a segment named a component
        for (const auto& seg : p.segs) expr(seg.index.get());
        for (const auto& seg : p.segs) {
            if (component) {
                component->slot += (component->slot.empty() ? "" : ".") + seg.name.text;
                add(seg.name.span, *component);
                continue;
            }
            if (!in) return;
            const auto& names = scope(*in);
            auto it = names.find(seg.name.text);
            if (it == names.end()) return;
            const Named& n = it->second;
            add(seg.name.span, declared(n.name));
            if (n.instance) {
                in = type(n.instance->type.text);
            } else if (n.component && seg.index && issued_type(*n.component)) {
                in = issued_type(*n.component);  // a pooled object: store[i].body...
            } else if (n.component) {
                component = declared(n.name);
            } else {
                return;  // a port or a logic connector: a slot itself
            }
        }
    }

    void component(const ast::ComponentDecl& k, const ast::ObjectDecl& o, const Target& self) {
        if (k.on) path(*k.on, &o);
        placement(k.placement);
        for (const auto& p : k.properties) expr(p.value.get());
        for (const auto& sh : k.shapes) {
            args(sh.args, "");
            placement(sh.placement);
        }
        for (const auto& an : k.animations) {
            for (const auto& p : an.properties) expr(p.value.get());
            rotations(an.rotations);
            for (const auto& mv : an.moves) expr(mv.get());
            for (const auto& key : an.keys) {
                expr(key.time.get());
                expr(key.placement.at.get());
                rotations(key.placement.rotations);
            }
        }
        for (const auto& v : k.variants) expr(v.model.get());
        for (const auto& pl : k.places) expr(pl.initial.get());
        for (const auto& r : k.routes) expr(r.pattern_expr.get());
        for (const auto& e : k.entries) {  // a plugin kind's: `coil 3 => s1.to_working (...)`
            expr(e.key.get());
            path(e.target, &o);
            for (const auto& a : e.options) expr(a.value.get());
        }
        for (const auto& p : k.properties)
            if ((p.name.text == "object" || p.name.text == "filter") && p.value &&
                (p.value->kind == ast::ExprKind::Name || p.value->kind == ast::ExprKind::Call))
                type_use(p.value->text, {p.value->span.file, p.value->span.begin,
                                         p.value->span.begin + uint32_t(p.value->text.size())});
        auto slot = [&](const std::string& name) { return Target{self.file, self.at, (self.slot.empty() ? "" : self.slot + ".") + name}; };
        for (const auto& pl : k.places) add(pl.name.span, slot(pl.name.text), true);
        for (const auto& an : k.animations) add(an.name.span, slot(an.name.text), true);
        for (const auto& v : k.variants) add(v.name.span, slot(v.name.text), true);
        for (const auto& t : k.transitions) {
            add(t.name.span, slot(t.name.text), true);
            for (const auto* arcs : {&t.inputs, &t.outputs})
                for (const auto& a : *arcs) add(a.place.span, slot(a.place.text));
        }
        for (const auto& child : k.children) {
            const Target t = slot(child.name.text);
            add(child.name.span, t, true);
            component(child, o, t);
        }
    }

    void members(const std::vector<ast::Member>& ms, const ast::ObjectDecl& o) {
        const size_t scope_size = values_.size();  // a body's lets and loop variable end with it
        for (const auto& m : ms) {
            if (auto* i = std::get_if<ast::InstanceDecl>(&m)) {
                add(i->name.span, declared(i->name.span), true);
                type_use(i->type.text, i->type.span);
                expr(i->index.get());
                args(i->args, i->type.text);
                placement(i->placement);
            } else if (auto* let = std::get_if<ast::LetDecl>(&m)) {
                expr(let->value.get());
                declare(let->name);
            } else if (auto* set = std::get_if<ast::SettingDecl>(&m)) {
                expr(set->value.get());
            } else if (auto* p = std::get_if<ast::PortDecl>(&m)) {
                add(p->name.span, declared(p->name.span), true);
                for (const auto& t : p->targets) path(t, &o);
            } else if (auto* k = std::get_if<ast::ComponentDecl>(&m)) {
                if (!k->name.text.empty()) add(k->name.span, declared(k->name.span), true);
                component(*k, o, declared(k->name.span));
            } else if (auto* l = std::get_if<ast::LogicDecl>(&m)) {
                add(l->name.span, declared(l->name.span), true);
                for (const auto& t : l->terms) path(t.path, &o);
            } else if (auto* f = std::get_if<ast::FlowDecl>(&m)) {
                path(f->from, &o);
                path(f->to, &o);
            } else if (auto* r = std::get_if<ast::RecordDecl>(&m)) {
                path(r->path, &o);
                expr(r->column.get());
            } else if (auto* loop = std::get_if<std::unique_ptr<ast::ForDecl>>(&m)) {
                expr((*loop)->from.get());
                expr((*loop)->to.get());
                const size_t outer = values_.size();
                declare((*loop)->var);
                members((*loop)->body, o);
                values_.resize(outer);
            } else if (auto* c = std::get_if<std::unique_ptr<ast::IfDecl>>(&m)) {
                expr((*c)->cond.get());
                members((*c)->then_body, o);
                members((*c)->else_body, o);
            }
        }
        values_.resize(scope_size);
    }

    std::map<int32_t, std::string> file_key_;
    std::map<std::string, const ast::ObjectDecl*> types_;
    std::map<const ast::ObjectDecl*, std::map<std::string, Named>> scopes_;
    std::vector<std::pair<std::string, Target>> values_;  // the names in scope, innermost last
    std::vector<Occurrence>* out_ = nullptr;
};

}  // namespace

std::optional<Target> target_at(const Compilation& c, const sema::LoadedModule& m, size_t offset) {
    std::vector<Occurrence> all;
    Walker(c).walk(m, all);
    const Occurrence* best = nullptr;
    for (const Occurrence& o : all)
        if (o.span.file == m.ast->file && o.span.begin <= offset && offset <= o.span.end &&
            (!best || o.span.end - o.span.begin < best->span.end - best->span.begin))
            best = &o;
    if (!best) return std::nullopt;
    return best->target;
}

void add_references(const Compilation& c, const Target& t, bool include_declaration, json& locations) {
    Walker walker(c);
    std::set<std::string> have;
    for (const json& l : locations) have.insert(l.dump());
    for (const auto& m : c.program.modules) {
        std::vector<Occurrence> all;
        walker.walk(m, all);
        for (const Occurrence& o : all) {
            if (o.target != t || (o.declaration && !include_declaration)) continue;
            json l = {{"uri", path_to_uri(m.key)}, {"range", range_of(c.sources, o.span)}};
            if (have.insert(l.dump()).second) locations.push_back(std::move(l));
        }
    }
}

json declaration_of(const Compilation& c, const Target& t) {
    for (const auto& m : c.program.modules) {
        if (m.key != t.file) continue;
        std::vector<Occurrence> all;
        Walker(c).walk(m, all);
        // A place, transition, variant or child graphics is declared by name; a built-in
        // slot (`look.tick`) by its component.
        for (const Target& want : {t, Target{t.file, t.at, ""}})
            for (const Occurrence& o : all)
                if (o.declaration && o.target == want)
                    return {{"uri", path_to_uri(m.key)}, {"range", range_of(c.sources, o.span)}};
    }
    return nullptr;
}

}  // namespace plant::lsp
