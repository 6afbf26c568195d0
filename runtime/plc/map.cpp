#include "plc/map.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace plant::plc {

using graph::Dir;
using graph::SlotType;

int32_t width(const Entry& e) {
    switch (e.encoding) {
    case Encoding::Int32:
    case Encoding::Float32: return 2;
    case Encoding::String: return e.length;
    default: return 1;
    }
}

bool is_bit_table(Table t) { return t == Table::Coil || t == Table::DiscreteInput; }
bool written_by_plc(Table t) { return t == Table::Coil || t == Table::HoldingRegister; }

std::string_view table_name(Table t) {
    switch (t) {
    case Table::Coil: return "coil";
    case Table::DiscreteInput: return "discrete input";
    case Table::InputRegister: return "input register";
    case Table::HoldingRegister: return "holding register";
    }
    return "?";
}

std::string_view encoding_name(Encoding e) {
    switch (e) {
    case Encoding::Bit: return "bit";
    case Encoding::Int16: return "int16";
    case Encoding::Int32: return "int32";
    case Encoding::Scaled: return "scaled";
    case Encoding::Float32: return "float32";
    case Encoding::String: return "string";
    case Encoding::Count: return "count";
    }
    return "?";
}

namespace {

std::string_view type_name(SlotType t) {
    switch (t) {
    case SlotType::Void: return "void";
    case SlotType::Bool: return "bool";
    case SlotType::Int: return "int";
    case SlotType::Real: return "real";
    case SlotType::Vec3: return "vec3";
    case SlotType::Quat: return "quat";
    case SlotType::Pose: return "pose";
    case SlotType::String: return "string";
    case SlotType::Ref: return "ref";
    }
    return "?";
}

// Why `e`'s encoding does not fit its type and table ("" when it does).
std::string misfit(const Entry& e) {
    const bool bits = is_bit_table(e.table);
    if (bits && e.encoding != Encoding::Bit)
        return fmt::format("a {} holds one bit: encoding {} needs a register", table_name(e.table), encoding_name(e.encoding));
    switch (e.encoding) {
    case Encoding::Bit:
        if (e.type == SlotType::Bool || e.type == SlotType::Void) return "";
        break;
    case Encoding::Int16:
    case Encoding::Int32:
        if (e.type == SlotType::Int) return "";
        break;
    case Encoding::Scaled:
    case Encoding::Float32:
        if (e.type == SlotType::Real) return "";
        break;
    case Encoding::String:
        if (e.type == SlotType::String) return "";
        break;
    case Encoding::Count:
        if (e.type != SlotType::Void) break;
        if (e.table != Table::InputRegister) return "a count shows an output's activations: it lives in an input register";
        return "";
    }
    return fmt::format("a {} slot cannot be encoded as {} (docs/plc.md, \"Encodings\")", type_name(e.type),
                       encoding_name(e.encoding));
}

}  // namespace

std::vector<MapError> check_map(const Map& map, const graph::Graph& g) {
    std::vector<MapError> out;
    if (map.entries.size() > size_t(kMaxEntries))
        out.push_back({-1, fmt::format("{} entries: a link maps at most {} (its fault block has room for no more)",
                                       map.entries.size(), kMaxEntries)});
    for (size_t i = 0; i < map.entries.size(); ++i) {
        const Entry& e = map.entries[i];
        auto error = [&](std::string m) { out.push_back({int32_t(i), std::move(m)}); };
        if (e.slots.empty()) {
            error(fmt::format("'{}': no slot", e.path));
            continue;
        }
        bool bad_slot = false;
        for (graph::SlotId s : e.slots) bad_slot |= !g.slots.contains(s);
        if (bad_slot) {
            error(fmt::format("'{}': a slot id out of the graph's range", e.path));
            continue;
        }
        if (e.encoding == Encoding::String && (e.length < 1 || e.length > 123))
            error(fmt::format("'{}': a string takes 1 to 123 registers, not {}", e.path, e.length));
        if (e.encoding == Encoding::Scaled && (!std::isfinite(e.scale) || e.scale == 0))
            error(fmt::format("'{}': scale {:g} (a finite, non-zero factor)", e.path, e.scale));
        const int64_t last = int64_t(e.address) + width(e) - 1;
        if (e.address < 0 || last >= kControlBase)
            error(fmt::format("'{}': {} address {}{} is out of range (0 to {}; the link's control block is above)",
                              e.path, table_name(e.table), e.address,
                              width(e) > 1 ? fmt::format("..{}", last) : "", kControlBase - 1));
        if (std::string m = misfit(e); !m.empty()) error(fmt::format("'{}': {}", e.path, m));
        if (written_by_plc(e.table) && e.dir != Dir::In)
            error(fmt::format("'{}' is an output: a {} is written by the PLC and drives an input", e.path, table_name(e.table)));
        if (!written_by_plc(e.table) && e.dir != Dir::Out)
            error(fmt::format("'{}' is an input: a {} is read by the PLC and shows an output", e.path, table_name(e.table)));
        for (size_t j = 0; j < i; ++j) {
            const Entry& f = map.entries[j];
            if (f.table != e.table) continue;
            if (e.address < f.address + width(f) && f.address < e.address + width(e))
                error(fmt::format("'{}': {} {} overlaps '{}' at {}", e.path, table_name(e.table), e.address, f.path, f.address));
        }
    }
    return out;
}

