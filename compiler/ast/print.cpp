#include "ast/print.h"

#include <fmt/format.h>

namespace plant::ast {
namespace {

class Printer {
public:
    Printer(const SourceMap& sm, std::ostream& out) : sm_(sm), out_(out) {}

    void line(int depth, const std::string& text, Span s) {
        std::string pos = "-";
        if (s.valid()) {
            auto lc = sm_.line_col(s.file, s.begin);
            pos = fmt::format("{}:{}", lc.line, lc.col);
        }
        out_ << std::string(static_cast<size_t>(depth) * 2, ' ') << text << "  @" << pos << "\n";
    }

    std::string expr(const Expr* e) {
        if (!e) return "_";
        switch (e->kind) {
        case ExprKind::Number: return e->text.empty() ? fmt::format("{}", e->number) : fmt::format("{} {}", e->number, e->text);
        case ExprKind::String: return fmt::format("\"{}\"", e->text);
        case ExprKind::Bool: return e->boolean ? "true" : "false";
        case ExprKind::Name: {
            std::string s = e->text;
            if (e->index) s += "[" + expr(e->index.get()) + "]";
            for (const auto& m : e->members) s += "." + m.text;
            return s;
        }
        case ExprKind::Unary: return fmt::format("({} {})", e->text, expr(e->kids[0].get()));
        case ExprKind::Binary: return fmt::format("({} {} {})", expr(e->kids[0].get()), e->text, expr(e->kids[1].get()));
        case ExprKind::Tuple:
        case ExprKind::List: {
            std::string s = e->kind == ExprKind::Tuple ? "(" : "[";
            for (size_t i = 0; i < e->kids.size(); ++i) s += (i ? ", " : "") + expr(e->kids[i].get());
            return s + (e->kind == ExprKind::Tuple ? ")" : "]");
        }
        case ExprKind::Call: {
            std::string s = e->text + "(";
            for (size_t i = 0; i < e->args.size(); ++i)
                s += (i ? ", " : "") + (e->args[i].name ? e->args[i].name->text + " = " : "") + expr(e->args[i].value.get());
            return s + ")";
        }
        }
        return "?";
    }

    std::string path(const Path& p) {
        std::string s;
        if (p.cast_base) s = "(" + path(*p.cast_base) + " as " + p.cast_type.text + ")";
        for (const auto& seg : p.segs) {
            s += (s.empty() ? "" : ".") + seg.name.text;
            if (seg.index) s += "[" + expr(seg.index.get()) + "]";
        }
        return s;
    }

    std::string placement(const std::optional<Placement>& p) { return p ? placement(*p) : ""; }
    std::string placement(const Placement& p) {
        std::string s = p.at ? " at " + expr(p.at.get()) : "";
        for (const auto& r : p.rotations)
            s += " rotate " + (r.axis_name ? r.axis_name->text : expr(r.axis_vec.get())) + " by " + expr(r.angle.get());
        return s;
    }

    void component(int d, const ComponentDecl& c) {
        line(d, fmt::format("component {} {}{}{}{}", c.kind.text, c.name.text, c.mode ? ": " + c.mode->text : "",
                            c.on ? " on " + path(*c.on) : "", placement(c.placement)), c.span);
        for (const auto& p : c.properties) line(d + 1, fmt::format("property {} = {}", p.name.text, expr(p.value.get())), p.span);
        for (const auto& s : c.shapes) {
            std::string a;
            for (size_t i = 0; i < s.args.size(); ++i) a += (i ? ", " : "") + expr(s.args[i].value.get());
            line(d + 1, fmt::format("shape {}({}){}", s.kind.text, a, placement(s.placement)), s.span);
        }
        for (const auto& a : c.animations) {
            line(d + 1, "animation " + a.name.text, a.span);
            for (const auto& p : a.properties) line(d + 2, fmt::format("property {} = {}", p.name.text, expr(p.value.get())), p.span);
            for (const auto& r : a.rotations)
                line(d + 2, "rotate " + (r.axis_name ? r.axis_name->text : expr(r.axis_vec.get())) + " by " + expr(r.angle.get()), r.span);
            for (const auto& m : a.moves) line(d + 2, "move " + expr(m.get()), m->span);
            for (const auto& k : a.keys) line(d + 2, "key " + expr(k.time.get()) + placement(k.placement), k.span);
        }
        for (const auto& v : c.variants) line(d + 1, fmt::format("variant {} = {}", v.name.text, expr(v.model.get())), v.span);
        for (const auto& p : c.places) line(d + 1, fmt::format("place {} = {}", p.name.text, p.initial ? expr(p.initial.get()) : "0"), p.span);
        for (const auto& t : c.transitions) {
            auto arcs = [](const std::vector<ArcDecl>& l) {
                std::string s;
                for (size_t i = 0; i < l.size(); ++i) s += (i ? " + " : "") + fmt::format("{}*{}", l[i].weight, l[i].place.text);
                return s;
            };
            line(d + 1, fmt::format("transition {}: {} -> {}", t.name.text, arcs(t.inputs), arcs(t.outputs)), t.span);
        }
        for (const auto& r : c.routes)
            line(d + 1, fmt::format("route {} => {}", r.pattern_expr ? expr(r.pattern_expr.get()) : "*", r.output.text), r.span);
        for (const auto& e : c.entries) {
            std::string a;
            for (size_t i = 0; i < e.options.size(); ++i)
                a += (i ? ", " : "") + (e.options[i].name ? e.options[i].name->text + " = " : "") +
                     expr(e.options[i].value.get());
            line(d + 1, fmt::format("entry {} {} => {}{}", e.word.text, expr(e.key.get()), path(e.target),
                                    a.empty() ? "" : " (" + a + ")"), e.span);
        }
        for (const auto& ch : c.children) component(d + 1, ch);
    }

