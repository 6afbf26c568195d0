// Target `viewer_message`: what a page sends to `plant serve` (docs/viewer.md, "Page to
// server"): the client-message decoder, then, for an event or a force, the input parser the
// server hands it to (against the switch example's graph); for a drill, the drill parser
// (faults/drill.h).
// Invariant: no crash, no sanitizer report, no exception; a refused message says why.
#include "faults/drill.h"
#include "serve/protocol.h"
#include "switch_fixture.h"

#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > plant::view::kMaxClientMessage) return 0;
    static const plant::fuzz::SwitchFixture f;
    plant::view::ClientMessage m;
    std::string error;
    if (!plant::view::decode_client_message(plant::fuzz::text(data, size), m, error)) {
        if (error.empty()) plant::fuzz::broken("a message refused without a reason");
        return 0;
    }
    if (m.kind == plant::view::ClientMessage::Kind::Event) {
        const std::string input = m.value.empty() ? m.path : m.path + " " + m.value;
        plant::engine::Event ev;
        if (!plant::engine::parse_input(f.c.graph, f.idx, input, ev, error) && error.empty())
            plant::fuzz::broken("an input refused without a reason");
    }
    if (m.kind == plant::view::ClientMessage::Kind::Drill) {
        plant::faults::Drill d;
        if (!plant::faults::parse_drill(f.c.graph, f.idx, m.path, d, error) && error.empty())
            plant::fuzz::broken("a drill refused without a reason");
    }
    return 0;
}
