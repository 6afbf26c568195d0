// Internal to compiler/sema: the kind-specific part of elaborating a component. The
// generic part (components.cpp: kind word, mode, properties known, set once and typed,
// sub-blocks allowed, the component and its fixed slots appended) hands each kind's
// lowering a Lowering; once every component of the object exists, its late linking (the
// references between components) gets a Linking. A kind on the kind table has both in its
// kinds/NAME/lower.cpp (KindLowering), as every built-in kind is, but for the connector,
// declared by its own form (KindDesc::own_form), which kinds/logic/lower.cpp makes and
// connects (Elaborator::make_logic, connect_logic); plugin.cpp lowers every plugin kind.
#pragma once

#include "sema/elaborator.h"

#include <map>
#include <string>

namespace plant::sema {

inline graph::Vec3 vec(const Value& v) { return {v.items[0].num, v.items[1].num, v.items[2].num}; }

// Properties of one component, looked up by name, checked once.
struct Props {
    std::map<std::string, std::pair<const ast::Property*, Value>> values;
    const Value* get(const std::string& n) const {
        auto it = values.find(n);
        return it == values.end() || it->second.second.kind == Value::Kind::None ? nullptr : &it->second.second;
    }
    bool has(const std::string& n) const { return values.count(n) > 0; }
};

// A component being lowered: appended with its fixed slots (from slot_adr on); its kind's
// record, detail and dynamic slots are the lowering's to add.
struct Lowering {
    Elaborator& el;
    Scope& scope;
    const ast::ComponentDecl& decl;
    const Env& env;
    const KindSpec& spec;
    const Props& props;
    std::string mode;         // the mode word, the kind's default when none is written
    graph::CompId comp;       // its id
    graph::Adr<graph::Slot> slot_adr;  // its first (fixed) slot
    Frame frame;              // its world frame
    graph::CompId parent;     // a child of its own kind (child graphics): its parent, else none

    double num(const char* n, double def) const;
    bool boolean(const char* n, bool def) const;
    void positive(const char* n) const;      // reported when set and not > 0
    void positive_vec(const char* n) const;  // reported when an item is not > 0
    // The component's detail: its row in its kind's table, lw.set_detail(g.timers.push_back(t)).
    template <class R>
    void set_detail(graph::Id<R> row) const {
        el.g_.comps[comp].detail = graph::Detail(row);
    }
};

// A component whose object's components all exist: references between them resolved.
struct Linking {
    Elaborator& el;
    Scope& scope;
    const ast::ComponentDecl& decl;
    const Env& env;
    graph::CompId comp;
    graph::Comp rec;
    std::string on;  // the `on` path, "" for none

    // Component `n` of this object, of any kind; none (reported) if there is none.
    graph::CompId find_comp(const std::string& n, Span span) const;
    // The row of component `n` of this object in R's table, find<graph::Body>: the component
    // is of the kind whose table that is (a `physics` one); none (reported) if it is not, or
    // there is none. `what` names the reference in the message ("'trigger'").
    template <class R>
    graph::Id<R> find(const std::string& n, Span span, const char* what) const {
        const graph::Comp* c = find_of_table(n, span, graph::table_name<R>(), what);
        return c ? graph::detail_of<R>(*c) : graph::Id<R>{};
    }
    graph::BodyId on_body() const { return find<graph::Body>(on, decl.on->span, "'on'"); }
    // find's lookup: component `n`, of the kind whose graph table is `table`; nullptr (reported) if none.
    const graph::Comp* find_of_table(const std::string& n, Span span, std::string_view table, const char* what) const;
    // The component's row in its kind's table (its detail), as that table's id: row<Joint>().
    template <class R>
    graph::Id<R> row() const {
        return graph::detail_of<R>(rec);
    }
    const ast::Property* prop(const char* n) const;
    // The component a reference property names, "" when it does not evaluate to a name.
    std::string ref_name(const ast::Property& p) const;
};

// The compiler's part of a kind on the kind table (kinds/NAME/lower.cpp, found through
// kinds/list.h): its lowering and, for a kind that names other components, its linking.
struct KindLowering {
    void (*lower)(Lowering& lw) = nullptr;
    void (*link)(Linking& lk) = nullptr;
};
const KindLowering* builtin_lowering(graph::CompKind kind);  // nullptr: Plugin (plugin.cpp)

// plugin.cpp: any plugin kind (graph/plugin.h)
void lower_plugin(Lowering& lw);
void link_plugin(Linking& lk);  // its component references (ParamType::CompRef)
// A placement on a kind whose row takes none (KindDesc::placed) would be dropped without a
// word: it is refused (E0311). Whether it was.
bool refuse_placement(Lowering& lw, const graph::KindDesc& kind);

}  // namespace plant::sema
