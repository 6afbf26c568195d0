#include "plc/kind.h"

#include "engine/plugin.h"
#include "engine/events.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstdlib>

namespace plant::plc {
namespace {

using graph::Dir;
using graph::ParamSpec;
using graph::ParamType;
using graph::SlotType;

constexpr std::string_view kWord = "modbus";

enum Param : int { port, host };
constexpr std::array kParams = {
    ParamSpec{"port", ParamType::Int, "", false, 0, "the TCP port; 0: --modbus-port's, else a free one"},
    ParamSpec{"host", ParamType::String, "", false, 0, "the IPv4 address to listen on; \"\": 127.0.0.1"},
};
enum Option : int { encoding, scale, unit, registers };
constexpr std::array kRegisterOptions = {
    ParamSpec{"encoding", ParamType::String, "", false, 0,
              "bit, int16, int32, scaled, float32, string or count; \"\": from the slot's type"},
    ParamSpec{"scale", ParamType::Number, "", false, 0, "the register holds round(value x scale); implies scaled"},
    ParamSpec{"unit", ParamType::String, "", false, 0, "a scaled register's unit, for the map"},
    ParamSpec{"registers", ParamType::Int, "", false, 0, "a string's registers (2 characters each); 0: 8"},
};
constexpr std::array kBitTypes = {SlotType::Bool, SlotType::Void};
constexpr std::array kRegisterTypes = {SlotType::Bool, SlotType::Void, SlotType::Int, SlotType::Real, SlotType::String};
constexpr int32_t kMaxAddress = kControlBase - 1;
constexpr std::array kEntries = {
    graph::EntrySpec{"coil", "a coil the PLC writes: drives a bool or void input", Dir::In, kBitTypes, {}, kMaxAddress},
    graph::EntrySpec{"discrete", "a discrete input the PLC reads: shows a bool or void output", Dir::Out, kBitTypes, {},
                     kMaxAddress},
    graph::EntrySpec{"input", "an input register the PLC reads: shows an output", Dir::Out, kRegisterTypes,
                     kRegisterOptions, kMaxAddress},
    graph::EntrySpec{"holding", "a holding register the PLC writes: drives an input", Dir::In, kRegisterTypes,
                     kRegisterOptions, kMaxAddress},
};

bool check_link(const graph::Graph& g, graph::PluginId plugin, graph::PluginProblem& problem);

constexpr graph::KindDesc kDesc{kWord, "a Modbus TCP link: the plant's slots as a PLC's registers (docs/plc.md)", {},
                                kParams, kEntries, graph::PluginPhase::None, graph::PluginPhase::None, graph::plugin_check<check_link>};

Table table_of(std::string_view word) {
    if (word == "coil") return Table::Coil;
    if (word == "discrete") return Table::DiscreteInput;
    if (word == "input") return Table::InputRegister;
    return Table::HoldingRegister;
}

constexpr std::array kEncodings = {Encoding::Bit,     Encoding::Int16,  Encoding::Int32, Encoding::Scaled,
                                   Encoding::Float32, Encoding::String, Encoding::Count};

// The encoding a register entry gets when its options name none: from the slot's type.
Encoding default_encoding(const Entry& e, bool scaled) {
    if (scaled) return Encoding::Scaled;
    switch (e.type) {
    case SlotType::Int: return Encoding::Int16;
    case SlotType::Real: return Encoding::Float32;
    case SlotType::String: return Encoding::String;
    case SlotType::Void: return e.table == Table::InputRegister ? Encoding::Count : Encoding::Bit;
    default: return Encoding::Bit;
    }
}

bool check_link(const graph::Graph& g, graph::PluginId plugin, graph::PluginProblem& problem) {
    Map m;
    if (!link_map(g, plugin, m, problem)) return false;
    if (const std::vector<MapError> errors = check_map(m, g); !errors.empty()) {
        problem = {errors.front().entry, errors.front().message};
        return false;
    }
    if (m.port == 0) return true;
    for (graph::PluginId q : graph::ids_of(g.plugins)) {
        if (q >= plugin) break;  // the links before this one
        const graph::Plugin& other = g.plugins[q];
        if (g.str(other.kind) != kWord || g.plugin_params[other.param_adr + port].num != m.port) continue;
        problem = {-1, fmt::format("port {} is taken by the link '{}': two links cannot serve one port", m.port,
                                   g.str(g.comps[other.comp].name))};
        return false;
    }
    return true;
}

}  // namespace

bool link_map(const graph::Graph& g, graph::PluginId plugin, Map& out, graph::PluginProblem& problem) {
    const graph::Plugin& p = g.plugins[graph::PluginId(plugin)];
    out = Map{};
    out.port = int(g.plugin_params[p.param_adr + port].num);
    out.host = std::string(g.str(g.plugin_params[p.param_adr + host].text));
    const engine::SlotIndex index = engine::slot_index(g);
    for (int32_t k = 0; k < p.entry_num; ++k) {
        const graph::PluginEntry& pe = g.plugin_entries[p.entry_adr + k];
        auto fail = [&](std::string message) {
            problem = {k, std::move(message)};
            return false;
        };
        Entry e;
        e.table = table_of(g.str(pe.word));
        e.address = int32_t(pe.key);
        for (const graph::PluginEntrySlot& s : g.plugin_entry_slots.slice(pe.slot_adr, pe.slot_num)) e.slots.push_back(s.v);
        if (e.slots.empty()) return fail("an entry that names no slot");
        const graph::Slot& first = g.slots[graph::SlotId(e.slots[0])];
        e.type = first.type;
        e.dir = first.dir;
        e.path = engine::path_of(index, e.slots);
        if (e.path.empty()) e.path = std::string(g.str(first.name));
        e.encoding = default_encoding(e, false);
        if (pe.param_num == graph::count_of(kRegisterOptions)) {
            auto option = [&](int o) -> const graph::PluginParam& { return g.plugin_params[pe.param_adr + o]; };
            const std::string_view name = g.str(option(encoding).text);
            const double factor = option(scale).num;
            e.unit = std::string(g.str(option(unit).text));
            e.encoding = default_encoding(e, factor != 0);
            if (!name.empty()) {
                const auto* it = std::find_if(kEncodings.begin(), kEncodings.end(),
                                              [&](Encoding c) { return encoding_name(c) == name; });
                if (it == kEncodings.end())
                    return fail(fmt::format("'{}': no encoding '{}' (bit, int16, int32, scaled, float32, string, count)",
                                            e.path, name));
                e.encoding = *it;
            }
            if (e.encoding == Encoding::Scaled) e.scale = factor;
            else if (factor != 0)
                return fail(fmt::format("'{}': a scale needs the scaled encoding, not {}", e.path, encoding_name(e.encoding)));
            if (!e.unit.empty() && e.encoding != Encoding::Scaled)
                return fail(fmt::format("'{}': a unit belongs to a scaled register, not to {}", e.path,
                                        encoding_name(e.encoding)));
            const int32_t length = int32_t(option(registers).num);
            if (length != 0 && e.encoding != Encoding::String)
                return fail(fmt::format("'{}': registers = {} is for a string, not {}", e.path, length,
                                        encoding_name(e.encoding)));
            e.length = e.encoding == Encoding::String ? (length == 0 ? 8 : length) : 1;
        }
        out.entries.push_back(std::move(e));
    }
    return true;
}

Map map_from_graph(const graph::Graph& g, int* links) {
    Map m;
    int n = 0;
    for (graph::PluginId p : graph::ids_of(g.plugins)) {
        if (g.str(g.plugins[p].kind) != kWord) continue;
        graph::PluginProblem problem;
        if (n++ == 0) link_map(g, p, m, problem);  // a problem shows in check_map
    }
    if (links) *links = n;
    return m;
}

void register_modbus_kind() {
    static constexpr engine::KindBehaviour kBehaviour{};  // kept by address: no hooks, no state
    static const bool registered = engine::register_plugin(kDesc, kBehaviour);
    if (!registered) std::abort();  // only a second kind named `modbus` could refuse it
}

}  // namespace plant::plc
