// Paths to slots, and the connections between them: ports, flows, connectors, records.
#include "sema/elaborator.h"

#include "graph/build.h"
#include "graph/kinds.h"

#include <fmt/format.h>

#include <cmath>
#include <map>

namespace plant::sema {

using graph::Dir;
using graph::SlotType;

namespace {

std::string path_text(const ast::Path& p) {
    std::string s;
    if (p.cast_base) s = "(" + path_text(*p.cast_base) + " as " + p.cast_type.text + ")";
    for (const auto& seg : p.segs) {
        if (!s.empty()) s += ".";
        s += seg.name.text;
        if (seg.index) s += "[..]";
    }
    return s;
}

// The word a plant file uses for a component's kind, a plugin's own among them.
std::string_view kind_word(const graph::Graph& g, graph::CompId comp) {
    if (const graph::KindDesc* d = graph::plugin_of(g, comp)) return d->word;
    return graph::kind_word(g.comps[comp].kind);
}

}  // namespace

graph::OptId<graph::Slot> Elaborator::find_comp_slot(graph::CompId comp, std::string_view slot_name) const {
    const auto& c = g_.comps[comp];
    for (graph::SlotId sl : children(c.slot_adr, c.slot_num))
        if (g_.str(g_.slots[sl].name) == slot_name) return sl;
    return {};
}

void Elaborator::name_component(const Scope& s, const std::vector<ast::PathSeg>& segs, size_t first, size_t last) {
    if (!names_ || first >= last) return;
    auto top = s.comps.find(segs[first].name.text);
    if (top == s.comps.end()) return;
    const Span decl = comp_spans_[top->second];
    name_use(segs[first].name.span, decl);
    std::string slot;
    for (size_t j = first + 1; j < last; ++j) {
        slot += (slot.empty() ? "" : ".") + segs[j].name.text;
        name_use(segs[j].name.span, decl, slot);
    }
}

Endpoint Elaborator::resolve(graph::DoId scope_do, const ast::Path& path, const Env& env) {
    Endpoint ep;
    ep.span = path.span;
    ep.text = path_text(path);
    if (path.cast_base) {
        Endpoint base = resolve(scope_do, *path.cast_base, env);
        if (!base.ok) return ep;
        if (base.slots.size() != 1 || base.type != SlotType::Ref || base.ref_slot.valid()) {
            sink_.report(DiagId::NotARef, path.cast_base->span,
                         fmt::format("'{}' is {} slot; only an object reference (ref) can be cast with 'as'",
                                     base.text, with_article(graph::word(base.type))));
            return ep;
        }
        int type_module = -1;
        const ast::ObjectDecl* type =
            find_type(path.cast_type.text, scopes_[scope_do].module, path.cast_type.span, &type_module);
        if (!type) return ep;
        name_use(path.cast_type.span, type->name.span);
        const graph::DoTypeId tid = do_type(path.cast_type.text, path.cast_type.span);
        if (auto it = ref_types_.find(base.slots[0]); it != ref_types_.end() && it->second != tid) {
            sink_.report(DiagId::RefTypeMismatch, path.cast_type.span,
                         fmt::format("'{}' holds a '{}', which is not a '{}'", base.text,
                                     g_.str(g_.do_types[it->second].name), path.cast_type.text));
            return ep;
        }
        ep.ok = true;
        ep.ref_slot = base.slots[0];
        ep.do_type = tid;
        ep.access_path = &path;
        return ep;  // the member is resolved against every object of the type, later
    }

    graph::DoId cur = scope_do;
    const auto& segs = path.segs;
    for (size_t i = 0; i < segs.size(); ++i) {
        const Scope& s = scopes_[cur];
        std::string key = segs[i].name.text;
        if (segs[i].index) {
            Value idx = ev_.eval(*segs[i].index, env);
            if (survey_ && idx.kind == Value::Kind::None) key += "[?]";  // a valueless loop's
            else if (!ev_.expect_int(idx, "index")) return ep;
            else key += fmt::format("[{}]", static_cast<long long>(idx.num));
        }
        auto it = s.children.find(key);
        if (survey_ && segs[i].index && it == s.children.end()) {  // any of the family will do
            it = s.children.lower_bound(segs[i].name.text + "[");
            if (it != s.children.end() && it->first.rfind(segs[i].name.text + "[", 0) != 0) it = s.children.end();
        }
        if (it != s.children.end()) {
            if (names_) {  // an instance by its name, a pooled object by its source's
                auto named = s.declared.find(it->first);
                name_use(segs[i].name.span,
                         named != s.declared.end() ? named->second : do_spans_[it->second]);
            }
            cur = it->second;
            if (i + 1 == segs.size()) {
                auto& d = sink_.report(DiagId::NotAnObject, path.span,
                                       fmt::format("'{}' is an object; name one of its slots, e.g. '{}.<slot>'", ep.text, ep.text));
                std::vector<std::string> ports;
                for (const auto& [n, port] : scopes_[cur].ports) ports.push_back(n);
                if (!ports.empty()) d.notes.push_back({{}, fmt::format("its ports: {}", fmt::join(ports, ", "))});
                return ep;
            }
            continue;
        }
        // A port of this object (own ports are used from inside, child ports from outside).
        if (auto it = s.ports.find(key); it != s.ports.end() && i + 1 == segs.size()) {
            name_use(segs[i].name.span, it->second.span);
            ep.ok = !it->second.slots.empty();
            ep.slots = it->second.slots;
            ep.type = it->second.type;
            ep.dir = it->second.input ? Dir::In : Dir::Out;
            return ep;
        }
        // A component: the longest run of segments that names one (child graphics are "a.b").
        std::string comp_name;
        graph::CompId comp;
        size_t after = i;
        for (size_t j = i; j < segs.size(); ++j) {
            comp_name += (j == i ? "" : ".") + segs[j].name.text;
            if (auto it = s.comps.find(comp_name); it != s.comps.end()) {
                comp = it->second;
                after = j + 1;
            }
        }
        if (comp.valid()) {
            name_component(s, segs, i, segs.size());
            std::string slot_name;
            for (size_t j = after; j < segs.size(); ++j) slot_name += (j == after ? "" : ".") + segs[j].name.text;
            const auto& c = g_.comps[comp];
            if (const graph::KindDesc* k = graph::builtin_kind(c.kind); slot_name.empty() && k && k->bare_slot >= 0)
                slot_name = k->slots[k->bare_slot].name;  // `go` is a connector's `go.out`
            const auto slot = slot_name.empty() ? graph::OptId<graph::Slot>{} : find_comp_slot(comp, slot_name);
            if (!slot.valid()) {
                std::vector<std::string> names;
                for (const graph::Slot& sl : g_.slots.slice(c.slot_adr, c.slot_num)) names.emplace_back(g_.str(sl.name));
                auto& d = sink_.report(DiagId::UnknownSlot, slot_name.empty() ? path.span : segs[after].name.span,
                                       slot_name.empty()
                                           ? fmt::format("'{}' is a {} component; name one of its slots", ep.text, kind_word(g_, comp))
                                           : fmt::format("{} component '{}' has no slot '{}'", kind_word(g_, comp),
                                                         g_.str(c.name), slot_name));
                if (auto hint = closest_name(slot_name, names); !hint.empty())
                    d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
                else if (!names.empty() && names.size() <= 16)
                    d.notes.push_back({{}, fmt::format("its slots: {}", fmt::join(names, ", "))});
                return ep;
            }
            const auto& sl = g_.slots[slot];
            ep.ok = true;
            ep.slots = {slot};
            ep.type = sl.type;
            ep.dir = sl.dir;
            return ep;
        }
        // An instance whose type is unknown was reported where it is declared.
        if (s.broken.count(segs[i].name.text)) return ep;
        std::vector<std::string> names;
        for (const auto& [k, v] : s.children) names.push_back(k);
        for (const auto& [k, v] : s.comps) names.push_back(k);
        for (const auto& [k, v] : s.ports) names.push_back(k);
        auto& d = sink_.report(DiagId::UnknownName, segs[i].name.span,
                               cur == scope_do ? fmt::format("unknown name '{}'", key)
                                               : fmt::format("'{}' has no member '{}'", g_.str(g_.dos[cur].path), key));
        // `s` or `s[9]` where the loop made s[0] ... s[2]: list them rather than guess.
        const std::string base = segs[i].name.text + "[";
        std::vector<std::string> family;
        for (auto f = s.children.lower_bound(base); f != s.children.end() && f->first.rfind(base, 0) == 0; ++f)
            family.push_back(f->first);
        if (!family.empty())
            d.notes.push_back({{}, fmt::format("'{}' names indexed instances: {}{}", segs[i].name.text,
                                               fmt::join(family.begin(), family.begin() + std::min<size_t>(family.size(), 4), ", "),
                                               family.size() > 4 ? ", ..." : "")});
        else if (auto hint = closest_name(key, names); !hint.empty())
            d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
        return ep;
    }
    return ep;
}

void Elaborator::bind_port(Scope& s, const ast::PortDecl& p, const Env& env) {
    PortInfo info;
    info.input = p.is_input;
    info.span = p.name.span;
    if (!graph::parse_word(p.type.text, info.type)) {
        const auto all = graph::words<SlotType>();
        const std::vector<std::string> words(all.begin(), all.end());
        auto& d = sink_.report(DiagId::UnknownType, p.type.span, fmt::format("unknown slot type '{}'", p.type.text));
        if (auto hint = closest_name(p.type.text, words); !hint.empty())
            d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
        else
            d.notes.push_back({{}, fmt::format("slot types: {} (an event is 'void')", fmt::join(words, ", "))});
        return;
    }
    if (p.targets.empty()) {
        sink_.report(DiagId::PortUnbound, p.name.span,
                     fmt::format("port '{}' forwards to nothing; write `{} {}: {} => component.slot`", p.name.text,
                                 p.is_input ? "in" : "out", p.name.text, p.type.text));
        return;
    }
    if (!p.is_input && p.targets.size() > 1) {
        sink_.report(DiagId::PortUnbound, p.targets[1].span, "an output port forwards exactly one inner output");
        return;
    }
    for (const auto& t : p.targets) {
        Endpoint e = resolve(s.do_id, t, env);
        if (!e.ok) continue;
        if (e.ref_slot.valid()) {
            sink_.report(DiagId::NotARef, t.span, "a port cannot forward to a slot of an object known only at run time");
            continue;
        }
        if (e.dir != (p.is_input ? Dir::In : Dir::Out)) {
            sink_.report(DiagId::DirectionMismatch, t.span,
                         fmt::format("{} port '{}' must forward to an {}, but '{}' is an {}", p.is_input ? "input" : "output",
                                     p.name.text, p.is_input ? "input" : "output", e.text, dir_word(e.dir)));
            continue;
        }
        if (e.type != info.type) {
            sink_.report(DiagId::SlotTypeMismatch, t.span,
                         fmt::format("port '{}' is declared '{}', but '{}' is '{}'", p.name.text, p.type.text, e.text,
                                     graph::word(e.type)));
            continue;
        }
        info.slots.insert(info.slots.end(), e.slots.begin(), e.slots.end());
    }
    scopes_[s.do_id].ports[p.name.text] = std::move(info);
}

void Elaborator::emit_flow(const std::vector<graph::SlotId>& from, const std::vector<graph::SlotId>& to,
                           graph::AccessId from_access, graph::AccessId to_access, graph::Cond cond, bool once, Span span) {
    // One flow per pair of ends: an input port may stand for several inner inputs.
    for (graph::SlotId f : from)
        for (graph::SlotId t : to) {
            graph::add_flow(g_, f, t, cond, once, from_access, to_access, src(span));
            flow_spans_.push_back(span);
        }
}

// A flow runs from an output to an input of the same type; otherwise one diagnostic.
bool Elaborator::flow_ends_fit(const Endpoint& from, Dir from_dir, SlotType from_type, const Endpoint& to, Dir to_dir,
                               SlotType to_type) {
    if (from_dir != Dir::Out) {
        auto& d = sink_.report(DiagId::DirectionMismatch, from.span,
                               fmt::format("a flow starts at an output, but '{}' is an input", from.text));
        if (to_dir == Dir::Out) d.notes.push_back({to.span, "and its target is an output: swap the two ends?"});
        return false;
    }
    if (to_dir != Dir::In) {
        sink_.report(DiagId::DirectionMismatch, to.span, fmt::format("a flow ends at an input, but '{}' is an output", to.text));
        return false;
    }
    if (from_type != to_type) {
        sink_.report(DiagId::SlotTypeMismatch, to.span,
                     fmt::format("slot types differ: '{}' output '{}' cannot drive '{}' input '{}'", graph::word(from_type),
                                 from.text, graph::word(to_type), to.text));
        return false;
    }
    return true;
}

void Elaborator::add_flow(const ast::FlowDecl& f, const Env& env, graph::DoId scope_do) {
    graph::Cond cond = graph::Cond::Source;
    if (f.condition && !graph::parse_word(f.condition->text, cond)) {
        auto& d = sink_.report(DiagId::BadCondition, f.condition->span,
                               fmt::format("unknown flow condition '{}'", f.condition->text));
        const auto all = graph::words<graph::Cond>();
        const std::vector<std::string> words(all.begin(), all.end());
        std::string ways;
        for (size_t i = 0; i < words.size(); ++i)
            ways += fmt::format("{}`when {}`{}", i == 0 ? "" : i + 1 == words.size() ? " or " : ", ", words[i],
                                i == 0 ? " (default)" : "");
        d.notes.push_back({{}, "a flow runs " + ways});
        if (auto hint = closest_name(f.condition->text, words); !hint.empty())
            d.notes.push_back({{}, fmt::format("did you mean '{}'?", hint)});
    }
    if (f.name) declare(scopes_[scope_do], f.name->text, f.name->span);
    Endpoint from = resolve(scope_do, f.from, env);
    Endpoint to = resolve(scope_do, f.to, env);
    if (!from.ok || !to.ok) return;
    if (from.ref_slot.valid() || to.ref_slot.valid()) {
        from.env = to.env = std::shared_ptr<const Env>();  // resolved in the type's own objects
        from.access_scope = to.access_scope = scope_do;
        pending_.push_back({&f, std::move(from), std::move(to), cond});
        return;
    }
    if (!flow_ends_fit(from, from.dir, from.type, to, to.dir, to.type)) return;
    emit_flow(from.slots, to.slots, {}, {}, cond, f.once, f.span);
}

void Elaborator::add_record(Scope& s, const ast::RecordDecl& r, const Env& env) {
    Endpoint e = resolve(s.do_id, r.path, env);
    if (!e.ok) return;
    if (e.ref_slot.valid() || e.slots.size() != 1) {
        sink_.report(DiagId::NotAnObject, r.path.span,
                     e.ref_slot.valid() ? fmt::format("record names one slot of a fixed object; '{}' belongs to whichever "
                                                      "object the reference holds at run time", e.text)
                                        : fmt::format("record names one slot, but port '{}' forwards to {} inputs; record "
                                                      "one of them", e.text, e.slots.size()));
        return;
    }
    std::string prefix(g_.str(g_.dos[s.do_id].path));
    std::string column = prefix.empty() ? e.text : prefix + "." + e.text;
    if (r.column) {
        Value v = ev_.eval(*r.column, env);
        if (!ev_.expect_string(v, "a record's column name")) return;
        column = v.str;
    } else if (column.find("[..]") != std::string::npos) {
        // Indexed paths name their evaluated indices: d[2].body.position.
        column = prefix;
        for (const auto& seg : r.path.segs) {
            column += (column.empty() ? "" : ".") + seg.name.text;
            if (seg.index) {
                Value i = ev_.eval(*seg.index, env);
                const bool whole = i.kind == Value::Kind::Num && is_whole(i.num);
                column += whole ? fmt::format("[{}]", static_cast<long long>(i.num)) : "[?]";
            }
        }
    }
    g_.records.push_back({e.slots[0], name(column)});
}

// Every flow through `(ref as Type).member`: the member is resolved in each object of
// that type, in ordinal order, and must be the same kind of slot in all of them.
std::optional<std::pair<SlotType, Dir>> Elaborator::probe_member(const std::string& type_name, const ast::Path& member,
                                                                bool& reported) {
    reported = false;
    auto it = types_.find(type_name);
    if (it == types_.end()) return std::nullopt;
    const ast::ObjectDecl& decl = *it->second.second;
    for (const auto& p : decl.params)
        if (!p.default_value) return std::nullopt;
    // The prototype reports into the real sink: problems of the type itself are the same
    // diagnostics its other uses give (the sink drops exact duplicates), and an unknown
    // member is reported at the member's position in the flow.
    Elaborator proto(prog_, sm_, sink_);
    proto.library_mode_ = true;
    proto.record_names(names_, survey_, surveyed_);
    proto.max_expanded_ = max_expanded_;
    const graph::DoId root = proto.new_do("", graph::DoId{}, proto.do_type(type_name, decl.name.span), Frame{}, decl.name.span);
    proto.type_stack_.push_back(type_name);
    proto.elaborate_do(root, decl, it->second.first, proto.bind_args(decl, {}, decl.name.span, Env{}));
    const int before = sink_.count(Severity::Error);
    Endpoint m = proto.resolve(root, member, Env{});
    if (!m.ok || m.slots.size() != 1) {
        reported = sink_.count(Severity::Error) > before;
        return std::nullopt;
    }
    const auto& sl = proto.g_.slots[m.slots[0]];
    return std::pair<SlotType, Dir>{sl.type, sl.dir};
}

void Elaborator::finish_accesses() {
    // The objects of each type, and the targets of each (type, member) once: every access to
    // the same member of the same type shares one range of access_targets, so the work and
    // the table grow with the plant, not with accesses times objects.
    graph::IdVector<graph::DoTypeId, std::vector<graph::DoId>> dos_of_type(g_.do_types.count());
    for (graph::DoId d : ids_of(g_.dos))
        if (g_.dos[d].type.valid()) dos_of_type[g_.dos[d].type].push_back(d);
    struct Targets {
        bool ok;
        graph::Adr<graph::AccessTarget> adr;
        int32_t count;
        SlotType type;
        Dir dir;
    };
    std::map<std::pair<graph::DoTypeId, std::string>, Targets> shared;
    for (auto& pf : pending_) {
        Endpoint* ends[2] = {&pf.from, &pf.to};
        graph::AccessId access_ids[2] = {};
        SlotType types[2] = {pf.from.type, pf.to.type};
        Dir dirs[2] = {pf.from.dir, pf.to.dir};
        bool ok = true;
        for (int k = 0; k < 2 && ok; ++k) {
            Endpoint& e = *ends[k];
            if (!e.ref_slot.valid()) continue;
            graph::Access acc;
            acc.ref_slot = e.ref_slot;
            acc.do_type = e.do_type;
            acc.target_adr = graph::next_adr(g_.access_targets);
            std::string member;
            for (const auto& seg : e.access_path->segs) member += (member.empty() ? "" : ".") + seg.name.text;
            acc.member = name(member);
            acc.src = src(e.span);
            auto known = shared.find({e.do_type, member});
            if (known != shared.end() && known->second.ok && known->second.count > 0) {  // else: resolved (and reported) again here
                acc.target_adr = known->second.adr;
                acc.target_num = known->second.count;
                types[k] = known->second.type;
                dirs[k] = known->second.dir;
                access_ids[k] = g_.accesses.push_back(acc);
                continue;
            }
            ast::Path sub;
            sub.span = e.span;
            for (const auto& seg : e.access_path->segs) {
                ast::PathSeg cp;
                cp.name = seg.name;
                sub.segs.push_back(std::move(cp));
            }
            bool first = true;
            int32_t count = 0;
            const std::vector<graph::DoId> none;
            const std::vector<graph::DoId>& candidates = dos_of_type.contains(e.do_type) ? dos_of_type[e.do_type] : none;
            for (graph::DoId d : candidates) {
                Endpoint m = resolve(d, sub, Env{});
                if (!m.ok || m.slots.size() != 1) {
                    if (m.ok) sink_.report(DiagId::NotAnObject, e.span, "a dynamic slot must name one slot");
                    ok = false;
                    break;
                }
                const auto& sl = g_.slots[m.slots[0]];
                if (first) {
                    types[k] = sl.type;
                    dirs[k] = sl.dir;
                    first = false;
                } else if (sl.type != types[k] || sl.dir != dirs[k]) {
                    // Parameters or conditions made the objects of one type differ.
                    sink_.report(DiagId::SlotTypeMismatch, e.span,
                                 fmt::format("'{}' is not the same kind of slot in every '{}': {} {} in one, {} {} in '{}'",
                                             e.text, g_.str(g_.do_types[e.do_type].name),
                                             graph::word(types[k]), dir_word(dirs[k]), graph::word(sl.type), dir_word(sl.dir),
                                             g_.str(g_.dos[d].path)));
                    ok = false;
                    break;
                }
                g_.access_targets.push_back({m.slots[0]});
                ++count;
            }
            if (ok && count == 0) {
                // No object of the type exists (a library checked alone, or a plant that
                // never builds one): check the member on a prototype built from defaults.
                bool reported = false;
                auto probe = probe_member(std::string(g_.str(g_.do_types[e.do_type].name)), sub, reported);
                if (probe) {
                    types[k] = probe->first;
                    dirs[k] = probe->second;
                } else if (reported) {
                    ok = false;
                } else {
                    sink_.report(DiagId::NotAnObject, e.span,
                                 fmt::format("no object of type '{}' exists here to check '{}' against, and none can be "
                                             "built from its defaults; the member may not exist",
                                             g_.str(g_.do_types[e.do_type].name), e.text));
                    ok = false;
                }
            }
            acc.target_num = count;
            shared[{e.do_type, member}] = Targets{ok, acc.target_adr, count, types[k], dirs[k]};
            if (ok) {
                access_ids[k] = g_.accesses.push_back(acc);
            }
        }
        if (!ok) continue;
        if (!flow_ends_fit(pf.from, dirs[0], types[0], pf.to, dirs[1], types[1])) continue;
        // A dynamic end is carried by its ref slot; the access names the member.
        auto carried = [](const Endpoint& e) {
            return e.ref_slot.valid() ? std::vector<graph::SlotId>{e.ref_slot} : e.slots;
        };
        emit_flow(carried(pf.from), carried(pf.to), access_ids[0], access_ids[1], pf.cond, pf.decl->once, pf.decl->span);
    }
}

}  // namespace plant::sema
