#include "serve/serve.h"

#include "serve/player.h"
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

namespace {

bool number(const std::string& text, double& v) {
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    return ec == std::errc() && end == text.data() + text.size() && std::isfinite(v);
}

}  // namespace

int serve_main(const graph::Graph* graph, const std::string& file, const std::vector<std::string>& args,
               std::ostream& out, std::ostream& err, engine::RunLink* link, const std::string& stdlib_dir) {
    ServerOptions so;
    so.viewer_dir = default_viewer_dir();
    const fs::path parent = fs::path(file).parent_path();
    so.models.plant_dir = parent.empty() ? fs::path(".").string() : parent.string();
    so.models.stdlib_dir = stdlib_dir;
    std::vector<engine::Event> scheduled;
    engine::SlotIndex slots;
    engine::Options eo;
    bool paused = false, no_roles = false;
    double speed = 1;
    auto fail = [&](const std::string& msg) {
        fmt::print(err, "plant serve: error: {}\n", msg);
        return 2;
    };
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&](std::string& v) {
            if (i + 1 >= args.size()) return false;
            v = args[++i];
            return true;
        };
        std::string v;
        double x = 0;
        if (a == "--paused") paused = true;
        else if (a == "--open") so.open = true;
        else if (a == "--no-roles") no_roles = true;
        else if (a == "--tls-cert") {
            if (!value(so.tls_cert)) return fail("--tls-cert needs a file (PEM)");
        } else if (a == "--tls-key") {
            if (!value(so.tls_key)) return fail("--tls-key needs a file (PEM)");
        }
        else if (a == "--replay") continue;  // the driver already chose a replay
        else if (a == "--port") {
            if (!value(v) || !number(v, x) || x < 0 || x > 65535 || x != double(int(x)))
                return fail(fmt::format("--port: '{}' is not a port number (0 to 65535)", v));
            so.port = uint16_t(x);
        } else if (a == "--host") {
            if (!value(so.host)) return fail("--host needs an address");
        } else if (a == "--viewer") {
            if (!value(so.viewer_dir)) return fail("--viewer needs a folder");
        } else if (a == "--models") {
            if (!value(so.models.models_dir)) return fail("--models needs a folder");
        } else if (a == "--speed") {
            if (!value(v) || !number(v, speed) || (speed != 0 && (speed < 0.01 || speed > 1000)))
                return fail(fmt::format("--speed: '{}' is not 0 (as fast as possible) or 0.01 to 1000", v));
        } else if (a == "--event" || a == "--events") {
            if (!graph) return fail(fmt::format("{} is for a live run, not a replay", a));
            if (!value(v)) return fail(fmt::format("{} needs a value", a));
            if (slots.empty()) slots = engine::slot_index(*graph);
            std::string error;
            if (a == "--events") {
                if (!engine::load_events(*graph, slots, v, scheduled, error)) return fail(error);
            } else {
                engine::Event ev;
                if (!engine::parse_event(*graph, slots, v, ev, error)) return fail("--event: " + error);
                scheduled.push_back(std::move(ev));
            }
        } else if (a == "--threads") {
            if (!value(v) || !number(v, x) || x < 1 || x > 256 || x != double(int(x)))
                return fail(fmt::format("--threads: '{}' is not a number of threads from 1 to 256", v));
            eo.threads = int(x);
        } else if (a == "--steady-transport") {
            if (!value(v) || (v != "on" && v != "off"))
                return fail(fmt::format("--steady-transport: '{}' is neither on nor off", v));
            eo.steady_transport = v == "on";
        } else {
            return fail(fmt::format("unknown flag '{}' (see plant serve --help)", a));
        }
    }
    // Roles (docs/viewer.md, "Roles"): on unless --open (or --no-roles, on this machine only).
    if (so.tls_cert.empty() != so.tls_key.empty())
        return fail(so.tls_cert.empty() ? "--tls-key needs --tls-cert too" : "--tls-cert needs --tls-key too");
    const bool loopback = loopback_host(so.host);
    if (no_roles && !loopback && !so.open)
        return fail(fmt::format("--no-roles on {} would give everyone who reaches it full control of the plant (forces "
                                "included); say --open as well if that is what you want, or leave roles on",
                                so.host));
    if (no_roles) so.open = true;
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
        player = make_live_player(*graph, eo, so.models, paused, speed, std::move(scheduled), link);
    } else {
        Recording rec;
        std::string error;
        if (!load_recording(file, rec, error)) {
            fmt::print(err, "plant serve: error: {}\n", error);
            return 1;
        }
        player = make_replay_player(std::move(rec), paused, speed);
    }
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
    return 0;
}

}  // namespace plant::view
