#pragma once
// How large a plant will be, known before anything is built where the source says it
// outright: an object type's members, its instances' members (sizes multiply), loops over
// literal ranges or lists, conditions on literals, sources' pools of literal size. The
// elaborator refuses a plant at once when this passes its limit (E0310), instead of finding
// out after building millions of members.

#include "ast/ast.h"

#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>

namespace plant::sema {

struct StaticSize {
    double members = 0;     // what the elaborator counts as expanded members
    double iterations = 0;  // loop iterations, empty bodies included
};

class SizeEstimate {
public:
    // `type` finds an object type's declaration by name (nullptr: unknown).
    explicit SizeEstimate(std::function<const ast::ObjectDecl*(const std::string&)> type) : type_(std::move(type)) {}
    // An instance of `decl` with its defaults: empty when a count depends on anything but
    // literals (a parameter, a name, an unknown type, a recursion).
    std::optional<StaticSize> of(const ast::ObjectDecl& decl);
    std::optional<StaticSize> of(std::span<const ast::Member> members);

private:
    std::optional<StaticSize> pool(const ast::ComponentDecl& c);
    std::function<const ast::ObjectDecl*(const std::string&)> type_;
    std::map<const ast::ObjectDecl*, std::optional<StaticSize>> known_;
    std::map<const ast::ObjectDecl*, bool> visiting_;
};

// The value of an expression of literal numbers and arithmetic on them (`3`, `2 * 8`, `0 - 4`),
// empty for anything else.
std::optional<double> literal_number(const ast::Expr& e);

}  // namespace plant::sema
