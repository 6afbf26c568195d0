// Instantiation: the plant object, then every instance inside it, depth first.
#include "sema/elaborator.h"
#include "sema/size.h"

#include "graph/build.h"
#include "graph/range.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <fmt/format.h>

namespace plant::sema {

namespace {
constexpr int kMaxDepth = 64;                  // nesting of loops/conditions

template <class T> Span span_of(const T& member) { return member.span; }

// The first name in `e` that is a parameter of `decl`, or null.
const ast::Expr* uses_param(const ast::Expr& e, const ast::ObjectDecl& decl) {
    if (e.kind == ast::ExprKind::Name)
        for (const auto& p : decl.params)
            if (p.name.text == e.text) return &e;
    for (const auto& k : e.kids)
        if (const ast::Expr* u = k ? uses_param(*k, decl) : nullptr) return u;
    for (const auto& a : e.args)
        if (const ast::Expr* u = a.value ? uses_param(*a.value, decl) : nullptr) return u;
    if (e.index) return uses_param(*e.index, decl);
    return nullptr;
}
template <class T> Span span_of(const std::unique_ptr<T>& member) { return member->span; }
}  // namespace

Elaborator::Elaborator(const Program& prog, const SourceMap& sm, Sink& sink)
    : prog_(prog), sm_(sm), sink_(sink), ev_(sink, *this) {
    graph_file_of_.assign(sm.size(), -1);
    // Object types are one namespace; a duplicate is an error even across modules.
    for (size_t m = 0; m < prog.modules.size(); ++m)
        for (const auto& o : prog.modules[m].ast->objects) {
            if (o.is_plant) continue;
            auto [it, fresh] = types_.try_emplace(o.name.text, static_cast<int>(m), &o);
            if (!fresh) {
                auto& d = sink_.report(DiagId::DuplicateName, o.name.span,
                                       fmt::format("object type '{}' is declared twice", o.name.text));
                d.notes.push_back({it->second.second->name.span, "first declared here"});
            }
        }
}

bool Elaborator::is_object_type(const std::string& name) const { return types_.count(name) > 0; }

const ast::ObjectDecl* Elaborator::object_type(const std::string& name) const {
    auto it = types_.find(name);
    return it == types_.end() ? nullptr : it->second.second;
}

void Elaborator::record_names(Names* names, bool survey, std::set<const ast::ObjectDecl*>* surveyed) {
    names_ = names;
    survey_ = survey;
    surveyed_ = surveyed;
    ev_.record_names(names);
    if (names)
        for (const auto& [type_name, type] : types_) names->declare(type.second->name.span);
}

graph::Src Elaborator::src(Span s) {
    if (!s.valid()) return {};
    auto& idx = graph_file_of_[s.file];
    if (idx < 0) {
        idx = graph::count_of(g_.files);
        g_.files.push_back(sm_.name(s.file));
    }
    auto lc = sm_.line_col(s.file, s.begin);
    return {idx, static_cast<int32_t>(lc.line), static_cast<int32_t>(lc.col)};
}

// A plant (or a library's type) whose size is known from its source alone and passes the
// limit is refused at once, at the member that passes it, before anything is built: nested
// instances multiply (40 levels of two instances each are 2^40 members), and building up to
// the limit took seconds and gigabytes.
bool Elaborator::too_large(const ast::ObjectDecl& o) {
    SizeEstimate sizes([&](const std::string& n) -> const ast::ObjectDecl* {
        auto it = types_.find(n);
        return it == types_.end() ? nullptr : it->second.second;
    });
    const double limit = double(max_expanded_);
    const auto whole = sizes.of(o);
    if (!whole || (whole->members <= limit && whole->iterations <= limit)) return false;
    StaticSize sum;  // up to the member that passes the limit
    for (const auto& m : o.members) {
        const auto size = sizes.of(std::span<const ast::Member>(&m, 1));
        if (!size) return false;
        sum.members += size->members;
        sum.iterations += size->iterations;
        if (sum.members <= limit && sum.iterations <= limit) continue;
        auto& d = sink_.report(
            DiagId::LoopTooLarge, std::visit([](const auto& x) { return span_of(x); }, m),
            whole->members > limit
                ? fmt::format("the plant expands to {:.0f} members, more than {}: nested instances and loops "
                              "multiply (this member is {:.0f} of them)",
                              whole->members, max_expanded_, size->members)
                : fmt::format("loops run {:.0f} iterations in all, more than {} (nested loops multiply)",
                              whole->iterations, max_expanded_));
        d.notes.push_back({o.name.span, "known from the source alone, so nothing was built"});
        return true;
    }
    return false;
}

void Elaborator::check_object(const ast::ObjectDecl& o, int module) {
    if (!survey_ && too_large(o)) return;  // a survey runs each loop once
    g_.plant = name(o.name.text);
    library_mode_ = true;
    const graph::DoId root_do = new_do("", graph::DoId{}, do_type(o.name.text, o.name.span), Frame{}, o.name.span);
    type_stack_.push_back(o.name.text);
    elaborate_do(root_do, o, module < 0 ? prog_.root : module, bind_args(o, {}, o.name.span, Env{}));
    finish_accesses();
    if (survey_) return;  // the names are all resolved
    check_plugins();
    if (!sink_.has_errors()) check_petri_nets();  // a net or flow in error would mislead the analysis
    check_logic_cycles();
    check_ranges();
    check_static_velocities();
    if (!sink_.has_errors()) check_conveyor_ends();  // a box in error would mislead it
}

graph::Graph Elaborator::run(bool require_plant) {
    if (prog_.root < 0) return std::move(g_);
    const auto& root = *prog_.modules[prog_.root].ast;
    const ast::ObjectDecl* plant = nullptr;
    for (const auto& o : root.objects) {
        if (!o.is_plant) continue;
        if (plant) {
            auto& d = sink_.report(DiagId::MultiplePlants, o.name.span,
                                   fmt::format("a file holds one plant, but '{}' is a second one", o.name.text));
            d.notes.push_back({plant->name.span, "first plant declared here"});
            continue;
        }
        plant = &o;
    }
    // Plants in imported modules are ignored: a module can be both a plant and a library.
    if (!plant) {
        for (const auto& a : prog_.overrides)
            sink_.report(DiagId::UnknownArgument, a.name ? a.name->span : a.span,
                         fmt::format("this file declares no plant, so there is nothing for --set '{}' to set",
                                     a.name ? a.name->text : ""));
        if (require_plant || root.objects.empty()) {
            if (!sink_.has_errors())
                sink_.report(DiagId::NoPlant, Span{root.file, 0, 0},
                             root.objects.empty() ? "this file declares nothing; add `plant NAME { ... }`"
                                                  : "no plant declared in this file; add `plant NAME { ... }`");
            return std::move(g_);
        }
        // A library: check every object type that can be built from its defaults alone.
        for (const auto& o : root.objects) {
            bool defaults = std::all_of(o.params.begin(), o.params.end(), [](const ast::Param& p) { return p.default_value != nullptr; });
            if (!defaults) continue;
            Elaborator one(prog_, sm_, sink_);
            one.max_expanded_ = max_expanded_;
            one.check_object(o);
        }
        return std::move(g_);
    }
    if (too_large(*plant)) return std::move(g_);
    g_.plant = name(plant->name.text);
    const graph::DoId root_do = new_do("", graph::DoId{}, graph::DoTypeId{}, Frame{}, plant->name.span);
    // The plant's parameters take their values from `--set NAME=VALUE`, else their defaults.
    elaborate_do(root_do, *plant, prog_.root, bind_args(*plant, prog_.overrides, plant->name.span, Env{}));
    finish_accesses();
    emit_ports();
    check_plugins();
    // The whole-plant warnings assume every flow was made: after an error, a failed flow
    // would show up as an input nothing drives or a place nothing feeds.
    if (!sink_.has_errors()) {
        check_petri_nets();
        check_unused();
    }
    check_logic_cycles();
    check_ranges();
    check_static_velocities();
    if (!sink_.has_errors()) check_conveyor_ends();  // a box in error would mislead it
    return std::move(g_);
}

// Every declared port, by object and name, for events and tools that address them.
void Elaborator::emit_ports() {
    for (graph::DoId d : scopes_.ids()) {
        if (!g_.dos.contains(d)) break;
        for (const auto& [port_name, info] : scopes_[d].ports) {
            if (info.slots.empty()) continue;
            graph::Port p;
            p.owner = d;
            p.name = name(port_name);
            p.type = info.type;
            p.dir = info.input ? graph::Dir::In : graph::Dir::Out;
            p.target_adr = graph::next_adr(g_.port_targets);
            p.target_num = graph::count_of(info.slots);
            p.src = src(info.span);
            for (graph::SlotId sl : info.slots) g_.port_targets.push_back({sl});
            g_.ports.push_back(p);
        }
    }
}

graph::DoId Elaborator::new_do(const std::string& path, graph::DoId parent, graph::DoTypeId type, const Frame& f,
                               Span s) {
    Scope sc;
    sc.do_id = graph::add_do(g_, path, parent, type, f.pose(), src(s));
    do_spans_.resize(g_.dos.size());
    do_spans_[sc.do_id] = s;
    sc.frame = f;
    scopes_.push_back(std::move(sc));
    return scopes_.back().do_id;
}

graph::DoTypeId Elaborator::do_type(const std::string& type_name, Span s) {
    if (auto it = do_types_.find(type_name); it != do_types_.end()) return it->second;
    graph::DoType t;
    t.name = name(type_name);
    // The type's declaration, wherever the first use (a filter, a cast, a source) is.
    if (auto it = types_.find(type_name); it != types_.end()) s = it->second.second->name.span;
    t.src = src(s);
    const graph::DoTypeId id = g_.do_types.push_back(t);
    do_types_[type_name] = id;
    return id;
}

const ast::ObjectDecl* Elaborator::find_type(const std::string& type_name, int module, Span use, int* type_module) {
    auto it = types_.find(type_name);
    // Visible: types of this module and of the modules it imports directly.
    bool visible = false;
    if (it != types_.end()) {
        int m = it->second.first;
        visible = m == module;
        for (int imp : prog_.modules[module].imports) visible = visible || imp == m;
    }
    if (it == types_.end() || !visible) {
        std::vector<std::string> candidates;
        for (const auto& [n, t] : types_) candidates.push_back(n);
        auto& d = sink_.report(DiagId::UnknownType, use, fmt::format("unknown object type '{}'", type_name));
        if (it != types_.end())
            d.notes.push_back({it->second.second->name.span,
                               "declared in a module this file does not import; add an import"});
        else if (const std::string std_module = stdlib_module_declaring(prog_.stdlib_dir, type_name); !std_module.empty())
            d.notes.push_back({{}, fmt::format("'{}' is declared in {}: add `import {}`", type_name, std_module, std_module)});
        else if (auto hint = closest_name(type_name, candidates); !hint.empty())
            d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
        return nullptr;
    }
    if (type_module) *type_module = it->second.first;
    return it->second.second;
}

// One more level of objects (an instance, or a source's pooled object) would nest deeper
// than kMaxDepth: reported at `at`. The elaboration recurses once per level.
bool Elaborator::nested_too_deep(Span at) {
    if (std::cmp_less(type_stack_.size(), kMaxDepth)) return false;
    sink_.report(DiagId::LoopTooLarge, at,
                 fmt::format("objects nest more than {} deep (an instance inside an instance inside ...)", kMaxDepth));
    return true;
}

bool Elaborator::declare(Scope& s, const std::string& n, Span span) {
    auto [it, fresh] = s.declared.try_emplace(n, span);
    if (fresh) return true;
    auto& d = sink_.report(DiagId::DuplicateName, span, fmt::format("'{}' is declared twice", n));
    d.notes.push_back({it->second, "first declared here"});
    return false;
}

// Members alone do not bound the work: nested loops with empty bodies produce none.
bool Elaborator::iterate(Span at) {
    if (expanded_ > max_expanded_) return false;  // the members' limit stopped it: reported once
    if (++iterations_ <= max_expanded_) return true;
    if (iterations_ == max_expanded_ + 1)
        sink_.report(DiagId::LoopTooLarge, at,
                     fmt::format("loops run more than {} iterations in all (nested loops multiply)", max_expanded_));
    return false;
}

void Elaborator::expand(const std::vector<ast::Member>& members, std::shared_ptr<const Env> env,
                        std::vector<Item>& out, int depth) {
    for (const auto& m : members) {
        if (++expanded_ > max_expanded_) {
            if (expanded_ == max_expanded_ + 1 && iterations_ <= max_expanded_)
                sink_.report(DiagId::LoopTooLarge, std::visit([](const auto& x) { return span_of(x); }, m),
                             fmt::format("the plant expands to more than {} members", max_expanded_));
            return;
        }
        if (depth >= kMaxDepth && (std::holds_alternative<std::unique_ptr<ast::ForDecl>>(m) ||
                                   std::holds_alternative<std::unique_ptr<ast::IfDecl>>(m))) {
            sink_.report(DiagId::LoopTooLarge, std::visit([](const auto& x) { return span_of(x); }, m),
                         fmt::format("loops and conditions nest more than {} deep", kMaxDepth));
            continue;
        }
        if (auto* let = std::get_if<ast::LetDecl>(&m)) {
            Value v = ev_.eval(*let->value, *env);
            auto next = std::make_shared<Env>(env);
            next->set(let->name.text, v, let->name.span);
            name_declared(let->name.span);
            env = next;
        } else if (auto* fp = std::get_if<std::unique_ptr<ast::ForDecl>>(&m)) {
            const ast::ForDecl& f = **fp;
            name_declared(f.var.span);
            if (survey_) {  // one pass, the variable at its first value (or valueless)
                Value first = ev_.eval(*f.from, *env);
                if (f.to) ev_.eval(*f.to, *env);
                if (!f.to) first = first.kind == Value::Kind::List && !first.items.empty() ? first.items[0] : Value{};
                auto inner = std::make_shared<Env>(env);
                inner->set(f.var.text, first, f.var.span);
                expand(f.body, inner, out, depth + 1);
                continue;
            }
            if (!f.to) {  // for x in LIST
                Value list = ev_.eval(*f.from, *env);
                if (list.kind == Value::Kind::None) continue;
                if (list.kind != Value::Kind::List) {
                    sink_.report(DiagId::ValueTypeMismatch, f.from->span,
                                 fmt::format("'for {} in' takes a list [...] or a range A .. B, not {}", f.var.text,
                                             with_article(describe(list))));
                    continue;
                }
                for (const Value& item : list.items) {
                    if (!iterate(f.span)) break;
                    auto inner = std::make_shared<Env>(env);
                    inner->set(f.var.text, item, f.var.span);
                    expand(f.body, inner, out, depth + 1);
                }
                continue;
            }
            Value from = ev_.eval(*f.from, *env);
            Value to = ev_.eval(*f.to, *env);
            if (!ev_.expect_int(from, "loop start") || !ev_.expect_int(to, "loop end")) continue;
            if (to.num - from.num > static_cast<double>(max_expanded_)) {
                sink_.report(DiagId::LoopTooLarge, f.span,
                             fmt::format("loop of {} iterations; the limit is {}", to.num - from.num, max_expanded_));
                continue;
            }
            for (long long i = static_cast<long long>(from.num); i < static_cast<long long>(to.num); ++i) {
                if (!iterate(f.span)) break;
                auto inner = std::make_shared<Env>(env);
                Value iv = Value::number(static_cast<double>(i), {}, f.var.span);
                iv.integer = true;
                inner->set(f.var.text, iv, f.var.span);
                expand(f.body, inner, out, depth + 1);
            }
        } else if (auto* ip = std::get_if<std::unique_ptr<ast::IfDecl>>(&m)) {
            const ast::IfDecl& c = **ip;
            Value cond = ev_.eval(*c.cond, *env);
            if (survey_) {
                expand(c.then_body, env, out, depth + 1);
                expand(c.else_body, env, out, depth + 1);
                continue;
            }
            if (!ev_.expect_bool(cond, "condition")) continue;
            expand(cond.boolean ? c.then_body : c.else_body, env, out, depth + 1);
        } else {
            out.push_back(Item{&m, env});
        }
    }
}

bool Elaborator::rotate(Eigen::Quaterniond& q, const ast::Rotation& r, const Env& env, double share, double* angle_out) {
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
    if (r.axis_name) {
        const auto& a = r.axis_name->text;
        if (a == "x") axis = Eigen::Vector3d::UnitX();
        else if (a == "y") axis = Eigen::Vector3d::UnitY();
        else if (a != "z") {
            sink_.report(DiagId::UnknownName, r.axis_name->span,
                         fmt::format("unknown axis '{}'; write x, y, z or a vector (x, y, z)", a));
            return false;
        }
    } else if (r.axis_vec) {
        Value v = ev_.eval(*r.axis_vec, env);
        if (!ev_.expect_vec3(v, {}, "rotation axis")) return false;
        axis = Eigen::Vector3d(v.items[0].num, v.items[1].num, v.items[2].num);
        if (axis.norm() < 1e-12) {
            sink_.report(DiagId::ZeroVector, r.axis_vec->span, "rotation axis is the zero vector");
            return false;
        }
        axis.normalize();
    }
    Value angle = ev_.eval(*r.angle, env);
    if (!ev_.expect_number(angle, units::dims::angle, "rotation angle")) return false;
    if (angle_out) *angle_out = angle.num;
    q = (q * Eigen::Quaterniond(Eigen::AngleAxisd(angle.num * share, axis))).normalized();
    return true;
}

Frame Elaborator::placement(const ast::Placement* p, const Env& env) {
    Frame f;
    if (!p) return f;
    if (p->at) {
        Value at = ev_.eval(*p->at, env);
        if (ev_.expect_vec3(at, units::dims::length, "position"))
            f.p = Eigen::Vector3d(at.items[0].num, at.items[1].num, at.items[2].num);
    }
    // Rotations are intrinsic: each turns about the axes left by the previous ones.
    for (const auto& r : p->rotations) rotate(f.q, r, env);
    return f;
}

std::shared_ptr<const Env> Elaborator::bind_args(const ast::ObjectDecl& decl, const std::vector<ast::Arg>& args,
                                                 Span call_span, const Env& caller_env) {
    auto env = std::make_shared<Env>();
    std::vector<const ast::Arg*> given(decl.params.size(), nullptr);
    size_t positional = 0;
    for (const auto& a : args) {
        size_t idx = decl.params.size();
        if (a.name) {
            for (size_t i = 0; i < decl.params.size(); ++i)
                if (decl.params[i].name.text == a.name->text) idx = i;
            if (idx < decl.params.size()) name_use(a.name->span, decl.params[idx].name.span);
            if (idx == decl.params.size()) {
                std::vector<std::string> names;
                for (const auto& p : decl.params) names.push_back(p.name.text);
                auto& d = sink_.report(DiagId::UnknownArgument, a.name->span,
                                       fmt::format("'{}' has no parameter '{}'", decl.name.text, a.name->text));
                if (auto hint = closest_name(a.name->text, names); !hint.empty())
                    d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
                d.notes.push_back({decl.name.span, fmt::format("'{}' declared here", decl.name.text)});
                continue;
            }
        } else {
            idx = positional++;
            if (idx >= decl.params.size()) {
                auto& d = sink_.report(DiagId::ExtraArgument, a.span,
                                       fmt::format("'{}' takes {} parameter{}; this argument is extra", decl.name.text,
                                                   decl.params.size(), decl.params.size() == 1 ? "" : "s"));
                d.notes.push_back({decl.name.span, fmt::format("'{}' declared here", decl.name.text)});
                continue;
            }
        }
        if (given[idx]) {
            sink_.report(DiagId::DuplicateProperty, a.span,
                         fmt::format("parameter '{}' is given twice", decl.params[idx].name.text));
            continue;
        }
        given[idx] = &a;
    }
    for (size_t i = 0; i < decl.params.size(); ++i) {
        const auto& p = decl.params[i];
        Value v;
        if (given[i] && decl.is_plant) {
            // A --set value is a constant: it sees no parameter of the plant.
            if (const ast::Expr* use = uses_param(*given[i]->value, decl)) {
                sink_.report(DiagId::UnknownName, use->span,
                             fmt::format("a --set value is a constant and cannot use the parameter '{}'", use->text));
                env->set(p.name.text, Value{}, p.name.span);
                continue;
            }
            v = ev_.eval(*given[i]->value, caller_env);
        } else if (given[i]) {
            v = ev_.eval(*given[i]->value, caller_env);
            if (survey_ && p.default_value) ev_.eval(*p.default_value, *env);  // for the names in it
        } else if (p.default_value) {
            v = ev_.eval(*p.default_value, *env);  // defaults may use earlier parameters
        } else {
            auto& d = sink_.report(DiagId::MissingArgument, call_span,
                                   fmt::format("missing argument '{}: {}' of '{}'", p.name.text, p.type.text,
                                               decl.name.text));
            d.notes.push_back({p.span, "parameter declared here without a default"});
            if (decl.is_plant)
                d.notes.push_back({{}, fmt::format("give it on the command line: --set {}=VALUE", p.name.text)});
            env->set(p.name.text, Value{}, p.name.span);  // known but valueless: its uses report nothing more
            continue;
        }
        // Check the value against the parameter's type.
        const std::string& t = p.type.text;
        std::string what = fmt::format("argument '{}'", p.name.text);
        bool ok = true;
        if (auto dim = units::dim_of_type(t)) ok = ev_.expect_number(v, *dim, what);
        else if (t == "int") ok = ev_.expect_int(v, what);
        else if (t == "bool") ok = ev_.expect_bool(v, what);
        else if (t == "string") ok = ev_.expect_string(v, what);
        else if (t == "position") ok = ev_.expect_vec3(v, units::dims::length, what);
        else if (t == "vector") ok = ev_.expect_vec3(v, {}, what);
        else if (t == "object") {
            ok = v.kind == Value::Kind::Type;
            if (!ok && v.kind != Value::Kind::None)
                sink_.report(DiagId::ValueTypeMismatch, v.span,
                             fmt::format("{} must be an object type such as Bottle(...), not {}", what, with_article(describe(v))));
        } else if (t == "list") {
            ok = v.kind == Value::Kind::List;
            if (!ok && v.kind != Value::Kind::None)
                sink_.report(DiagId::ValueTypeMismatch, v.span, fmt::format("{} must be a list [...]", what));
        } else {
            std::vector<std::string> known = units::dimension_type_names();
            for (const char* k : {"int", "bool", "string", "position", "vector", "object", "list"}) known.push_back(k);
            auto& d = sink_.report(DiagId::UnknownType, p.type.span, fmt::format("unknown parameter type '{}'", t));
            if (auto hint = closest_name(t, known); !hint.empty())
                d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
            ok = false;
        }
        if (ok && v.kind == Value::Kind::Num && units::dim_of_type(t)) v.any_dim = false, v.dim = *units::dim_of_type(t);
        if (ok) env->set(p.name.text, v, p.name.span);
        else env->set(p.name.text, Value{}, p.name.span);
    }
    // Constraints, with every parameter bound: `lines: int = 1 where lines >= 1`.
    for (size_t i = 0; i < decl.params.size(); ++i) {
        const auto& p = decl.params[i];
        if (!p.constraint) continue;
        const Value* mine = env->find(p.name.text);
        if (!mine || mine->kind == Value::Kind::None) {  // reported already
            if (survey_) ev_.eval(*p.constraint, *env);     // for the names in it
            continue;
        }
        Value c = ev_.eval(*p.constraint, *env);
        if (c.kind == Value::Kind::None) continue;
        if (!ev_.expect_bool(c, fmt::format("the constraint of '{}'", p.name.text))) continue;
        if (c.boolean) continue;
        const Span at = given[i] ? given[i]->value->span : call_span;
        const Span& cs = p.constraint->span;
        const std::string cond(std::string_view(sm_.text(cs.file)).substr(cs.begin, cs.end - cs.begin));
        auto& d = sink_.report(DiagId::ConstraintFails, at,
                               fmt::format("'{}' of '{}' must satisfy '{}'{}", p.name.text, decl.name.text, cond,
                                           given[i] ? "" : " (its default does not)"));
        d.notes.push_back({cs, fmt::format("the constraint of '{}'", p.name.text)});
        env->set(p.name.text, Value{}, p.name.span);  // known but valueless: its uses report nothing more
    }
    return env;
}

void Elaborator::elaborate_do(graph::DoId do_id, const ast::ObjectDecl& decl, int module, std::shared_ptr<const Env> env) {
    if (surveyed_) surveyed_->insert(&decl);
    scopes_[do_id].decl = &decl;
    scopes_[do_id].module = module;
    for (const auto& p : decl.params) {
        declare(scopes_[do_id], p.name.text, p.name.span);
        name_declared(p.name.span);
    }

    std::vector<Item> items;
    expand(decl.members, env, items, 0);

    // Components first, so that one DO's components (and their slots) are contiguous
    // (graph::add_comp keeps the DO's range).
    std::vector<std::pair<graph::CompId, const Item*>> made;
    std::map<std::string, Span, std::less<>> settings_seen;  // each setting once: no silent "last wins"
    for (const auto& it : items) {
        Scope& s = scopes_[do_id];
        if (auto* c = std::get_if<ast::ComponentDecl>(it.member)) {
            const graph::CompId comp = make_component(s, *c, *it.env, {}, "");
            if (comp.valid()) made.emplace_back(comp, &it);
        } else if (auto* l = std::get_if<ast::LogicDecl>(it.member)) {
            make_logic(s, *l);
        } else if (auto* p = std::get_if<ast::PortDecl>(it.member)) {
            declare(s, p->name.text, p->name.span);
            name_declared(p->name.span);
        } else if (auto* st = std::get_if<ast::SettingDecl>(it.member)) {
            if (!decl.is_plant) {
                sink_.report(DiagId::UnknownProperty, st->name.span,
                             fmt::format("'{}' = ... is a plant setting; only a plant can set it", st->name.text));
                continue;
            }
            if (auto [at, fresh] = settings_seen.emplace(st->name.text, st->name.span); !fresh) {
                auto& d = sink_.report(DiagId::DuplicateProperty, st->name.span,
                                       fmt::format("plant setting '{}' is set twice", st->name.text));
                d.notes.push_back({at->second, "first set here"});
                continue;
            }
            Value v = ev_.eval(*st->value, *it.env);
            if (st->name.text == "rate") {
                if (ev_.expect_number(v, units::dims::frequency, "rate")) {
                    if (v.num <= 0) sink_.report(DiagId::NonPositive, v.span, "the step rate must be positive");
                    else if (v.num < graph::kMinRate || v.num > graph::kMaxRate)
                        sink_.report(DiagId::OutOfRange, v.span,
                                     fmt::format("the step rate must lie between 1 Hz and 1 MHz, not {:g} Hz", v.num));
                    else g_.settings.rate = v.num;
                }
            } else if (st->name.text == "gravity") {
                if (ev_.expect_vec3(v, units::dims::acceleration, "gravity")) {
                    const graph::Vec3 grav{v.items[0].num, v.items[1].num, v.items[2].num};
                    if (graph::gravity_in_range(grav.data())) g_.settings.gravity = grav;
                    else
                        sink_.report(DiagId::OutOfRange, v.span,
                                     fmt::format("gravity must lie within 1 km/s² along each axis, not ({:g}, {:g}, {:g}) m/s²",
                                                 grav[0], grav[1], grav[2]));
                }
            } else if (st->name.text == "steady_transport") {
                if (ev_.expect_bool(v, "steady_transport")) g_.settings.steady_transport = v.boolean;
            } else {
                auto& d = sink_.report(DiagId::UnknownProperty, st->name.span,
                                       fmt::format("unknown plant setting '{}'", st->name.text));
                if (auto hint = closest_name(st->name.text, {"rate", "gravity", "steady_transport"}); !hint.empty())
                    d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
            }
        }
    }
    for (auto [comp, it] : made)
        link_component(scopes_[do_id], comp, std::get<ast::ComponentDecl>(*it->member), *it->env);

    // Child instances, then pooled objects of this DO's sources.
    for (const auto& it : items) {
        auto* inst = std::get_if<ast::InstanceDecl>(it.member);
        if (!inst) continue;
        std::string iname = inst->name.text;
        name_declared(inst->name.span);
        if (inst->index) {
            Value idx = ev_.eval(*inst->index, *it.env);
            if (survey_ && idx.kind == Value::Kind::None) iname += "[?]";  // a valueless loop's
            else if (!ev_.expect_int(idx, "instance index")) continue;
            else iname += fmt::format("[{}]", static_cast<long long>(idx.num));
        }
        if (!declare(scopes_[do_id], iname, inst->name.span)) {
            if (const ast::ObjectDecl* t = survey_ ? object_type(inst->type.text) : nullptr) {  // for its names
                name_use(inst->type.span, t->name.span);
                bind_args(*t, inst->args, inst->type.span, *it.env);
                placement(inst->placement ? &*inst->placement : nullptr, *it.env);
            }
            continue;
        }
        int type_module = -1;
        const ast::ObjectDecl* type = find_type(inst->type.text, module, inst->type.span, &type_module);
        if (type) name_use(inst->type.span, type->name.span);
        if (!type) {
            // Reported once, here: uses of the instance are not errors of their own.
            scopes_[do_id].broken.insert(inst->name.text);
            continue;
        }
        if (nested_too_deep(inst->type.span)) continue;
        if (std::find(type_stack_.begin(), type_stack_.end(), type->name.text) != type_stack_.end()) {
            auto& d = sink_.report(DiagId::RecursiveObject, inst->type.span,
                                   fmt::format("'{}' contains itself", type->name.text));
            d.notes.push_back({type->name.span, "declared here"});
            continue;
        }
        auto child_env = bind_args(*type, inst->args, inst->args.empty() ? inst->type.span : inst->args_span,
                                   *it.env);
        Frame f = scopes_[do_id].frame *
                  placement(inst->placement ? &*inst->placement : nullptr, *it.env);
        const std::string parent_path(g_.str(g_.dos[do_id].path));
        std::string path = parent_path.empty() ? iname : parent_path + "." + iname;
        const graph::DoId child = new_do(path, do_id, do_type(type->name.text, type->name.span), f, inst->span);
        if (inst->placement && inst->placement->at) do_at_spans_[child] = inst->placement->at->span;
        scopes_[do_id].children[iname] = child;
        type_stack_.push_back(type->name.text);
        elaborate_do(child, *type, type_module, child_env);
        type_stack_.pop_back();
    }
    make_pools(do_id, items);

    // Connections: ports, connector inputs, flows, records.
    for (const auto& it : items) {
        Scope& s = scopes_[do_id];
        if (auto* p = std::get_if<ast::PortDecl>(it.member)) bind_port(s, *p, *it.env);
    }
    for (const auto& it : items) {
        Scope& s = scopes_[do_id];
        if (auto* l = std::get_if<ast::LogicDecl>(it.member)) connect_logic(s, *l, *it.env);
        else if (auto* f = std::get_if<ast::FlowDecl>(it.member)) add_flow(*f, *it.env, do_id);
        else if (auto* r = std::get_if<ast::RecordDecl>(it.member)) add_record(s, *r, *it.env);
    }
    for (auto [comp, it] : made) add_entries(comp, std::get<ast::ComponentDecl>(*it->member), *it->env, do_id);
}

// Pooled objects of a source: built now, contiguous DO ids, outside the world until issued.
void Elaborator::make_pools(graph::DoId do_id, const std::vector<Item>& items) {
    for (const auto& it : items) {
        auto* c = std::get_if<ast::ComponentDecl>(it.member);
        if (!c || c->kind.text != "source") continue;
        auto found = scopes_[do_id].comps.find(c->name.text);
        if (found == scopes_[do_id].comps.end()) continue;
        const graph::CompId comp = found->second;
        auto& src_rec = g_.sources[graph::detail_of<graph::Source>(g_.comps[comp])];
        const ast::Property* obj = nullptr;
        for (const auto& p : c->properties)
            if (p.name.text == "object") obj = &p;
        if (!obj || !src_rec.do_type.valid() || src_rec.pool_num <= 0) continue;
        Value v = ev_.eval(*obj->value, *it.env);
        if (v.kind != Value::Kind::Type) continue;
        int type_module = -1;
        const ast::ObjectDecl* type = find_type(v.str, scopes_[do_id].module, v.span, &type_module);
        if (!type) continue;
        if (nested_too_deep(v.span)) continue;
        if (std::find(type_stack_.begin(), type_stack_.end(), type->name.text) != type_stack_.end()) {
            sink_.report(DiagId::RecursiveObject, v.span, fmt::format("'{}' issues itself", type->name.text));
            continue;
        }
        static const std::vector<ast::Arg> no_args;
        const auto& args = v.call && v.call->kind == ast::ExprKind::Call ? v.call->args : no_args;
        auto env = bind_args(*type, args, v.span, *it.env);
        Frame at;
        const auto& sp = src_rec.pose;
        at.p = Eigen::Vector3d(sp.p[0], sp.p[1], sp.p[2]);
        at.q = Eigen::Quaterniond(sp.q[3], sp.q[0], sp.q[1], sp.q[2]);
        const int32_t n = survey_ ? std::min(src_rec.pool_num, 1) : src_rec.pool_num;  // one reads the names
        const graph::DoTypeId tid = src_rec.do_type;
        const std::string parent_path(g_.str(g_.dos[do_id].path));
        std::vector<graph::DoId> made;
        const graph::Adr<graph::Do> pool_adr = graph::next_adr(g_.dos);  // the rows made next
        for (int32_t i = 0; i < n; ++i) {
            std::string iname = fmt::format("{}[{}]", c->name.text, i);
            std::string path = parent_path.empty() ? iname : parent_path + "." + iname;
            const graph::DoId d = new_do(path, do_id, tid, at, c->name.span);
            g_.dos[d].pool = comp;
            scopes_[do_id].children[iname] = d;
            made.push_back(d);
        }
        g_.sources[graph::detail_of<graph::Source>(g_.comps[comp])].pool_adr = pool_adr;
        type_stack_.push_back(type->name.text);
        for (graph::DoId d : made) elaborate_do(d, *type, type_module, env);
        type_stack_.pop_back();
    }
}

graph::Graph elaborate(const Program& prog, const SourceMap& sources, Sink& sink, bool require_plant,
                       long long max_members) {
    Elaborator e(prog, sources, sink);
    e.max_expanded_ = max_members;
    return e.run(require_plant);
}

}  // namespace plant::sema
