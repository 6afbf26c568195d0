// What each name in the parsed modules stands for, as elaboration resolved it: the table the
// language server reads (definition, references, hover) instead of resolving names itself.
// A use names a declaration by the span of the declared name and, for a slot of a component,
// the slot's dotted name in it ("tick", "Home.entered"; a built-in slot has no declaration).
#pragma once

#include "diag/diagnostic.h"
#include "sema/modules.h"

#include <set>
#include <string>
#include <tuple>
#include <vector>

namespace plant::sema {

struct NameUse {
    Span use;    // the name as written
    Span decl;   // the declared name it stands for (a slot: its component's)
    std::string slot;
    bool declaration = false;  // `use` is the declaration itself
};

class Names {
public:
    // `use` stands for the name declared at `decl` (and, for a component's slot, `slot` in it).
    void use(Span use, Span decl, const std::string& slot = "") { add(use, decl, slot, false); }
    // A name is declared at `name` (a component's place, variant ...: `slot` of the component at `owner`).
    void declare(Span name) { add(name, name, "", true); }
    void declare(Span name, Span owner, const std::string& slot) { add(name, owner, slot, true); }
    const std::vector<NameUse>& all() const { return all_; }

private:
    void add(Span use, Span decl, const std::string& slot, bool declaration);
    std::set<std::tuple<int32_t, uint32_t, uint32_t, int32_t, uint32_t, std::string, bool>> seen_;
    std::vector<NameUse> all_;
};

// Every object type and plant of every module in `prog` elaborated, as `plant check` checks
// a library's types, with every name it meets recorded in `out`: a parameter without a
// default is valueless, both branches of an `if` are taken, a loop's body is elaborated once
// and a source pools one object, so that a name is resolved wherever it is written. A type
// is elaborated alone unless it already was inside another. Diagnostics are dropped (the
// compilation that loaded `prog` reports its own); no graph is kept.
void survey_names(const Program& prog, const SourceMap& sources, Names& out, long long max_members);

}  // namespace plant::sema
