// Our own syntax tree, built from the ANTLR parse tree in compiler/parse and never
// containing ANTLR types. Every node carries the byte span it came from.
#pragma once

#include "diag/diagnostic.h"

#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace plant::ast {

struct Ident {
    std::string text;
    Span span;
};

struct Expr;
using ExprPtr = std::unique_ptr<Expr>;

enum class ExprKind { Number, String, Bool, Name, Unary, Binary, Tuple, List, Call };

struct Arg {
    std::optional<Ident> name;  // named argument `length = 2 m`
    ExprPtr value;
    Span span;
};

struct Expr {
    ExprKind kind;
    Span span;
    double number = 0;      // Number: the numeral as written
    std::string text;       // Number: unit text ("" none); String: value; Name: name; Unary/Binary: op; Call: callee
    Span unit_span;         // Number with a unit
    bool boolean = false;   // Bool
    ExprPtr index;          // Name: name[index]
    std::vector<Ident> members;  // Name: name.a.b
    std::vector<ExprPtr> kids;   // Unary (1), Binary (2), Tuple, List
    std::vector<Arg> args;       // Call
};

struct PathSeg {
    Ident name;
    ExprPtr index;  // seg[index], may be null
};

// a.b[i].c, or (a.object as Bottle).c.d
struct Path {
    std::unique_ptr<Path> cast_base;  // non-null for a cast path
    Ident cast_type;
    std::vector<PathSeg> segs;
    Span span;
};

struct Rotation {
    std::optional<Ident> axis_name;  // x, y or z
    ExprPtr axis_vec;                // or an explicit axis (x, y, z)
    ExprPtr angle;
    Span span;
};

struct Placement {
    ExprPtr at;  // may be null when only rotations are given
    std::vector<Rotation> rotations;
    Span span;
};

struct Property {
    Ident name;
    ExprPtr value;
    Span span;
};

struct ShapeDecl {
    Ident kind;
    std::vector<Arg> args;
    std::optional<Placement> placement;
    Span span;
};

struct KeyDecl {
    ExprPtr time;
    Placement placement;
    Span span;
};

struct AnimationDecl {
    Ident name;
    std::vector<Property> properties;
    std::vector<Rotation> rotations;
    std::vector<ExprPtr> moves;
    std::vector<KeyDecl> keys;
    Span span;
};

struct VariantDecl {
    Ident name;
    ExprPtr model;
    Span span;
};

struct PlaceDecl {
    Ident name;
    ExprPtr initial;  // may be null: zero tokens
    Span span;
};

struct ArcDecl {
    Ident place;
    double weight = 1;
    bool weight_written = false;
    Span weight_span;
    Span span;
};

struct TransitionDecl {
    Ident name;
    std::vector<ArcDecl> inputs;
    std::vector<ArcDecl> outputs;
    Span span;
};

struct RouteDecl {
    std::string pattern;  // "*" for the wildcard; else the pattern's source text
    ExprPtr pattern_expr; // a string or a list of strings; null for "*"
    Span pattern_span;
    Ident output;
    Span span;
};

// `coil 3 => s1.to_working(pulse = 1)`: an entry of a plugin kind's table, whose
// descriptor names the words it takes (graph/plugin.h: EntrySpec).
struct EntryDecl {
    Ident word;
    ExprPtr key;
    Path target;
    std::vector<Arg> options;
    Span span;
};

struct ComponentDecl {
    Ident kind;
    Ident name;
    std::optional<Ident> mode;
    std::optional<Path> on;  // attached to another component (a field on a body)
    std::optional<Placement> placement;
    std::vector<Property> properties;
    std::vector<ShapeDecl> shapes;
    std::vector<AnimationDecl> animations;
    std::vector<VariantDecl> variants;
    std::vector<PlaceDecl> places;
    std::vector<TransitionDecl> transitions;
    std::vector<RouteDecl> routes;
    std::vector<ComponentDecl> children;  // child graphics
    std::vector<EntryDecl> entries;       // plugin kinds' entries
    Span span;
};

struct PortDecl {
    bool is_input;
    Ident name;
    Ident type;
    std::vector<Path> targets;
    Span span;
};

struct LetDecl {
    Ident name;
    ExprPtr value;
    Span span;
};

struct FlowDecl {
    std::optional<Ident> name;
    Path from;
    Path to;
    std::optional<Ident> condition;
    bool once = false;
    Span span;
};

struct LogicTerm {
    bool negated = false;
    Path path;
    Span span;
};

struct LogicDecl {
    Ident name;
    std::vector<LogicTerm> terms;
    std::vector<Ident> ops;  // "and"/"or", between terms
    Span span;
};

struct RecordDecl {
    Path path;
    ExprPtr column;  // a string expression, may be null
    Span span;
};

struct SettingDecl {
    Ident name;
    ExprPtr value;
    Span span;
};

struct InstanceDecl {
    Ident name;
    ExprPtr index;  // name[index] inside a loop
    Ident type;
    std::vector<Arg> args;
    Span args_span;
    std::optional<Placement> placement;
    Span span;
};

struct ForDecl;
struct IfDecl;

using Member = std::variant<PortDecl, LetDecl, FlowDecl, LogicDecl, RecordDecl, SettingDecl,
                            InstanceDecl, ComponentDecl, std::unique_ptr<ForDecl>,
                            std::unique_ptr<IfDecl>>;

struct ForDecl {
    Ident var;
    ExprPtr from;  // the range's start, or the list
    ExprPtr to;    // exclusive; null: `for x in LIST` iterates over the list's items
    std::vector<Member> body;
    Span span;
};

struct IfDecl {
    ExprPtr cond;
    std::vector<Member> then_body;
    std::vector<Member> else_body;
    Span span;
};

struct Param {
    Ident name;
    Ident type;
    ExprPtr default_value;
    ExprPtr constraint;  // `where EXPR`: a condition every value must meet
    Span span;
};

struct ObjectDecl {
    bool is_plant = false;
    Ident name;
    std::vector<Param> params;
    std::vector<Member> members;
    Span span;
};

struct Import {
    std::string module;  // dotted: "std.belts"
    Span span;
};

struct Module {
    int32_t file = -1;
    std::vector<Import> imports;
    std::vector<ObjectDecl> objects;  // object types and plants, in order
};

// Span covering both.
inline Span join(Span a, Span b) {
    if (!a.valid()) return b;
    if (!b.valid()) return a;
    return Span{a.file, std::min(a.begin, b.begin), std::max(a.end, b.end)};
}

}  // namespace plant::ast
