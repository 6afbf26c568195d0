// A test-only program: the bottling plant with the PLC link's server on the map of
// bottling_map.h, until the link kind lets `plant run` declare one. The mbpoll tests
// (tests/plc/mbpoll_test.sh) drive it with Debian's real mbpoll binary.
//
//   plc_harness [--for 30s] [--warmup 20s] [--lockstep] [--port N] [--port-file FILE]
//
// --warmup runs that much simulated time flat out before serving (so bottles are on the
// line), then the plant runs paced to the wall clock (or, with --lockstep, as clients
// grant steps). It prints "listening on 127.0.0.1:PORT" once serving, and at the end (or
// on SIGINT / SIGTERM) the steps run, the server's counts and whether belt b1 runs.
#include "bottling_map.h"
#include "compiler.h"
#include "engine/engine.h"
#include "engine/interrupt.h"
#include "engine/events.h"
#include "plc/server.h"
#include "panel/kind.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

int main(int argc, char** argv) {
    plant::panel::register_panel_kinds();  // the bottling line's operator panel
    double duration = 30, warmup = 0;
    plant::plc::ServerOptions o;
    std::string port_file, error;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool has = i + 1 < argc;
        if (a == "--for" && has) {
            if (!plant::engine::parse_duration(argv[++i], duration, error)) break;
        } else if (a == "--warmup" && has) {
            if (!plant::engine::parse_duration(argv[++i], warmup, error)) break;
        } else if (a == "--lockstep") {
            o.lockstep = true;
        } else if (a == "--port" && has) {
            o.port = std::atoi(argv[++i]);
        } else if (a == "--port-file" && has) {
            port_file = argv[++i];
        } else {
            error = "usage: plc_harness [--for 30s] [--warmup 20s] [--lockstep] [--port N] [--port-file FILE]";
            break;
        }
    }
    if (!error.empty()) {
        std::fprintf(stderr, "plc_harness: %s\n", error.c_str());
        return 2;
    }
    plant::Compilation c;
    plant::CompileOptions opts;
    opts.stdlib_dir = PLANT_SOURCE_DIR "/stdlib";
    plant::compile_file(PLANT_SOURCE_DIR "/plants/bottling.plant", opts, c);
    plant::plc::Map map;
    if (!c.ok() || !plant::test::bottling_map(c.graph, map, error)) {
        std::fprintf(stderr, "plc_harness: %s\n", c.ok() ? error.c_str() : "the bottling plant does not compile");
        return 1;
    }
    plant::engine::Engine e(c.graph);
    plant::plc::Server server(c.graph, map, o);
    if (!server.start(error)) {
        std::fprintf(stderr, "plc_harness: %s\n", error.c_str());
        return 1;
    }
    auto step = [&] {
        server.before_step(e);
        e.step();
        server.after_step(e);
    };
    while (e.time() < warmup - 1e-9) step();
    std::printf("listening on 127.0.0.1:%d\n", server.port());
    std::fflush(stdout);
    if (!port_file.empty()) std::ofstream(port_file) << server.port() << "\n";
    const auto t0 = std::chrono::steady_clock::now();
    const double start = e.time();
    int rc = 0;
    plant::engine::InterruptGuard interrupt;  // SIGINT / SIGTERM end the run with its summary
    while (e.time() < start + duration - 1e-9 && !plant::engine::InterruptGuard::requested()) {
        if (o.lockstep && !server.wait_for_step(error)) {
            std::fprintf(stderr, "plc_harness: %s\n", error.c_str());
            rc = 1;
            break;
        }
        step();
        if (o.lockstep) continue;
        const double ahead = (e.time() - start) - std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (ahead > 0) std::this_thread::sleep_for(std::chrono::duration<double>(ahead));
    }
    int32_t drive = -1;
    for (size_t f = 0; f < c.graph.fields.size(); ++f)
        if (c.graph.comp_path(c.graph.fields[plant::graph::FieldId(f)].comp) == "line[0].b1.drive") drive = int32_t(f);
    const plant::plc::ServerStats s = server.stats();
    std::printf("steps: %lld\nrequests: %lld (%lld exceptions)\nclients: %lld accepted, %lld left, %lld dropped\n"
                "events applied: %lld\nline[0].b1.drive: %s\n",
                (long long)e.steps(), (long long)s.requests, (long long)s.exceptions, (long long)s.accepted,
                (long long)s.left, (long long)s.dropped, (long long)s.applied,
                drive >= 0 && e.field_on(plant::graph::FieldId(drive)) ? "on" : "off");
    return rc;
}
