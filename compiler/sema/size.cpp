#include "sema/size.h"

#include <algorithm>

namespace plant::sema {

std::optional<double> literal_number(const ast::Expr& e) {
    switch (e.kind) {
    case ast::ExprKind::Number:
        if (!e.text.empty()) return std::nullopt;  // a quantity with a unit is no count
        return e.number;
    case ast::ExprKind::Unary: {
        if (e.text != "-" || e.kids.size() != 1) return std::nullopt;
        const auto v = literal_number(*e.kids[0]);
        return v ? std::optional<double>(-*v) : std::nullopt;
    }
    case ast::ExprKind::Binary: {
        if (e.kids.size() != 2) return std::nullopt;
        const auto a = literal_number(*e.kids[0]), b = literal_number(*e.kids[1]);
        if (!a || !b) return std::nullopt;
        if (e.text == "+") return *a + *b;
        if (e.text == "-") return *a - *b;
        if (e.text == "*") return *a * *b;
        return std::nullopt;  // a division or a comparison: not worth guessing at
    }
    default: return std::nullopt;
    }
}

std::optional<StaticSize> SizeEstimate::of(const ast::ObjectDecl& decl) {
    if (auto it = known_.find(&decl); it != known_.end()) return it->second;
    if (visiting_[&decl]) return std::nullopt;  // a recursion: the elaborator reports it
    visiting_[&decl] = true;
    auto size = of(decl.members);
    visiting_[&decl] = false;
    known_[&decl] = size;
    return size;
}

std::optional<StaticSize> SizeEstimate::pool(const ast::ComponentDecl& c) {
    if (c.kind.text != "source") return StaticSize{};
    const ast::Expr *object = nullptr, *pool = nullptr;
    for (const auto& p : c.properties) {
        if (p.name.text == "object") object = p.value.get();
        if (p.name.text == "pool") pool = p.value.get();
    }
    if (!object || !pool) return StaticSize{};
    const auto n = literal_number(*pool);  // `object = Bottle` or `object = Bottle(mass = 40 g)`
    if (!n || (object->kind != ast::ExprKind::Name && object->kind != ast::ExprKind::Call)) return std::nullopt;
    const ast::ObjectDecl* t = type_(object->text);
    if (!t) return std::nullopt;
    const auto one = of(*t);
    if (!one) return std::nullopt;
    return StaticSize{std::max(*n, 0.0) * one->members, std::max(*n, 0.0) * one->iterations};
}

std::optional<StaticSize> SizeEstimate::of(std::span<const ast::Member> members) {
    StaticSize s;
    for (const auto& m : members) {
        s.members += 1;
        if (const auto* inst = std::get_if<ast::InstanceDecl>(&m)) {
            const ast::ObjectDecl* t = type_(inst->type.text);
            if (!t) return std::nullopt;
            const auto child = of(*t);
            if (!child) return std::nullopt;
            s.members += child->members;
            s.iterations += child->iterations;
        } else if (const auto* c = std::get_if<ast::ComponentDecl>(&m)) {
            const auto p = pool(*c);
            if (!p) return std::nullopt;
            s.members += p->members;
            s.iterations += p->iterations;
        } else if (const auto* fp = std::get_if<std::unique_ptr<ast::ForDecl>>(&m)) {
            const ast::ForDecl& f = **fp;
            std::optional<double> n;
            if (!f.to) {
                if (f.from->kind == ast::ExprKind::List) n = double(f.from->kids.size());
            } else if (const auto a = literal_number(*f.from), b = literal_number(*f.to); a && b) {
                n = std::max(*b - *a, 0.0);
            }
            if (!n) return std::nullopt;
            const auto body = of(f.body);
            if (!body) return std::nullopt;
            s.iterations += *n * (1 + body->iterations);
            s.members += *n * body->members;
        } else if (const auto* ip = std::get_if<std::unique_ptr<ast::IfDecl>>(&m)) {
            const ast::IfDecl& c = **ip;
            if (c.cond->kind != ast::ExprKind::Bool) return std::nullopt;
            const auto body = of(c.cond->boolean ? c.then_body : c.else_body);
            if (!body) return std::nullopt;
            s.members += body->members;
            s.iterations += body->iterations;
        }
    }
    return s;
}

}  // namespace plant::sema