bool make_entry(const engine::SlotIndex& index, const EntrySpec& spec, Entry& out, std::string& error) {
    auto it = index.find(spec.path);
    if (it == index.end()) {
        const std::string hint = engine::closest_path(index, spec.path);
        error = hint.empty() ? fmt::format("no slot '{}'", spec.path)
                             : fmt::format("no slot '{}'; did you mean '{}'?", spec.path, hint);
        return false;
    }
    out = Entry{spec.table, spec.address, spec.path, it->second.slots, it->second.type, it->second.dir,
                spec.encoding, spec.scale, spec.unit, spec.length};
    return true;
}

namespace {

// What a register or bit of `e` means to a PLC programmer: "1 = active in the last step".
std::string meaning(const Entry& e) {
    switch (e.encoding) {
    case Encoding::Bit:
        if (e.type == SlotType::Bool) return "the value";
        return e.dir == Dir::In ? "1 fires the input (once per write)" : "1 = active in the last step";
    case Encoding::Int16: return "signed 16 bit";
    case Encoding::Int32: return "signed 32 bit, high word first";
    case Encoding::Scaled: return fmt::format("value x {:g}{}", e.scale, e.unit.empty() ? "" : " (" + e.unit + ")");
    case Encoding::Float32: return "IEEE float, high word first";
    case Encoding::String: return fmt::format("{} ASCII bytes, high byte first, NUL padded", 2 * e.length);
    case Encoding::Count: return "steps active so far (16 bit, wraps)";
    }
    return "";
}

}  // namespace

std::string format_map(const Map& map, const graph::Graph&, MapFormat format) {
    std::vector<size_t> order(map.entries.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        const Entry &x = map.entries[a], &y = map.entries[b];
        return x.table != y.table ? x.table < y.table : x.address < y.address;
    });
    struct Row {
        std::string table, address, path, type, encoding, meaning;
    };
    std::vector<Row> rows;
    for (size_t i : order) {
        const Entry& e = map.entries[i];
        const int32_t last = e.address + width(e) - 1;
        rows.push_back({std::string(table_name(e.table)),
                        last > e.address ? fmt::format("{}-{}", e.address, last) : fmt::format("{}", e.address), e.path,
                        fmt::format("{} {}", e.dir == Dir::In ? "in" : "out", type_name(e.type)),
                        std::string(encoding_name(e.encoding)), meaning(e)});
    }
    rows.push_back({"holding register", fmt::format("{}", kAdvance), "(link) advance", "", "uint16",
                    "lock-step: write N to run N more steps; reads the steps still to run"});
    rows.push_back({"input register", fmt::format("{}-{}", kStatusSteps, kStatusSteps + 1), "(link) steps", "", "uint32",
                    "steps run, high word first"});
    rows.push_back({"input register", fmt::format("{}-{}", kStatusTimeMs, kStatusTimeMs + 1), "(link) time", "", "uint32",
                    "simulated time in ms, high word first"});
    rows.push_back({"input register", fmt::format("{}", kStatusLockstep), "(link) lockstep", "", "bit", "1 in lock-step"});
    if (!map.entries.empty())
        rows.push_back({"holding register",
                        fmt::format("{}-{}", kFaultBase, kFaultBase + kFaultStride * int32_t(map.entries.size()) - 1),
                        "(link) faults", "", "per entry",
                        fmt::format("{} + {}*entry: mode (0 release, 1 stuck, 2 open, 3 invert), stuck value (float32)",
                                    kFaultBase, kFaultStride)});
    std::string out;
    if (format == MapFormat::Csv) {
        auto quote = [](const std::string& s) {
            if (s.find_first_of(",\"") == std::string::npos) return s;
            std::string q = "\"";
            for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
            return q + "\"";
        };
        out = "table,address,path,slot,encoding,meaning\n";
        for (const Row& r : rows)
            out += fmt::format("{},{},{},{},{},{}\n", quote(r.table), quote(r.address), quote(r.path), quote(r.type),
                               quote(r.encoding), quote(r.meaning));
        return out;
    }
    out = "| table | address | path | slot | encoding | meaning |\n|---|---|---|---|---|---|\n";
    for (const Row& r : rows)
        out += fmt::format("| {} | {} | {} | {} | {} | {} |\n", r.table, r.address, r.path[0] == '(' ? r.path : "`" + r.path + "`",
                           r.type, r.encoding, r.meaning);
    return out;
}

}  // namespace plant::plc
