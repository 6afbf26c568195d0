// `plant serve`: a live run of a compiled graph, or the replay of a recording, shown by the
// viewer page (docs/viewer.md). Its command line is app/serve.cpp.
//
// Roles (docs/viewer.md): unless `open`, a secret token is drawn from the OS; the URL with
// it is the instructor's, `?role=trainee` a trainee's; on loopback a page without either is
// the instructor's (one user at their own machine), elsewhere a trainee's. `no_roles` off
// loopback without `open` is refused (2).
// Models are looked up under the models folder, beside the plant, then under the standard
// library's models. Returns when SIGINT or SIGTERM arrives (0), or 2 for a bad folder, 1
// when it cannot listen. `link` (an OPC UA server the command started) exchanges with the
// live run at its step boundaries, as it does in `plant run`; what its clients apply is
// logged like a page's events.
#pragma once

#include "engine/run.h"
#include "faults/drill.h"
#include "graph/graph.h"
#include "serve/server.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace plant::view {

struct ServeOptions {
    ServerOptions server;  // port, host, the page's folder, the models' folders
    double speed = 1;      // times real time (0: as fast as possible)
    bool paused = false;
    bool no_roles = false;  // --no-roles: `open` on this machine only
    engine::Options engine;             // threads
    std::vector<engine::Event> events;  // a live run's timed events
    std::vector<faults::Drill> drills;  // a live run's drills (--drill FILE)
    // Where the session report goes when the session ends (--report-dir): report.md,
    // report.html, session.events (serve/report.h); "" none.
    std::string report_dir;
};

// `graph` is null for a replay: then `file` is the recording.
int serve_main(const graph::Graph* graph, const std::string& file, ServeOptions options, std::ostream& out,
               std::ostream& err, engine::RunLink* link = nullptr);

// The folder the page is served from by default.
std::string default_viewer_dir();

}  // namespace plant::view
