// Internal to compiler/sema: the state shared by the elaboration files. Elaboration
// instantiates the plant object by object (parameters substituted, loops unrolled),
// checks names, types, directions, units and values, and writes the flat graph as it
// goes: DOs, components and slots get their ids in a fixed depth-first order.
#pragma once

#include "graph/graph.h"
#include "sema/elaborate.h"
#include "sema/modules.h"
#include "sema/names.h"
#include "sema/schema.h"
#include "sema/value.h"

#include <Eigen/Geometry>
#include <map>
#include <optional>
#include <memory>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

namespace plant::sema {

struct Frame {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    Frame operator*(const Frame& local) const { return {p + q * local.p, (q * local.q).normalized()}; }
    Frame inverse() const {
        Eigen::Quaterniond qi = q.conjugate();
        return {qi * -p, qi};
    }
    graph::Pose pose() const {
        return {{p.x(), p.y(), p.z()}, {q.x(), q.y(), q.z(), q.w()}};
    }
};

struct PortInfo {
    bool input = false;
    graph::SlotType type = graph::SlotType::Void;
    std::vector<graph::SlotId> slots;  // inputs: every forwarded input; outputs: the one output
    Span span;
};

struct Scope {
    graph::DoId do_id;
    const ast::ObjectDecl* decl = nullptr;
    int module = -1;
    Frame frame;
    std::map<std::string, graph::CompId> comps;  // component name -> comp id
    std::map<std::string, graph::DoId> children;  // instance name ("b" or "b[3]") -> DO id
    std::map<std::string, PortInfo> ports;
    std::map<std::string, Span> declared;     // every member name, for duplicates
    std::set<std::string> broken;             // instances whose type is unknown (reported)
};

// A member of an object after loops and conditions were expanded, with its scope chain.
struct Item {
    const ast::Member* member;
    std::shared_ptr<const Env> env;
};

// A slot direction as messages name it: "input", "output".
inline std::string_view dir_word(graph::Dir d) { return d == graph::Dir::In ? "input" : "output"; }

// A resolved end of a flow.
struct Endpoint {
    bool ok = false;
    std::vector<graph::SlotId> slots;  // static slots (one, or several for an input port)
    graph::SlotType type = graph::SlotType::Void;
    graph::Dir dir = graph::Dir::Out;
    // Dynamic access: the ref slot (none: a static end), the object type, the member path below it.
    graph::OptId<graph::Slot> ref_slot;
    graph::DoTypeId do_type;
    const ast::Path* access_path = nullptr;
    graph::DoId access_scope;
    std::shared_ptr<const Env> env;
    std::string text;
    Span span;
};

struct Props;  // sema/kinds/lowering.h

struct PendingAccessFlow {
    const ast::FlowDecl* decl;
    Endpoint from, to;
    graph::Cond cond;
};

class Elaborator : public TypeLookup {
public:
    Elaborator(const Program& prog, const SourceMap& sm, Sink& sink);
    graph::Graph run(bool require_plant);
    void check_object(const ast::ObjectDecl& o, int module = -1);  // module: the root's when -1

    bool is_object_type(const std::string& name) const override;
    const ast::ObjectDecl* object_type(const std::string& name) const override;

    // The names resolved from now on are recorded in `names` (sema/names.h); `survey`:
    // elaborate every branch, one pass of every loop and one pooled object of a source
    // (survey_names), adding each object type elaborated to `surveyed`.
    void record_names(Names* names, bool survey, std::set<const ast::ObjectDecl*>* surveyed = nullptr);
    void name_use(Span use, Span decl, const std::string& slot = "") {
        if (names_) names_->use(use, decl, slot);
    }
    void name_declared(Span name) {
        if (names_) names_->declare(name);
    }
    // The segments [first, last) of a path, or of `on`, that name a component of `s` ("a",
    // child graphics "a.b") and the slot after it: each a use of the component or its slot.
    void name_component(const Scope& s, const std::vector<ast::PathSeg>& segs, size_t first, size_t last);

    // elaborate.cpp
    void elaborate_do(graph::DoId do_id, const ast::ObjectDecl& decl, int module,
                      std::shared_ptr<const Env> env);
    graph::DoId new_do(const std::string& path, graph::DoId parent, graph::DoTypeId type, const Frame& f, Span src);
    graph::DoTypeId do_type(const std::string& name, Span src);
    std::shared_ptr<const Env> bind_args(const ast::ObjectDecl& decl, const std::vector<ast::Arg>& args,
                                         Span call_span, const Env& caller_env);
    const ast::ObjectDecl* find_type(const std::string& name, int module, Span use, int* type_module);
    void expand(const std::vector<ast::Member>& members, std::shared_ptr<const Env> env,
                std::vector<Item>& out, int depth);
    bool declare(Scope& s, const std::string& name, Span span);
    bool nested_too_deep(Span at);
    bool too_large(const ast::ObjectDecl& o);
    Frame placement(const ast::Placement* p, const Env& env);
    // q := q * (the rotation, its angle scaled by share); the full angle in *angle_out.
    bool rotate(Eigen::Quaterniond& q, const ast::Rotation& r, const Env& env, double share = 1.0,
                double* angle_out = nullptr);
    graph::Src src(Span s);
    graph::Name name(std::string_view s) { return g_.intern(s); }

