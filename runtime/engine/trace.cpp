#include "engine/trace.h"
#include "engine/run.h"
#include "engine/times.h"

#include "graph/kinds.h"

#include <algorithm>
#include <cmath>
#include <ostream>

namespace plant::engine {

using namespace plant::graph;

namespace {

using Kind = TraceColumn::Kind;

void add_slot(const Graph& g, SlotId slot, const std::string& name, std::vector<TraceColumn>& out) {
    static const char* const kPose[] = {".x", ".y", ".z", ".qx", ".qy", ".qz", ".qw"};
    static const char* const kQuat[] = {".qx", ".qy", ".qz", ".qw"};
    const SlotType t = g.slots[slot].type;
    const int w = slot_width(t);
    if (t == SlotType::Void) out.push_back({Kind::Activity, slot.v, 0, name});
    else if (t == SlotType::String) out.push_back({Kind::Text, slot.v, 0, name});
    else if (w == 1) out.push_back({Kind::Value, slot.v, 0, name});
    else
        for (int i = 0; i < w; ++i)
            out.push_back({Kind::Value, slot.v, i, name + (t == SlotType::Quat ? kQuat[i] : kPose[i])});
}

// CSV needs quotes around text with separators or quotes in it.
void put_text(fmt::memory_buffer& b, std::string_view s) {
    if (s.find_first_of(",\"\n") == std::string_view::npos) {
        b.append(s);
        return;
    }
    b.push_back('"');
    for (char c : s) {
        if (c == '"') b.push_back('"');
        b.push_back(c);
    }
    b.push_back('"');
}

}  // namespace

std::vector<TraceColumn> trace_columns(const Graph& g, TraceSelect sel) {
    std::vector<TraceColumn> out;
    if (!sel.any() && !g.records.empty()) {
        for (const Record& r : g.records) {
            std::string name(g.str(r.column));
            add_slot(g, r.slot, name.empty() ? g.slot_path(r.slot) : name, out);
        }
        return out;
    }
    if (!sel.any()) sel = {true, true, true};
    if (sel.bodies)
        for (BodyId b : ids_of(g.bodies)) {
            if (g.bodies[b].mode != BodyMode::Dynamic) continue;
            std::string base = g.comp_path(g.bodies[b].comp);
            static const char* const kAxis[] = {".x", ".y", ".z"};
            for (int i = 0; i < 3; ++i) out.push_back({Kind::BodyAxis, b.v, i, base + kAxis[i]});
            out.push_back({Kind::BodySpeed, b.v, 0, base + ".speed"});
        }
    if (sel.places)
        for (PlaceId p : ids_of(g.places)) {
            const Place& pl = g.places[p];
            std::string name = pl.tokens_slot.valid() ? g.slot_path(pl.tokens_slot)
                                                      : g.comp_path(pl.comp) + "." + std::string(g.str(pl.name));
            out.push_back({Kind::Tokens, p.v, 0, name});
        }
    if (sel.slots)
        for (SlotId s : ids_of(g.slots))
            if (g.slots[s].type == SlotType::Void && g.slots[s].dir == Dir::Out)
                out.push_back({Kind::Activity, s.v, 0, g.slot_path(s)});
    return out;
}

bool can_lose(const Graph& g) {
    return std::any_of(g.bodies.begin(), g.bodies.end(), [](const Body& b) { return b.mode == BodyMode::Dynamic; });
}

TraceColumn lost_column() { return TraceColumn{TraceColumn::Kind::Lost, -1, 0, "lost"}; }

TraceColumn forced_column(std::vector<SlotId> slots) {
    TraceColumn c{TraceColumn::Kind::Forced, -1, 0, "forced", std::move(slots)};
    return c;
}

TraceWriter::TraceWriter(Engine& e, std::vector<TraceColumn> columns, std::ostream& out)
    : e_(e), cols_(std::move(columns)), counts_(cols_.size(), 0), out_(out), decimals_(trace_time_decimals(e.dt())) {
    for (size_t i = 0; i < cols_.size(); ++i) {
        const TraceColumn& c = cols_[i];
        if (c.kind == Kind::Value || c.kind == Kind::Text) e_.watch(c.slot());
        if (c.kind == Kind::Activity) activity_.push_back(i);
    }
}

void TraceWriter::header() {
    buf_.append(std::string_view("time"));
    for (const TraceColumn& c : cols_) {
        buf_.push_back(',');
        put_text(buf_, c.name);
    }
    buf_.push_back('\n');
    flush();
}

void TraceWriter::row() {
    // Shortest round-trip formatting: a trace compares bit for bit across runs. The time is
    // on the step grid with the run's fixed decimals (times.h: 18570 steps at 150 Hz print as
    // 123.800000, and a row an interrupt adds at step 27512 as 183.413333, not
    // 183.41333333333333).
    fmt::format_to(std::back_inserter(buf_), "{:.{}f}", double(e_.steps()) / e_.rate(), decimals_);
    for (const TraceColumn& c : cols_) {
        buf_.push_back(',');
        switch (c.kind) {
        case Kind::Value: fmt::format_to(std::back_inserter(buf_), "{}", e_.value(c.slot())[c.index]); break;
        case Kind::Text: put_text(buf_, e_.str(int32_t(e_.value(c.slot())[0]))); break;
        case Kind::Activity: fmt::format_to(std::back_inserter(buf_), "{}", counts_[&c - cols_.data()]); break;
        // A parked body (a pooled object not in the world) has empty cells, not the pool's pose.
        case Kind::BodyAxis:
            if (!e_.body_in_world(c.body())) break;
            fmt::format_to(std::back_inserter(buf_), "{}", e_.body_com(c.body())[c.index]); break;
        case Kind::BodySpeed: {
            if (!e_.body_in_world(c.body())) break;
            Vec3 v = e_.body_velocity(c.body());
            fmt::format_to(std::back_inserter(buf_), "{}", std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
            break;
        }
        case Kind::Tokens: fmt::format_to(std::back_inserter(buf_), "{}", e_.tokens(c.place())); break;
        case Kind::Lost: {
            const std::span<const DoId> lost = e_.lost();
            std::string cell;
            for (; lost_ < lost.size(); ++lost_)
                cell += fmt::format("{}{} {}", cell.empty() ? "" : ";", e_.graph().str(e_.graph().dos[lost[lost_]].path),
                                    loss_text(e_, lost[lost_]));
            put_text(buf_, cell);
            break;
        }
        case Kind::Forced: {
            std::string cell;
            for (SlotId s : c.slots) {
                const ForceMode m = e_.forced(s);
                if (m == ForceMode::None) continue;
                cell += fmt::format("{}{}={}", cell.empty() ? "" : ";", e_.graph().slot_path(s),
                                    m == ForceMode::Stuck ? "stuck" : m == ForceMode::Open ? "open" : "invert");
            }
            put_text(buf_, cell);
            break;
        }
        }
    }
    buf_.push_back('\n');
    std::fill(counts_.begin(), counts_.end(), 0);
    if (buf_.size() > (1 << 16)) flush();
}

void TraceWriter::step() {
    for (size_t i : activity_) counts_[i] += e_.active(cols_[i].slot()) ? 1 : 0;
}

void TraceWriter::finish() {
    for (size_t i : activity_) counts_[i] += e_.emitted(cols_[i].slot()) ? 1 : 0;
}

void TraceWriter::flush() {
    out_.write(buf_.data(), std::streamsize(buf_.size()));
    buf_.clear();
}

}  // namespace plant::engine
