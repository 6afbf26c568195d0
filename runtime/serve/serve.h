// The `plant serve` command: a live run of a compiled graph, or the replay of a recording,
// shown by the viewer page (docs/viewer.md). `args` are the flags after the file.
//
//   --port N        TCP port (default 8150; 0: any free port, printed)
//   --host ADDR     address to listen on (default 127.0.0.1)
//   --viewer DIR    the page's folder (default: $PLANT_VIEWER, else the checkout's viewer/)
//   --models DIR    where graphics models (glTF/GLB) are looked up besides the plant's folder
//   --paused        start paused
//   --speed X       0.1, 1, 10 ... times real time; 0 as fast as possible (default 1)
//   --threads N     physics threads (as plant run)
//   --steady-transport on|off   (as plant run)
//   --event "5s PATH [VALUE]", --events FILE   timed events applied in the run (as plant run)
//   --tls-cert FILE, --tls-key FILE   serve https and wss only (PEM files, both)
//   --open          no roles: every page has full control, on any --host
//   --no-roles      the same, refused on an address other than loopback without --open
//
// Roles (docs/viewer.md): unless --open, a secret token is drawn from the OS; the URL with
// it is the instructor's, `?role=trainee` a trainee's; on loopback a page without either is
// the instructor's (one user at their own machine), elsewhere a trainee's.
// Models are looked up under --models, beside the plant, then under `stdlib_dir`/models.
// Returns when SIGINT or SIGTERM arrives (0), or 2 for a bad flag (--no-roles on a
// non-loopback address without --open among them), 1 when it cannot listen.
// `link` (an OPC UA server the driver started) exchanges with the live run at its step
// boundaries, as it does in `plant run`; what its clients apply is logged like a page's events.
#pragma once

#include "engine/run.h"
#include "graph/graph.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace plant::view {

// `graph` is null for a replay: then `file` is the recording.
int serve_main(const graph::Graph* graph, const std::string& file, const std::vector<std::string>& args,
               std::ostream& out, std::ostream& err, engine::RunLink* link = nullptr,
               const std::string& stdlib_dir = {});

// The folder the page is served from by default.
std::string default_viewer_dir();

}  // namespace plant::view