    // components.cpp (the generic part; each kind's in its kinds/NAME/lower.cpp, a plugin's in
    // sema/kinds/plugin.cpp)
    std::string check_mode(const ast::ComponentDecl& c, const KindSpec& spec);
    Props check_properties(const Scope& sc, const ast::ComponentDecl& c, const KindSpec& spec, const Env& env);
    void check_sub_blocks(const ast::ComponentDecl& c, const KindSpec& spec);
    bool inside_plugin(const Scope& sc, const std::string& holder, std::string_view word) const;
    // `parent`: the component a child of its own kind (child graphics) is made in, else none.
    graph::CompId make_component(Scope& s, const ast::ComponentDecl& c, const Env& env, graph::CompId parent,
                                 const std::string& prefix);
    graph::SlotId add_slot(graph::CompId comp, std::string_view name, graph::SlotType t, graph::Dir dir, Span span);
    void link_component(Scope& s, graph::CompId comp, const ast::ComponentDecl& c, const Env& env);
    // kinds/logic/lower.cpp: a connector, declared by its own form, made with the object's
    // members; its terms resolved into flows once they all exist.
    void make_logic(Scope& s, const ast::LogicDecl& l);
    void connect_logic(Scope& s, const ast::LogicDecl& l, const Env& env);
    void make_pools(graph::DoId do_id, const std::vector<Item>& items);

    // resolve.cpp
    Endpoint resolve(graph::DoId scope_do, const ast::Path& path, const Env& env);
    // A plugin component's entries (sema/kinds/plugin.cpp), with the flows of its scope.
    void add_entries(graph::CompId comp, const ast::ComponentDecl& c, const Env& env, graph::DoId scope_do);
    // The kinds' own checks (graph::KindDesc::check) over every plugin component.
    void check_plugins();
    bool expect_slot_value(const Value& v, graph::SlotType t, const std::string& what);
    bool entry_options(const ast::EntryDecl& e, const graph::EntrySpec& es, graph::SlotType target, const Env& env,
                       std::vector<graph::PluginParam>& out);
    void bind_port(Scope& s, const ast::PortDecl& p, const Env& env);
    void add_flow(const ast::FlowDecl& f, const Env& env, graph::DoId scope_do);
    bool flow_ends_fit(const Endpoint& from, graph::Dir from_dir, graph::SlotType from_type, const Endpoint& to,
                       graph::Dir to_dir, graph::SlotType to_type);
    void add_record(Scope& s, const ast::RecordDecl& r, const Env& env);
    void emit_flow(const std::vector<graph::SlotId>& from, const std::vector<graph::SlotId>& to,
                   graph::AccessId from_access, graph::AccessId to_access, graph::Cond cond, bool once, Span span);
    void finish_accesses();
    void emit_ports();
    std::optional<std::pair<graph::SlotType, graph::Dir>> probe_member(const std::string& type_name, const ast::Path& member,
                                                                        bool& reported);
    // The slot of `comp` named `slot_name`; none if it has none.
    graph::OptId<graph::Slot> find_comp_slot(graph::CompId comp, std::string_view slot_name) const;

    // checks.cpp
    void check_petri_nets();
    void check_unused();
    graph::IdVector<graph::SlotId, uint8_t> driven_or_exposed() const;
    void check_logic_cycles();
    void check_ranges();
    void check_static_velocities();
    // geometry.cpp
    void check_conveyor_ends();

    const Program& prog_;
    const SourceMap& sm_;
    Sink& sink_;
    Evaluator ev_;
    graph::Graph g_;
    graph::IdVector<graph::DoId, Scope> scopes_;
    std::map<std::string, std::pair<int, const ast::ObjectDecl*>> types_;  // object types by name
    std::map<std::string, graph::DoTypeId> do_types_;
    std::vector<std::string> type_stack_;  // objects being instantiated, for recursion
    std::map<graph::SlotId, graph::DoTypeId> ref_types_;  // ref slot -> DoType it holds
    std::vector<PendingAccessFlow> pending_;
    std::vector<int32_t> graph_file_of_;  // SourceMap file -> Graph::files index
    std::map<graph::CompId, Span> comp_spans_;
    graph::IdVector<graph::DoId, Span> do_spans_;  // its declaration
    std::map<graph::DoId, Span> do_at_spans_;     // the position its placement gives (`at (...)`)
    graph::IdVector<graph::FlowId, Span> flow_spans_;  // its declaration (for warnings)
    graph::IdVector<graph::PluginId, Span> plugin_spans_;  // the component's name
    graph::IdVector<graph::Id<graph::PluginEntry>, Span> entry_spans_;  // the entry
    // A hull's points by their coordinates: the same hull again (every bottle of a pool)
    // names the points already in Graph::points instead of copying them (kinds/body/lower.cpp).
    std::map<std::vector<double>, graph::Adr<graph::Point>> hulls_;
    std::map<graph::PlaceId, Span> place_spans_;  // its declaration (for warnings)
    std::map<graph::TransitionId, Span> transition_spans_;
    long long max_expanded_ = kMaxMembers;  // the limit on both counts below
    long long expanded_ = 0;      // members produced by loops, against runaway loops
    long long iterations_ = 0;    // loop iterations over all nesting, empty bodies included
    bool iterate(Span at);        // counts one; false past the limit (reported once)
    bool library_mode_ = false;  // checking one object type of a library
    Names* names_ = nullptr;     // where resolved names are recorded, if anywhere
    bool survey_ = false;        // every branch and one pass of every loop (survey_names)
    std::set<const ast::ObjectDecl*>* surveyed_ = nullptr;  // the types elaborated so far
};

}  // namespace plant::sema
