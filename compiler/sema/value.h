// Compile-time values: what parameters, lets, loop variables and properties evaluate to.
#pragma once

#include "ast/ast.h"
#include "diag/diagnostic.h"
#include "units/units.h"

#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace plant::sema {

class Names;  // sema/names.h

struct Value {
    enum class Kind { None, Num, Bool, Str, Vec, List, Type, Name };
    Kind kind = Kind::None;
    double num = 0;
    units::Dim dim;
    bool integer = false;   // written without a fraction and no unit
    bool any_dim = false;   // the literal 0: fits every dimension
    bool boolean = false;
    std::string str;        // Str; Type: type name; Name: dotted name (a reference)
    std::vector<Value> items;      // Vec (numbers) and List
    const ast::Expr* call = nullptr;  // Type: the call `Bottle(mass = 20 g)`, or a bare name
    std::string hint;       // Name: the closest parameter, let or loop variable, for "did you mean"
    Span span;

    static Value number(double v, units::Dim d, Span s) {
        Value x;
        x.kind = Kind::Num;
        x.num = v;
        x.dim = d;
        x.span = s;
        return x;
    }
};

// A whole number a double holds exactly, and a loop counter or index can take: |v| < 9e15.
inline bool is_whole(double v) { return std::floor(v) == v && std::abs(v) < 9e15; }

std::string describe(const Value& v);  // "length", "bool", "string", "vec3 of length" ...
std::string with_article(std::string_view noun);  // "an int", "a length"

// Lexical scope chain: parameters, lets and loop variables.
class Env {
public:
    explicit Env(std::shared_ptr<const Env> parent = nullptr) : parent_(std::move(parent)) {}
    // `declared`: the name's declaration (a parameter's, a `let`'s, a loop variable's).
    void set(const std::string& name, Value v, Span declared = {}) {
        vars_[name] = std::move(v);
        if (declared.valid()) declared_[name] = declared;
    }
    const Value* find(const std::string& name) const;
    Span declared(const std::string& name) const;  // where the innermost `name` was declared
    // The closest name in scope to `wanted`, for "did you mean" (closest_name over every name,
    // this scope's first).
    std::string closest(std::string_view wanted) const;

private:
    std::shared_ptr<const Env> parent_;
    std::map<std::string, Value> vars_;
    std::map<std::string, Span> declared_;
};

class TypeLookup {
public:
    virtual ~TypeLookup() = default;
    virtual bool is_object_type(const std::string& name) const = 0;
    virtual const ast::ObjectDecl* object_type(const std::string& name) const = 0;  // null: none
};

class Evaluator {
public:
    Evaluator(Sink& sink, const TypeLookup& types) : sink_(sink), types_(types) {}
    // Evaluates; on error reports and returns a None value (no cascade of errors).
    // A number that overflows or is undefined (an infinity, a NaN) is reported where it
    // arises (E0212) and the value is None, so no plant gets a non-finite quantity.
    Value eval(const ast::Expr& e, const Env& env);

    // Checks helpers: report E0203/E0204 and return false on mismatch.
    bool expect_number(const Value& v, units::Dim dim, std::string_view what);
    bool expect_vec3(const Value& v, units::Dim dim, std::string_view what);
    bool expect_int(const Value& v, std::string_view what);
    bool expect_bool(const Value& v, std::string_view what);
    bool expect_string(const Value& v, std::string_view what);
    Sink& sink() { return sink_; }
    // The names met from now on are recorded in `names` (null: not recorded).
    void record_names(Names* names) { names_ = names; }

private:
    Value eval_raw(const ast::Expr& e, const Env& env);
    Value number(const ast::Expr& e);
    Value binary(const ast::Expr& e, const Value& a, const Value& b);
    Value call(const ast::Expr& e, const Env& env);
    Sink& sink_;
    const TypeLookup& types_;
    Names* names_ = nullptr;
};

}  // namespace plant::sema
