// Target `events`: the events-file and `--event` syntax ("TIME PATH [VALUE]", forces,
// releases, hands: grab, move, drop, remove) against the switch example's graph, then each parsed event applied to a running
// engine and its events-file line parsed back.
// Invariant: no crash, no sanitizer report; a refused line says why; a parsed event
// formats to a line that parses to the same slots and kind; applying it never breaks a step.
#include "engine/engine.h"
#include "switch_fixture.h"

#include <memory>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > 4096) return 0;
    static const plant::fuzz::SwitchFixture f;
    const plant::graph::Graph& g = f.c.graph;
    std::unique_ptr<plant::engine::Engine> e;
    std::string_view rest = plant::fuzz::text(data, size);
    int lines = 0;
    while (!rest.empty() && lines++ < 16) {
        const size_t nl = rest.find('\n');
        const std::string_view line = rest.substr(0, nl);
        rest = nl == std::string_view::npos ? std::string_view{} : rest.substr(nl + 1);
        plant::engine::Event ev;
        std::string error;
        if (!plant::engine::parse_event(g, f.idx, line, ev, error)) {
            if (error.empty()) plant::fuzz::broken("an event refused without a reason");
            continue;
        }
        const std::string back = plant::engine::format_event(g, ev);
        plant::engine::Event ev2;
        if (!plant::engine::parse_event(g, f.idx, back, ev2, error)) plant::fuzz::broken("a formatted event does not parse");
        if (ev2.slots != ev.slots || ev2.force != ev.force || ev2.mode != ev.mode || ev2.hand != ev.hand ||
            ev2.body != ev.body || ev2.object != ev.object)
            plant::fuzz::broken("an event does not round-trip");
        if (!e) e = std::make_unique<plant::engine::Engine>(g);
        plant::engine::apply_event(*e, ev);
        e->step();
    }
    return 0;
}