    void members(int d, const std::vector<Member>& ms) {
        for (const auto& m : ms) {
            if (auto* x = std::get_if<PortDecl>(&m)) {
                std::string t;
                for (const auto& p : x->targets) t += (t.empty() ? " => " : ", ") + path(p);
                line(d, fmt::format("port {} {}: {}{}", x->is_input ? "in" : "out", x->name.text, x->type.text, t), x->span);
            } else if (auto* x = std::get_if<LetDecl>(&m)) {
                line(d, fmt::format("let {} = {}", x->name.text, expr(x->value.get())), x->span);
            } else if (auto* x = std::get_if<FlowDecl>(&m)) {
                line(d, fmt::format("flow {}{} -> {}{}{}", x->name ? x->name->text + ": " : "", path(x->from), path(x->to),
                                    x->condition ? " when " + x->condition->text : "", x->once ? " once" : ""), x->span);
            } else if (auto* x = std::get_if<LogicDecl>(&m)) {
                std::string s;
                for (size_t i = 0; i < x->terms.size(); ++i)
                    s += (i ? " " + x->ops[i - 1].text + " " : "") + (x->terms[i].negated ? "not " : "") + path(x->terms[i].path);
                line(d, fmt::format("logic {} = {}", x->name.text, s), x->span);
            } else if (auto* x = std::get_if<RecordDecl>(&m)) {
                line(d, fmt::format("record {}{}", path(x->path), x->column ? " as " + expr(x->column.get()) : ""), x->span);
            } else if (auto* x = std::get_if<SettingDecl>(&m)) {
                line(d, fmt::format("setting {} = {}", x->name.text, expr(x->value.get())), x->span);
            } else if (auto* x = std::get_if<InstanceDecl>(&m)) {
                std::string a;
                for (size_t i = 0; i < x->args.size(); ++i)
                    a += (i ? ", " : "") + (x->args[i].name ? x->args[i].name->text + " = " : "") + expr(x->args[i].value.get());
                line(d, fmt::format("instance {}{}: {}({}){}", x->name.text, x->index ? "[" + expr(x->index.get()) + "]" : "",
                                    x->type.text, a, placement(x->placement)), x->span);
            } else if (auto* x = std::get_if<ComponentDecl>(&m)) {
                component(d, *x);
            } else if (auto* x = std::get_if<std::unique_ptr<ForDecl>>(&m)) {
                line(d, (*x)->to ? fmt::format("for {} in {} .. {}", (*x)->var.text, expr((*x)->from.get()), expr((*x)->to.get()))
                                 : fmt::format("for {} in {}", (*x)->var.text, expr((*x)->from.get())),
                     (*x)->span);
                members(d + 1, (*x)->body);
            } else if (auto* x = std::get_if<std::unique_ptr<IfDecl>>(&m)) {
                line(d, "if " + expr((*x)->cond.get()), (*x)->span);
                members(d + 1, (*x)->then_body);
                if (!(*x)->else_body.empty()) {
                    line(d, "else", (*x)->span);
                    members(d + 1, (*x)->else_body);
                }
            }
        }
    }

private:
    const SourceMap& sm_;
    std::ostream& out_;
};

}  // namespace

void print(const Module& m, const SourceMap& sm, std::ostream& out) {
    Printer p(sm, out);
    out << "module " << (m.file >= 0 ? sm.name(m.file) : "?") << "\n";
    for (const auto& i : m.imports) p.line(1, "import " + i.module, i.span);
    for (const auto& o : m.objects) {
        std::string params;
        for (size_t i = 0; i < o.params.size(); ++i)
            params += (i ? ", " : "") + o.params[i].name.text + ": " + o.params[i].type.text +
                      (o.params[i].default_value ? " = " + p.expr(o.params[i].default_value.get()) : "") +
                      (o.params[i].constraint ? " where " + p.expr(o.params[i].constraint.get()) : "");
        p.line(1, fmt::format("{} {}{}", o.is_plant ? "plant" : "object", o.name.text, o.is_plant && o.params.empty() ? "" : "(" + params + ")"), o.span);
        p.members(2, o.members);
    }
}

}  // namespace plant::ast
