#include "app/summary.h"

#include "engine/times.h"

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <ostream>

namespace plant::app {

using engine::RunSummary;
using engine::time_text;

namespace {

// The lost objects, one a line in the order lost, up to this many.
constexpr size_t kLossLines = 20;

void objects_text(const RunSummary& s, std::ostream& out) {
    const RunSummary::Objects& m = s.objects;
    if (!m.shown) return;
    fmt::print(out, "objects:\n");
    if (m.issued) fmt::print(out, "  issued by sources:     {}\n", *m.issued);
    if (m.taken) fmt::print(out, "  taken by exits:        {}\n", *m.taken);
    fmt::print(out, "  on the line:           {}\n", m.on_line);
    if (m.removed) fmt::print(out, "  removed by hand:       {}\n", m.removed);
    fmt::print(out, "  lost (left the world): {}{}\n", m.lost, m.lost ? " (" + m.lost_names + ")" : "");
    for (size_t i = 0; i < m.lost_objects.size() && i < kLossLines; ++i)
        fmt::print(out, "    {}: {}; left the world at {} s\n", m.lost_objects[i].object, m.lost_objects[i].where,
                   time_text(m.lost_objects[i].left_at, s.dt));
    if (m.lost_objects.size() > kLossLines) fmt::print(out, "    ... and {} more\n", m.lost_objects.size() - kLossLines);
    fmt::print(out, "  stalled over 30 s:     {}{}\n", m.stalled, m.stalled ? " (" + m.stalled_names + ")" : "");
}

void records_text(const RunSummary& s, std::ostream& out) {
    if (s.records.empty()) return;
    size_t width = 0;
    for (const auto& r : s.records) width = std::max(width, r.column.size());
    fmt::print(out, "records:\n");
    for (const auto& r : s.records) {
        if (r.events) fmt::print(out, "  {:<{}}  {} events ({:.1f} per minute)\n", r.column, width, r.count, r.per_minute);
        else fmt::print(out, "  {:<{}}  {:g}{}\n", r.column, width, r.value, r.sum ? " (sum)" : "");
    }
}

void forces_text(const RunSummary& s, std::ostream& out) {
    if (s.forces.empty()) return;
    size_t width = 0;
    for (const auto& x : s.forces) width = std::max(width, x.path.size());
    fmt::print(out, "forced:           {}\n", s.forces.size());
    for (const auto& x : s.forces)
        fmt::print(out, "  {:<{}}  {:<14}  from {} s to {}\n", x.path, width, x.how, time_text(x.from, s.dt),
                   x.until < 0 ? fmt::format("the end ({} s)", time_text(s.time, s.dt))
                               : fmt::format("{} s", time_text(x.until, s.dt)));
}

}  // namespace

void write_summary_text(const RunSummary& s, std::ostream& out) {
    if (!s.interrupted_by.empty())
        fmt::print(out, "interrupted:      by {} after {} s of {:g} s\n", s.interrupted_by, time_text(s.time, s.dt), s.duration);
    fmt::print(out, "simulated time:   {} s\n", time_text(s.time, s.dt));
    fmt::print(out, "steps:            {} at {:g} Hz\n", s.steps, 1.0 / s.dt);
    if (s.regions > 1)
        fmt::print(out, "physics regions:  {} (a Bullet world each), on {} thread{}\n", s.regions, s.threads,
                   s.threads == 1 ? "" : "s");
    fmt::print(out, "wall time:        {:.3f} s\n", s.wall);
    fmt::print(out, "real-time factor: {:.1f}\n", s.wall > 0 ? s.time / s.wall : 0.0);
    objects_text(s, out);
    records_text(s, out);
    fmt::print(out, "warnings:         {}\n", s.warnings);
    for (const auto& w : s.warning_counts)
        if (w.count) fmt::print(out, "  {}: {}\n", w.text, w.count);
    if (!s.silent_triggers.empty()) {
        std::string names;
        for (size_t i = 0; i < s.silent_triggers.size() && i < 5; ++i) names += (i ? ", " : "") + s.silent_triggers[i];
        if (s.silent_triggers.size() > 5) names += ", ...";
        fmt::print(out, "  triggers that never fired: {} ({})\n", s.silent_triggers.size(), names);
    }
    forces_text(s, out);
}

void write_summary_json(const RunSummary& s, std::ostream& out) {
    using json = nlohmann::ordered_json;
    json j;
    j["format"] = "plant-run-summary 1";
    j["interrupted_by"] = s.interrupted_by.empty() ? json(nullptr) : json(s.interrupted_by);
    j["duration_s"] = s.duration;
    j["simulated_time_s"] = s.time;
    j["steps"] = s.steps;
    j["rate_hz"] = 1.0 / s.dt;
    j["physics_regions"] = s.regions;
    j["threads"] = s.threads;
    j["wall_time_s"] = s.wall;
    j["real_time_factor"] = s.wall > 0 ? s.time / s.wall : 0.0;
    const RunSummary::Objects& m = s.objects;
    json lost = json::array();
    for (const auto& l : m.lost_objects) lost.push_back({{"object", l.object}, {"where", l.where}, {"left_at_s", l.left_at}});
    j["objects"] = {{"issued", m.issued ? json(*m.issued) : json(nullptr)},
                    {"taken", m.taken ? json(*m.taken) : json(nullptr)},
                    {"on_line", m.on_line},
                    {"removed", m.removed},
                    {"lost", m.lost},
                    {"stalled", m.stalled},
                    {"lost_objects", lost},
                    {"stalled_objects", m.stalled_objects}};
    json records = json::array();
    for (const auto& r : s.records) {
        if (r.events) records.push_back({{"column", r.column}, {"events", r.count}, {"per_minute", r.per_minute}});
        else records.push_back({{"column", r.column}, {"value", r.value}, {"sum", r.sum}});
    }
    j["records"] = records;
    json warnings = {{"total", s.warnings}};
    for (const auto& w : s.warning_counts) warnings[w.key] = w.count;
    warnings["silent_triggers"] = s.silent_triggers;
    j["warnings"] = warnings;
    json forces = json::array();
    for (const auto& x : s.forces)
        forces.push_back({{"path", x.path}, {"how", x.how}, {"from_s", x.from},
                          {"until_s", x.until < 0 ? json(nullptr) : json(x.until)}});
    j["forced"] = forces;
    // A NaN or an infinity (a record's value) is not JSON: null, and the warnings say why.
    out << j.dump(2, ' ', false, json::error_handler_t::replace) << "\n";
}

}  // namespace plant::app
