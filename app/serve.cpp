// `plant serve FILE` and `plant serve --replay RECORDING`: the viewer's server
// (serve/serve.h) with the flags read here, and the links of the parts that serve a live run.
#include "app/command.h"
#include "app/compile.h"
#include "app/parts.h"
#include "engine/events.h"
#include "serve/serve.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <iostream>

namespace plant::app {

namespace {

constexpr const char* kServeAbout =
    R"(Runs FILE (a .plant, or a .graph written by `plant build`) paced to the wall clock and
serves a page that shows it in 3D: open the printed URL. The page pauses, steps, changes
the speed, restarts, and acts on any input slot or port through the inspector; every
action is an event, logged on the page, and /events is the session's events file
(`plant run FILE --events events.txt` replays it headless, bit for bit). With --replay it
plays a recording made by `plant run FILE --record RECORDING`, with a timeline.)";

bool number(const std::string& text, double& v) {
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    return ec == std::errc() && end == text.data() + text.size() && std::isfinite(v);
}

int serve_command(const std::vector<std::string>& args) {
    Cli cli("serve", "FILE [options]\n       plant serve --replay RECORDING [options]", kServeAbout,
            "Roles: it prints the instructor's URL (with a secret token) and the trainees' URL; a\n"
            "trainee's page operates only the plant's `operable` inputs, its panels and the hand, and\n"
            "is not shown forces. On 127.0.0.1 a page without a token is the instructor's.\n"
            "Stop with Ctrl-C. The protocol and the page: docs/viewer.md.\n");
    cli.unknown_word("flag");
    view::ServeOptions so;
    so.server.viewer_dir = view::default_viewer_dir();
    std::string port, speed, threads;
    std::vector<std::string> event, events;
    bool replay = false, lockstep = false;
    cli.flag("--replay", replay, "FILE is a recording (`plant run --record`): play it, with a timeline");
    cli.value("--port", port, "TCP port (default 8150; 0: any free port)", "N");
    cli.value("--host", so.server.host, "address to listen on (default 127.0.0.1: this machine only)", "ADDR",
              "an address");
    cli.value("--speed", speed, "times real time (default 1; 0: as fast as possible)", "X");
    cli.flag("--paused", so.paused, "start paused");
    cli.value("--tls-cert", so.server.tls_cert, "serve https and wss only, with this certificate (PEM; with --tls-key)",
              "FILE", "a file");
    cli.value("--tls-key", so.server.tls_key, "the certificate's private key (PEM)", "FILE", "a file");
    cli.flag("--open", so.server.open, "no roles: every page has full control (any --host)");
    cli.flag("--no-roles", so.no_roles, "the same on this machine; refused on another address without --open");
    cli.value("--viewer", so.server.viewer_dir, "the page's folder (default: $PLANT_VIEWER, else viewer/)", "DIR",
              "a folder");
    cli.value("--models", so.server.models.models_dir,
              "where glTF/GLB models are found first (then beside the plant,\nthen the standard library's models, "
              "stdlib/models)",
              "DIR", "a folder");
    cli.value("--threads", threads, "physics threads (as plant run)", "N");
    std::string steady;
    cli.value("--steady-transport", steady, "as plant run", "on|off");
    const CLI::Option* event_option =
        cli.values("--event", event, "a timed event, as plant run (repeatable; forces, hands too)", "\"5s PATH [VALUE]\"");
    const CLI::Option* events_option = cli.values("--events", events, "one such event per line", "FILE");
    std::vector<std::string> drill_files;
    cli.values("--drill", drill_files,
               "drills, one per line: at a time, now, or `when PATH >= N`;\nhidden or shown; `repaired by INPUT` "
               "(docs/training.md; repeatable)",
               "FILE");
    cli.value("--report-dir", so.report_dir,
              "when the session ends (Ctrl-C), write its report there:\nreport.md, report.html, session.events",
              "DIR", "a folder");
    CompileFlags cf;
    add_compile_flags(cli, cf);
    std::vector<std::unique_ptr<Part>> all = parts();
    bool links = false;
    for (auto& p : all) {
        p->add_flags(cli, Where::Serve);
        links = links || !p->link_name().empty();
    }
    if (links) cli.flag("--lockstep", lockstep, "(plant run's: a served plant runs paced by the wall clock)");
    std::vector<std::string> files;
    cli.positionals(files);
    if (const int code = cli.parse(args, std::cout, std::cerr); code >= 0) return code;
    if (const int code = check_compile_flags(cli, cf, std::cerr); code >= 0) return code;
    if (files.size() != 1)
        return cli.usage_error(std::cerr, "serve takes one FILE (.plant, .graph, or a recording with --replay)");
    double x = 0;
    if (!port.empty()) {
        if (!number(port, x) || x < 0 || x > 65535 || x != double(int(x)))
            return cli.usage_error(std::cerr, fmt::format("--port: '{}' is not a port number (0 to 65535)", port));
        so.server.port = uint16_t(x);
    }
    if (!speed.empty() && (!number(speed, so.speed) || (so.speed != 0 && (so.speed < 0.01 || so.speed > 1000))))
        return cli.usage_error(std::cerr, fmt::format("--speed: '{}' is not 0 (as fast as possible) or 0.01 to 1000", speed));
    if (!threads.empty()) {
        if (!number(threads, x) || x < 1 || x > 256 || x != double(int(x)))
            return cli.usage_error(std::cerr, fmt::format("--threads: '{}' is not a number of threads from 1 to 256", threads));
        so.engine.threads = int(x);
    }
    if (!steady.empty() && steady != "on" && steady != "off")
        return cli.usage_error(std::cerr, fmt::format("--steady-transport: '{}' is neither on nor off", steady));
    so.engine.steady_transport = steady != "off";
    if (lockstep)
        return cli.usage_error(std::cerr, "--lockstep: plant serve runs paced by the wall clock; lock-step is plant run's");
    std::string error;
    for (auto& p : all)
        if (!p->check(Where::Serve, error)) return cli.usage_error(std::cerr, error);
    const std::filesystem::path parent = std::filesystem::path(files[0]).parent_path();
    so.server.models.plant_dir = parent.empty() ? std::string(".") : parent.string();
    so.server.models.stdlib_dir = stdlib_of(cf);
    if (replay) {
        if (!cf.sets.empty()) return cli.usage_error(std::cerr, "--set does not apply to a replay");
        if (!event.empty() || !events.empty() || !drill_files.empty() || !so.report_dir.empty())
            return cli.usage_error(std::cerr, fmt::format("{} is for a live run, not a replay",
                                                          !event.empty()         ? "--event"
                                                          : !events.empty()      ? "--events"
                                                          : !drill_files.empty() ? "--drill"
                                                                                 : "--report-dir"));
        return view::serve_main(nullptr, files[0], std::move(so), std::cout, std::cerr);
    }
    graph::Graph g;
    int code = 0;
    if (!load_graph(cli, files[0], cf, g, code)) return code;
    // --event and --events in the order given, as plant run.
    engine::SlotIndex slots;
    size_t next_event = 0, next_file = 0;
    for (const CLI::Option* opt : cli.app().parse_order()) {
        if (opt != event_option && opt != events_option) continue;
        if (slots.empty()) slots = engine::slot_index(g);
        if (opt == events_option) {
            if (!engine::load_events(g, slots, events[next_file++], so.events, error)) return cli.usage_error(std::cerr, error);
            continue;
        }
        engine::Event ev;
        if (!engine::parse_event(g, slots, event[next_event++], ev, error))
            return cli.usage_error(std::cerr, "--event: " + error);
        so.events.push_back(std::move(ev));
    }
    for (const std::string& f : drill_files) {
        if (slots.empty()) slots = engine::slot_index(g);
        if (!faults::load_drills(g, slots, f, so.drills, error)) return cli.usage_error(std::cerr, "--drill: " + error);
    }
    const RunPlace place{parent.string(), stdlib_of(cf), "plant serve"};
    std::unique_ptr<engine::RunLink> link;
    for (auto& p : all) {
        if (p->link_name().empty() || !p->wanted(g)) continue;
        if (!(link = p->start(g, false, place, std::cerr, error))) {
            std::cerr << "plant serve: error: " << error << "\n";
            return 1;
        }
    }
    return view::serve_main(&g, files[0], std::move(so), std::cout, std::cerr, link.get());
}

}  // namespace

extern const Command kServeCommand{"serve", "run a plant paced to the wall clock and show it in the browser (3D, "
                                            "controls, inspector)", serve_command};

}  // namespace plant::app
