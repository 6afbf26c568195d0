#include "serve/serve.h"

#include "serve/player.h"
#include "serve/report.h"
#include "serve/roles.h"
#include "serve/server.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <charconv>
#include <cstdlib>
#include <filesystem>
#include <ostream>

namespace plant::view {

namespace fs = std::filesystem;

std::string default_viewer_dir() {
    if (const char* env = std::getenv("PLANT_VIEWER"); env && *env) return env;
    return PLANT_VIEWER_DIR;
}

int serve_main(const graph::Graph* graph, const std::string& file, ServeOptions options, std::ostream& out,
               std::ostream& err, engine::RunLink* link) {
    ServerOptions& so = options.server;
    const bool paused = options.paused;
    const double speed = options.speed;
    auto fail = [&](const std::string& msg) {
        fmt::print(err, "plant serve: error: {}\n", msg);
        return 2;
    };
    // Roles (docs/viewer.md, "Roles"): on unless --open (or --no-roles, on this machine only).
    if (so.tls_cert.empty() != so.tls_key.empty())
        return fail(so.tls_cert.empty() ? "--tls-key needs --tls-cert too" : "--tls-cert needs --tls-key too");
    const bool loopback = loopback_host(so.host);
    if (options.no_roles && !loopback && !so.open)
        return fail(fmt::format("--no-roles on {} would give everyone who reaches it full control of the plant (forces "
                                "included); say --open as well if that is what you want, or leave roles on",
                                so.host));
    if (options.no_roles) so.open = true;
    if (!so.open) {
        std::string error;
        so.token = make_token(error);
        if (so.token.empty()) {
            fmt::print(err, "plant serve: error: {}\n", error);
            return 1;
        }
    }
    std::error_code ec;
    if (!fs::is_regular_file(fs::path(so.viewer_dir) / "index.html", ec))
        fmt::print(err, "plant serve: warning: no viewer page in '{}' (--viewer DIR); the server runs without it\n",
                   so.viewer_dir);
    else if (!fs::is_directory(fs::path(so.viewer_dir) / "node_modules" / "three", ec))
        fmt::print(err, "plant serve: warning: the page's packages are not installed: run `scripts/setup.sh` (npm ci in {})\n",
                   so.viewer_dir);

    if (std::error_code dir_ec; !so.models.models_dir.empty() && !fs::is_directory(so.models.models_dir, dir_ec))
        return fail(fmt::format("--models: '{}' is not a folder", so.models.models_dir));
    // Models that will not be shown: said once here, and on the page.
    if (graph)
        for (const ModelProblem& p : model_problems(*graph, so.models))
            fmt::print(err, "plant serve: model {}: {}; the page draws the body's shapes instead\n", p.model, p.problem);

    std::unique_ptr<Player> player;
    if (graph) {
        player = make_live_player(*graph, options.engine, so.models, paused, speed, std::move(options.events), link,
                                  std::move(options.drills));
    } else {
        Recording rec;
        std::string error;
        if (!load_recording(file, rec, error)) {
            fmt::print(err, "plant serve: error: {}\n", error);
            return 1;
        }
        player = make_replay_player(std::move(rec), paused, speed);
    }
    if (!options.report_dir.empty() && !graph) return fail("--report-dir: a replay has no session to report");
    so.plant_file = file;
    Server server(*player, so);
    std::string error;
    if (!server.start(error)) {
        fmt::print(err, "plant serve: error: {}\n", error);
        return 1;
    }
    player->start();
    const bool v6 = so.host.find(':') != std::string::npos;
    const std::string base = fmt::format("{}://{}{}{}:{}/", so.tls_cert.empty() ? "http" : "https", v6 ? "[" : "",
                                         so.host, v6 ? "]" : "", server.port());
    // The first line as before roles: the page (on this machine, the instructor's).
    fmt::print(out, "plant serve: {}\n", base);
    if (so.open) {
        fmt::print(out, "plant serve: open: every page has full control (no roles)\n");
    } else {
        fmt::print(out, "plant serve: instructor: {}?token={}\n", base, so.token);
        fmt::print(out, "plant serve: trainees: {}?role=trainee\n", base);
    }
    if (!loopback && so.tls_cert.empty())
        fmt::print(err, "plant serve: warning: {} is reachable from the network without TLS: the instructor's token "
                        "travels in clear (--tls-cert, --tls-key)\n", so.host);
    out.flush();
    server.wait_for_signal();
    fmt::print(out, "plant serve: stopped\n");
    server.stop();
    player->stop();
    if (options.report_dir.empty()) return 0;
    // The session's report, from its events replayed headless (docs/training.md).
    if (const auto f = player->frame(); !f || f->frame.time <= 0) {
        fmt::print(out, "plant serve: no report: the session ended before its first step\n");
        return 0;
    }
    const std::string text = player->events_file();
    Session session;
    if (!replay_session_text(*graph, file, "session.events", text, 0, session, error) ||
        !write_report(session, text, options.report_dir, error)) {
        fmt::print(err, "plant serve: error: the session report: {}\n", error);
        return 1;
    }
    fmt::print(out, "plant serve: report: {0}/report.md, {0}/report.html, {0}/session.events ({1} faults, {2} events, "
                    "{3} s of plant time)\n",
               options.report_dir, session.faults.size(), session.events.size(), engine::time_text(session.end, session.dt));
    return 0;
}

}  // namespace plant::view
