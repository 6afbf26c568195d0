#include "serve/serve.h"

#include "serve/player.h"
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
        player = make_live_player(*graph, options.engine, so.models, paused, speed, std::move(options.events), link);
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
    fmt::print(out, "plant serve: http://{}{}{}:{}/\n", v6 ? "[" : "", so.host, v6 ? "]" : "", server.port());
    out.flush();
    server.wait_for_signal();
    fmt::print(out, "plant serve: stopped\n");
    server.stop();
    player->stop();
    return 0;
}

}  // namespace plant::view
