#include "sema/value.h"
#include "sema/names.h"

#include <cmath>
#include <fmt/format.h>

namespace plant::sema {

using units::Dim;

// A string built by '+' is at most this long (1 MiB): doubling one in a loop of lets
// would otherwise exhaust memory.
constexpr size_t kMaxString = size_t(1) << 20;
using units::dim_name;

std::string describe(const Value& v) {
    switch (v.kind) {
    case Value::Kind::None: return "nothing";
    case Value::Kind::Num:
        if (v.dim.none()) return v.integer ? "int" : "real";
        return dim_name(v.dim);
    case Value::Kind::Bool: return "bool";
    case Value::Kind::Str: return "string";
    case Value::Kind::Vec: {
        Dim d = v.items.empty() ? Dim{} : v.items[0].dim;
        return fmt::format("vec{} of {}", v.items.size(), d.none() ? "real" : dim_name(d));
    }
    case Value::Kind::List: return "list";
    case Value::Kind::Type: return "object type '" + v.str + "'";
    case Value::Kind::Name: return "name '" + v.str + "'";
    }
    return "?";
}

std::string with_article(std::string_view noun) {
    bool vowel = !noun.empty() && std::string_view("aeiou").find(noun.front()) != std::string_view::npos;
    return fmt::format("{} {}", vowel ? "an" : "a", noun);
}

const Value* Env::find(const std::string& name) const {
    for (const Env* e = this; e; e = e->parent_.get()) {
        auto it = e->vars_.find(name);
        if (it != e->vars_.end()) return &it->second;
    }
    return nullptr;
}

Span Env::declared(const std::string& name) const {
    for (const Env* e = this; e; e = e->parent_.get()) {
        if (!e->vars_.count(name)) continue;
        auto it = e->declared_.find(name);
        return it == e->declared_.end() ? Span{} : it->second;
    }
    return {};
}

std::string Env::closest(std::string_view wanted) const {
    ClosestName closest(wanted);
    for (const Env* e = this; e; e = e->parent_.get())
        for (const auto& [k, v] : e->vars_) closest.offer(k);
    return closest.best();
}

namespace {

bool dims_fit(const Value& a, const Value& b) { return a.dim == b.dim || a.any_dim || b.any_dim; }

Dim pick_dim(const Value& a, const Value& b) { return a.any_dim ? b.dim : a.dim; }

// A name that is no parameter, let or loop variable where a value is needed: a misspelt
// parameter, a unit written apart from its number (`50 cm / s`), or a slot, whose value
// exists only at run time. Reports it; false for every other value.
bool report_name(Sink& sink, const Value& v, std::string_view what) {
    if (v.kind != Value::Kind::Name) return false;
    if (v.str.find('.') != std::string::npos) {
        auto& d = sink.report(DiagId::NotAConstant, v.span,
                              fmt::format("'{}' is not known at compile time; {} needs a constant value", v.str, what));
        d.notes.push_back({{}, "a slot has a value only at run time; to pass it on, connect it with a flow"});
        return true;
    }
    auto& d = sink.report(DiagId::UnknownName, v.span,
                          fmt::format("unknown name '{}' (not a parameter, let or loop variable)", v.str));
    if ((what == "'/'" || what == "'*'") && units::parse_unit(v.str))
        d.notes.push_back({{}, fmt::format("'{}' is a unit: write it right after its number, e.g. 50 cm/s, not 50 cm / s", v.str)});
    else if (!v.hint.empty())
        d.notes.push_back({{}, fmt::format("did you mean '{}'?", v.hint)});
    return true;
}

}  // namespace

namespace {
bool all_finite(const Value& v) {
    if (v.kind == Value::Kind::Num) return std::isfinite(v.num);
    if (v.kind == Value::Kind::Vec)
        for (const Value& x : v.items)
            if (!all_finite(x)) return false;
    return true;
}
}  // namespace

Value Evaluator::eval(const ast::Expr& e, const Env& env) {
    Value v = eval_raw(e, env);
    if (all_finite(v)) return v;
    sink_.report(DiagId::ArithmeticError, e.span,
                 v.kind == Value::Kind::Vec || std::isinf(v.num) ? "this value is too large to be represented"
                                                                   : "this value is not a number (an undefined operation)");
    return {};
}

// A number literal with its unit, in SI units.
Value Evaluator::number(const ast::Expr& e) {
    if (!std::isfinite(e.number)) {
        sink_.report(DiagId::OutOfRange, e.span, "this number is too large");
        return {};
    }
    Value v = Value::number(e.number, {}, e.span);
    if (e.text.empty()) {
        v.integer = is_whole(e.number);
        v.any_dim = e.number == 0;
        return v;
    }
    std::string bad;
    bool bad_exponent = false;
    auto unit = units::parse_unit(e.text, &bad, &bad_exponent);
    if (!unit && bad_exponent) {
        sink_.report(DiagId::OutOfRange, e.unit_span,
                     fmt::format("the unit '{}' has an exponent beyond ±{}", bad, units::kMaxExponent));
        return {};
    }
    if (!unit) {
        auto& d = sink_.report(DiagId::UnknownUnit, e.unit_span, fmt::format("unknown unit '{}'", bad));
        std::string hint = closest_name(bad, units::unit_atoms());
        if (!hint.empty()) d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
        else d.notes.push_back({{}, fmt::format("units: {}", fmt::join(units::unit_atoms(), " "))});
        if (e.text.find_first_of("*/") != std::string::npos)
            d.notes.push_back({{}, "a unit follows its number directly; to divide by a parameter write (10 cm) / t"});
        return {};
    }
    v.num = unit->si(e.number);
    v.dim = unit->dim;
    if (!std::isfinite(v.num)) {
        sink_.report(DiagId::OutOfRange, e.span, "this number is too large in SI units");
        return {};
    }
    return v;
}

Value Evaluator::eval_raw(const ast::Expr& e, const Env& env) {
    using K = ast::ExprKind;
    switch (e.kind) {
    case K::Number: return number(e);
    case K::String: {
        Value v;
        v.kind = Value::Kind::Str;
        v.str = e.text;
        v.span = e.span;
        return v;
    }
    case K::Bool: {
        Value v;
        v.kind = Value::Kind::Bool;
        v.boolean = e.boolean;
        v.span = e.span;
        return v;
    }
    case K::Name: {
        if (names_) {
            const Span name{e.span.file, e.span.begin, e.span.begin + static_cast<uint32_t>(e.text.size())};
            if (env.find(e.text)) {
                if (const Span at = env.declared(e.text); at.valid()) names_->use(name, at);
            } else if (e.members.empty() && types_.is_object_type(e.text)) {
                names_->use(name, types_.object_type(e.text)->name.span);
            }
        }
        if (const Value* found = env.find(e.text); found && e.members.empty() && !e.index) {
            Value v = *found;
            v.span = e.span;
            return v;
        }
        // An item of a list: `codes[0]` (a whole index from 0, inside the list).
        if (const Value* found = env.find(e.text); found && found->kind == Value::Kind::List && e.index &&
                                                    e.members.empty()) {
            Value i = eval(*e.index, env);
            if (i.kind == Value::Kind::None || !expect_int(i, "a list index")) return {};
            if (i.num < 0 || i.num >= double(found->items.size())) {
                sink_.report(DiagId::OutOfRange, e.index->span,
                             fmt::format("index {} is outside the list '{}' of {} item{}", static_cast<long long>(i.num),
                                         e.text, found->items.size(), found->items.size() == 1 ? "" : "s"));
                return {};
            }
            Value v = found->items[size_t(i.num)];
            v.span = e.span;
            return v;
        }
        if (types_.is_object_type(e.text) && e.members.empty()) {
            Value v;
            v.kind = Value::Kind::Type;
            v.str = e.text;
            v.call = &e;
            v.span = e.span;
            return v;
        }
        // Otherwise a reference to a component, resolved by whoever asked for it.
        Value v;
        v.kind = Value::Kind::Name;
        v.str = e.text;
        if (e.members.empty()) v.hint = env.closest(e.text);
        for (const auto& m : e.members) v.str += "." + m.text;
        v.span = e.span;
        return v;
    }
    case K::Unary: {
        Value a = eval(*e.kids[0], env);
        if (a.kind == Value::Kind::None) return a;
        if (report_name(sink_, a, "the operand")) return {};
        if (e.text == "not") {
            if (!expect_bool(a, "operand of 'not'")) return {};
            a.boolean = !a.boolean;
            a.span = e.span;
            return a;
        }
        if (a.kind == Value::Kind::Num) {
            a.num = -a.num;
        } else if (a.kind == Value::Kind::Vec) {
            for (auto& it : a.items) it.num = -it.num;
        } else {
            sink_.report(DiagId::ValueTypeMismatch, e.span, fmt::format("cannot negate {}", with_article(describe(a))));
            return {};
        }
        a.span = e.span;
        return a;
    }
    case K::Binary: {
        Value a = eval(*e.kids[0], env);
        Value b = eval(*e.kids[1], env);
        if (a.kind == Value::Kind::None || b.kind == Value::Kind::None) return {};
        Value r = binary(e, a, b);
        r.span = e.span;
        return r;
    }
    case K::Tuple: {
        Value v;
        v.kind = Value::Kind::Vec;
        v.span = e.span;
        for (const auto& k : e.kids) {
            Value x = eval(*k, env);
            if (x.kind == Value::Kind::None) return {};
            if (report_name(sink_, x, "a vector component")) return {};
            if (x.kind != Value::Kind::Num) {
                sink_.report(DiagId::ValueTypeMismatch, k->span,
                             fmt::format("a vector holds numbers, not {}", with_article(describe(x))));
                return {};
            }
            v.items.push_back(x);
        }
        // All components share one dimension; a bare 0 takes the others' dimension. A number
        // without a unit among numbers with one is the component in error: `(1.5, 0 m, 0 m)`.
        for (const auto& x : v.items) {
            if (x.any_dim || !x.dim.none()) continue;
            for (const auto& y : v.items) {
                if (y.any_dim || y.dim.none()) continue;
                const std::string unit = y.dim == units::dims::angle ? "deg" : units::si_unit(y.dim);
                auto& diag = sink_.report(DiagId::DimensionMismatch, x.span,
                                          fmt::format("this vector component has no unit, but the others are in {} ({})",
                                                      unit, dim_name(y.dim)));
                diag.notes.push_back({{}, fmt::format("add a unit, e.g. `{:g} {}`", x.num, unit)});
                return {};
            }
        }
        Dim d{};
        bool have = false;
        for (const auto& x : v.items)
            if (!x.any_dim) {
                if (have && !(x.dim == d)) {
                    sink_.report(DiagId::DimensionMismatch, x.span,
                                 fmt::format("vector components differ: {} and {}", dim_name(d), dim_name(x.dim)));
                    return {};
                }
                d = x.dim;
                have = true;
            }
        for (auto& x : v.items) {
            if (x.any_dim) x.dim = d;
            x.any_dim = !have;
        }
        return v;
    }
    case K::List: {
        Value v;
        v.kind = Value::Kind::List;
        v.span = e.span;
        for (const auto& k : e.kids) {
            Value x = eval(*k, env);
            if (x.kind == Value::Kind::None) return {};
            v.items.push_back(x);
        }
        // One kind of item, and numbers of one dimension: [1 m, 2 m], ["A-*", "B-*"].
        const Value* first = nullptr;
        for (const Value& x : v.items) {
            if (x.kind == Value::Kind::Num && x.any_dim) continue;  // a bare 0 fits any dimension
            if (!first) {
                first = &x;
                continue;
            }
            if (x.kind != first->kind) {
                sink_.report(DiagId::ValueTypeMismatch, x.span,
                             fmt::format("a list holds items of one kind: this is {}, the first is {}",
                                         with_article(describe(x)), with_article(describe(*first))));
                return {};
            }
            if (x.kind == Value::Kind::Num && !(x.dim == first->dim)) {
                sink_.report(DiagId::DimensionMismatch, x.span,
                             fmt::format("list items differ: {} and {}", dim_name(first->dim), dim_name(x.dim)));
                return {};
            }
        }
        return v;
    }
    case K::Call: return call(e, env);
    }
    return {};
}

Value Evaluator::binary(const ast::Expr& e, const Value& a, const Value& b) {
    const std::string& op = e.text;
    using VK = Value::Kind;
    auto mismatch = [&](const Value& x, const Value& y) {
        sink_.report(DiagId::DimensionMismatch, e.span,
                     fmt::format("'{}' needs equal dimensions, but the left side is {} and the right side {}",
                                 op, with_article(describe(x)), with_article(describe(y))));
        return Value{};
    };
    auto exponent_overflow = [&] {
        sink_.report(DiagId::OutOfRange, e.span,
                     fmt::format("'{}' gives a dimension with an exponent beyond ±{}", op, units::kMaxExponent));
        return Value{};
    };
    if (report_name(sink_, a, fmt::format("'{}'", op)) || report_name(sink_, b, fmt::format("'{}'", op))) return {};
    if (op == "and" || op == "or") {
        if (!expect_bool(a, "left side of '" + op + "'") || !expect_bool(b, "right side of '" + op + "'")) return {};
        Value r = a;
        r.boolean = op == "and" ? (a.boolean && b.boolean) : (a.boolean || b.boolean);
        return r;
    }
    if (op == "==" || op == "!=") {
        Value r;
        r.kind = VK::Bool;
        if (a.kind == VK::Str && b.kind == VK::Str) r.boolean = a.str == b.str;
        else if (a.kind == VK::Bool && b.kind == VK::Bool) r.boolean = a.boolean == b.boolean;
        else if (a.kind == VK::Num && b.kind == VK::Num) {
            if (!dims_fit(a, b)) return mismatch(a, b);
            r.boolean = a.num == b.num;
        } else {
            sink_.report(DiagId::ValueTypeMismatch, e.span,
                         fmt::format("cannot compare {} with {}", with_article(describe(a)), with_article(describe(b))));
            return {};
        }
        if (op == "!=") r.boolean = !r.boolean;
        return r;
    }
    if (a.kind == VK::Str && b.kind == VK::Str && op == "+") {
        if (a.str.size() + b.str.size() > kMaxString) {
            sink_.report(DiagId::OutOfRange, e.span,
                         fmt::format("this string would be longer than {} bytes", kMaxString));
            return {};
        }
        Value r = a;
        r.str = a.str + b.str;
        return r;
    }
    if (a.kind == VK::Str && b.kind == VK::Num && op == "+") {  // "belt" + 3
        Value r = a;
        r.str = a.str + (b.integer ? std::to_string(static_cast<long long>(b.num)) : fmt::format("{}", b.num));
        return r;
    }
    if (a.kind == VK::Num && b.kind == VK::Num) {
        Value r = Value::number(0, {}, e.span);
        if (op == "+" || op == "-" || op == "%" || op == "<" || op == "<=" || op == ">" || op == ">=") {
            if (!dims_fit(a, b)) return mismatch(a, b);
            r.dim = pick_dim(a, b);
            r.integer = a.integer && b.integer;
            if (op == "+") r.num = a.num + b.num;
            else if (op == "-") r.num = a.num - b.num;
            else if (op == "%") {
                if (b.num == 0) {
                    sink_.report(DiagId::ArithmeticError, e.span, "remainder of a division by zero");
                    return {};
                }
                r.num = std::fmod(a.num, b.num);
            } else {
                r.kind = VK::Bool;
                r.boolean = op == "<" ? a.num < b.num : op == "<=" ? a.num <= b.num
                          : op == ">" ? a.num > b.num : a.num >= b.num;
            }
            r.integer = r.integer && is_whole(r.num);  // whole numbers stay exact in a double
            return r;
        }
        if (op == "*") {
            r.num = a.num * b.num;
            const std::optional<Dim> dim = a.dim.times(b.dim);
            if (!dim) return exponent_overflow();
            r.dim = *dim;
            r.integer = a.integer && b.integer && is_whole(r.num);
            return r;
        }
        if (op == "/") {
            if (b.num == 0) {
                sink_.report(DiagId::ArithmeticError, e.span, "division by zero");
                return {};
            }
            r.num = a.num / b.num;
            const std::optional<Dim> dim = a.dim.over(b.dim);
            if (!dim) return exponent_overflow();
            r.dim = *dim;
            r.integer = a.integer && b.integer && std::fmod(a.num, b.num) == 0;
            return r;
        }
    }
    // Vector arithmetic: v + v, v - v, s * v, v * s, v / s.
    if (a.kind == VK::Vec && b.kind == VK::Vec && (op == "+" || op == "-") && a.items.size() == b.items.size()) {
        Value r = a;
        for (size_t i = 0; i < a.items.size(); ++i) {
            Value x = binary(e, a.items[i], b.items[i]);
            if (x.kind == VK::None) return {};
            r.items[i] = x;
        }
        return r;
    }
    if ((op == "*" || op == "/") && a.kind == VK::Vec && b.kind == VK::Num) {
        Value r = a;
        for (auto& it : r.items) {
            Value x = binary(e, it, b);
            if (x.kind == VK::None) return {};
            it = x;
        }
        return r;
    }
    if (op == "*" && a.kind == VK::Num && b.kind == VK::Vec) return binary(e, b, a);
    sink_.report(DiagId::ValueTypeMismatch, e.span,
                 fmt::format("'{}' is not defined for {} and {}", op, with_article(describe(a)), with_article(describe(b))));
    return {};
}

Value Evaluator::call(const ast::Expr& e, const Env& env) {
    const std::string& f = e.text;
    if (types_.is_object_type(f)) {
        if (names_) {  // the type's name, its named arguments and the names in its arguments
            const ast::ObjectDecl& type = *types_.object_type(f);
            names_->use({e.span.file, e.span.begin, e.span.begin + static_cast<uint32_t>(f.size())}, type.name.span);
            for (const auto& a : e.args) {
                if (a.name)
                    for (const auto& p : type.params)
                        if (p.name.text == a.name->text) names_->use(a.name->span, p.name.span);
                if (a.value) eval(*a.value, env);
            }
        }
        Value v;
        v.kind = Value::Kind::Type;
        v.str = f;
        v.call = &e;
        v.span = e.span;
        return v;
    }
    if (f == "choose") {  // choose(condition, value if true, value if false)
        if (e.args.size() != 3) {
            sink_.report(e.args.size() < 3 ? DiagId::MissingArgument : DiagId::ExtraArgument, e.span,
                         fmt::format("'choose' takes 3 arguments, {} given", e.args.size()));
            return {};
        }
        Value c = eval(*e.args[0].value, env);
        if (!expect_bool(c, "first argument of 'choose'")) return {};
        Value r = eval(*e.args[c.boolean ? 1 : 2].value, env);
        r.span = e.span;
        return r;
    }
    std::vector<Value> a;
    for (const auto& arg : e.args) {
        if (arg.name) {
            sink_.report(DiagId::UnknownArgument, arg.name->span,
                         fmt::format("function '{}' takes no named arguments", f));
            return {};
        }
        a.push_back(eval(*arg.value, env));
        if (a.back().kind == Value::Kind::None) return {};
    }
    auto arity = [&](size_t n) {
        if (a.size() == n) return true;
        sink_.report(a.size() < n ? DiagId::MissingArgument : DiagId::ExtraArgument, e.span,
                     fmt::format("'{}' takes {} argument{}, {} given", f, n, n == 1 ? "" : "s", a.size()));
        return false;
    };
    auto num = [&](size_t i) { return a[i].kind == Value::Kind::Num; };
    auto need_nums = [&]() {
        for (size_t i = 0; i < a.size(); ++i)
            if (report_name(sink_, a[i], fmt::format("'{}'", f))) {
                return false;
            } else if (!num(i)) {
                sink_.report(DiagId::ValueTypeMismatch, a[i].span,
                             fmt::format("'{}' takes numbers, not {}", f, with_article(describe(a[i]))));
                return false;
            }
        return true;
    };
    using units::dims::angle;
    using units::dims::inertia;
    using units::dims::length;
    using units::dims::mass;
    if (f == "sqrt") {
        if (!arity(1) || !need_nums()) return {};
        Dim d = a[0].dim;
        if (d.L % 2 || d.M % 2 || d.T % 2 || d.A % 2) {
            sink_.report(DiagId::ArithmeticError, e.span, fmt::format("cannot take the square root of {}", with_article(describe(a[0]))));
            return {};
        }
        if (a[0].num < 0) {
            sink_.report(DiagId::ArithmeticError, e.span,
                         fmt::format("cannot take the square root of a negative value ({}{})", a[0].num,
                                     d.none() ? "" : " " + units::si_unit(d)));
            return {};
        }
        return Value::number(std::sqrt(a[0].num), Dim{int8_t(d.L / 2), int8_t(d.M / 2), int8_t(d.T / 2), int8_t(d.A / 2)}, e.span);
    }
    if (f == "abs") {
        if (!arity(1) || !need_nums()) return {};
        Value r = a[0];
        r.num = std::abs(r.num);
        return r;
    }
    if (f == "min" || f == "max") {
        if (a.size() < 2) return arity(2), Value{};
        if (!need_nums()) return {};
        Value r = a[0];
        for (size_t i = 1; i < a.size(); ++i) {
            if (!dims_fit(r, a[i])) {
                sink_.report(DiagId::DimensionMismatch, a[i].span,
                             fmt::format("'{}' needs equal dimensions: {} and {}", f, describe(r), describe(a[i])));
                return {};
            }
            if ((f == "min") == (a[i].num < r.num)) r = a[i];
        }
        r.span = e.span;
        return r;
    }
    if (f == "sin" || f == "cos" || f == "tan") {
        if (!arity(1) || !need_nums() || !expect_number(a[0], angle, "argument of " + f)) return {};
        double x = a[0].num;
        return Value::number(f == "sin" ? std::sin(x) : f == "cos" ? std::cos(x) : std::tan(x), {}, e.span);
    }
    // Inertia of homogeneous solids, principal moments about the centre (z is the axis).
    auto inertia_vec = [&](double ixx, double iyy, double izz) {
        Value v;
        v.kind = Value::Kind::Vec;
        v.span = e.span;
        for (double x : {ixx, iyy, izz}) v.items.push_back(Value::number(x, inertia, e.span));
        return v;
    };
    if (f == "solid_cylinder") {
        if (!arity(3) || !need_nums() || !expect_number(a[0], mass, "mass") ||
            !expect_number(a[1], length, "radius") || !expect_number(a[2], length, "height"))
            return {};
        double m = a[0].num, r = a[1].num, h = a[2].num;
        double side = m * (3 * r * r + h * h) / 12.0;
        return inertia_vec(side, side, m * r * r / 2.0);
    }
    if (f == "solid_box") {
        if (!arity(4) || !need_nums() || !expect_number(a[0], mass, "mass")) return {};
        for (int i = 1; i < 4; ++i)
            if (!expect_number(a[i], length, "extent")) return {};
        double m = a[0].num, x = a[1].num, y = a[2].num, z = a[3].num;
        return inertia_vec(m * (y * y + z * z) / 12, m * (x * x + z * z) / 12, m * (x * x + y * y) / 12);
    }
    if (f == "solid_sphere") {
        if (!arity(2) || !need_nums() || !expect_number(a[0], mass, "mass") || !expect_number(a[1], length, "radius"))
            return {};
        double i = 0.4 * a[0].num * a[1].num * a[1].num;
        return inertia_vec(i, i, i);
    }
    auto& d = sink_.report(DiagId::UnknownName, e.span, fmt::format("unknown function or object type '{}'", f));
    std::vector<std::string> known = {"sqrt", "abs", "min", "max", "sin", "cos", "tan", "choose",
                                      "solid_cylinder", "solid_box", "solid_sphere"};
    std::string hint = closest_name(f, known);
    if (!hint.empty()) d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
    return {};
}

bool Evaluator::expect_number(const Value& v, Dim dim, std::string_view what) {
    if (v.kind == Value::Kind::None || report_name(sink_, v, what)) return false;
    if (v.kind != Value::Kind::Num) {
        sink_.report(DiagId::ValueTypeMismatch, v.span,
                     fmt::format("{} must be {}, not {}", what, dim.none() ? "a number" : with_article(dim_name(dim)),
                                 with_article(describe(v))));
        return false;
    }
    if (!(v.dim == dim) && !v.any_dim) {
        auto& d = sink_.report(DiagId::DimensionMismatch, v.span,
                               fmt::format("{} must be {} (in {}), but this is {}", what, with_article(dim_name(dim)),
                                           units::si_unit(dim), v.dim.none() ? "a plain number" : with_article(dim_name(v.dim))));
        if (v.dim.none())
            d.notes.push_back({{}, fmt::format("a number without a unit has no dimension; write its unit, e.g. {} {}", v.num,
                                               dim == units::dims::angle ? "deg" : units::si_unit(dim))});
        return false;
    }
    return true;
}

bool Evaluator::expect_vec3(const Value& v, Dim dim, std::string_view what) {
    if (v.kind == Value::Kind::None || report_name(sink_, v, what)) return false;
    if (v.kind != Value::Kind::Vec || v.items.size() != 3) {
        sink_.report(DiagId::ValueTypeMismatch, v.span,
                     fmt::format("{} must be a vector (x, y, z) of {}, not {}", what,
                                 dim.none() ? "numbers" : dim_name(dim), with_article(describe(v))));
        return false;
    }
    for (const auto& it : v.items)
        if (!(it.dim == dim) && !it.any_dim) {
            sink_.report(DiagId::DimensionMismatch, v.span,
                         fmt::format("{} must be a vector of {}, but its components are {}", what,
                                     dim_name(dim), it.dim.none() ? "plain numbers" : with_article(dim_name(it.dim))));
            return false;
        }
    return true;
}

bool Evaluator::expect_int(const Value& v, std::string_view what) {
    if (v.kind == Value::Kind::None || report_name(sink_, v, what)) return false;
    if (v.kind != Value::Kind::Num || !v.dim.none() || std::floor(v.num) != v.num) {
        sink_.report(DiagId::ValueTypeMismatch, v.span, fmt::format("{} must be a whole number, not {}", what,
                                                                    with_article(v.kind == Value::Kind::Num && v.dim.none() ? "fraction" : describe(v))));
        return false;
    }
    // Loop bounds and indices become 64-bit integers (is_whole).
    if (!is_whole(v.num)) {
        sink_.report(DiagId::ValueTypeMismatch, v.span,
                     fmt::format("{} must be a whole number of at most 15 digits, not {}", what, v.num));
        return false;
    }
    return true;
}

bool Evaluator::expect_bool(const Value& v, std::string_view what) {
    if (v.kind == Value::Kind::None || report_name(sink_, v, what)) return false;
    if (v.kind != Value::Kind::Bool) {
        sink_.report(DiagId::ValueTypeMismatch, v.span, fmt::format("{} must be true or false, not {}", what, with_article(describe(v))));
        return false;
    }
    return true;
}

bool Evaluator::expect_string(const Value& v, std::string_view what) {
    if (v.kind == Value::Kind::None || report_name(sink_, v, what)) return false;
    if (v.kind != Value::Kind::Str) {
        sink_.report(DiagId::ValueTypeMismatch, v.span, fmt::format("{} must be a string, not {}", what, with_article(describe(v))));
        return false;
    }
    return true;
}

}  // namespace plant::sema
