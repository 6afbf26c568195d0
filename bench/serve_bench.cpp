// plant_bench_serve: what one page watching `plant serve` costs the run.
//
// For each number N of bottles in circulation the bottling plant is compiled with
// `lines = round(N / 12)` lines and run by the server's player as fast as possible (speed 0),
// once with no page and once with one page connected over loopback that asks for 30 frames
// a second and reads everything (a WebSocket client on its own thread). The measured window
// is the wall time the player takes from simulated time `warmup` to `warmup + window`
// (read from the published frames). The two cases run in pairs, in turns (bench/pairs.h): the
// ratio is the median of the pairs' ratios, step time with the page / step time without.
// Target <= 1.05.
//
//   plant_bench_serve [--counts=50,1000] [--runs=3] [--warmup=30] [--window=15] [--threads=N] [--fps=30] [--rows]
#include "compiler.h"
#include "serve/player.h"
#include "serve/server.h"

#include "flags.h"
#include "pairs.h"
#include "panel/kind.h"

#include <utility>  // before Boost 1.74's asio (std::exchange)

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

namespace {

using plant::bench::Pairs;

namespace beast = boost::beast;
namespace net = boost::asio;
using tcp = net::ip::tcp;

struct Args {
    std::vector<int> counts{50, 1000};
    int runs = 3;
    double warmup = 30, window = 15;
    int threads = 0;  // the engine's; 0: one per core, as `plant serve`
    int fps = 30;     // what the page asks for
    bool rows = false;
};

double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// One page: reads every message until told to stop; counts frames.
struct Page {
    std::atomic<bool> stop{false};
    std::atomic<long> frames{0};
    std::thread thread;
    void start(uint16_t port, int fps) {
        thread = std::thread([this, port, fps] {
            try {
                net::io_context ioc;
                beast::websocket::stream<tcp::socket> ws(ioc);
                ws.next_layer().connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
                ws.read_message_max(std::uint64_t(1) << 30);  // a large plant's scene is megabytes
                ws.handshake("127.0.0.1", "/ws");
                ws.write(net::buffer(R"({"type":"hello","fps":)" + std::to_string(fps) + "}"));
                beast::flat_buffer buf;
                while (!stop) {
                    ws.read(buf);
                    if (ws.got_binary()) ++frames;
                    buf.consume(buf.size());
                }
                beast::error_code ec;
                ws.next_layer().close(ec);
            } catch (const std::exception&) {
                // the server closed: the run is over
            }
        });
    }
};

// Wall seconds the player takes over the window; frames the page got in it.
double measure(const plant::graph::Graph& g, const Args& a, bool with_page, long& frames) {
    plant::engine::Options eo;
    eo.threads = a.threads;
    auto player = plant::view::make_live_player(g, eo, {}, false, 0);
    plant::view::ServerOptions so;
    so.port = 0;
    plant::view::Server server(*player, so);
    std::string error;
    if (!server.start(error)) {
        std::fprintf(stderr, "serve bench: %s\n", error.c_str());
        std::exit(1);
    }
    Page page;
    if (with_page) page.start(server.port(), a.fps);
    player->start();
    auto sim = [&] {
        auto f = player->frame();
        return f ? f->frame.time : 0.0;
    };
    while (sim() < a.warmup) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    const double t0 = now(), s0 = sim();
    const long f0 = page.frames;
    while (sim() < s0 + a.window) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    const double wall = now() - t0, simulated = sim() - s0;
    frames = page.frames - f0;
    player->stop();
    server.stop();
    page.stop = true;
    if (page.thread.joinable()) page.thread.join();
    return wall / simulated;  // wall seconds per simulated second
}

}  // namespace

int main(int argc, char** argv) {
    plant::panel::register_panel_kinds();  // the bottling line's operator panel
    Args a;
    plant::bench::Flags f("plant_bench_serve", "[FLAGS]",
                          "What one page watching `plant serve` costs the run: the bottling plant with a page\n"
                          "and without, in turns (bench/README.md).");
    f.wholes("--counts", a.counts, 1, 1000000, "bottles in circulation, one row each (default 50,1000)");
    f.pairs(a.runs, a.warmup, a.window, a.rows);  // pairs per count
    f.whole("--threads", a.threads, 1, 256, "threads for the plant (default: one per core)");
    f.whole("--fps", a.fps, 1, 240, "frames a second the page asks for (default 30)");
    if (const int code = f.parse(argc, argv); code >= 0) return code;
    if (!a.rows) {
        std::printf("| area | case | measured | target | met |\n|---|---|---|---|---|\n");
    }
    for (int n : a.counts) {
        const int lines = std::max(1, int(std::lround(n / 12.0)));
        plant::Compilation c;
        plant::CompileOptions opts;
        opts.stdlib_dir = PLANT_SOURCE_DIR "/stdlib";
        opts.overrides = {"lines=" + std::to_string(lines)};
        plant::compile_file(PLANT_SOURCE_DIR "/plants/bottling.plant", opts, c);
        if (!c.ok()) {
            std::fprintf(stderr, "serve bench: the bottling plant does not compile\n");
            return 1;
        }
        Pairs pairs;
        long frames = 0;
        double with_time = 0;
        for (int r = 0; r < a.runs; ++r) {
            std::fprintf(stderr, "serve bench: %d bottles, pair %d of %d\n", n, r + 1, a.runs);
            pairs.run(r, [&](bool page) {
                long f = 0;
                const double t = measure(c.graph, a, page, f);
                if (page) frames += f, with_time += t;
                return t;
            });
            std::fprintf(stderr, "serve bench: %.4f vs %.4f wall s per simulated s, x%.3f\n", pairs.without.back(),
                         pairs.with.back(), pairs.ratios().back());
        }
        const double ratio = pairs.ratio();
        const auto [lo, hi] = pairs.range();
        const double fps = double(frames) / (a.window * with_time);
        std::printf("| viewer | one page at %d frames/s, %d bottles in circulation (%d lines, as fast as possible) | "
                    "ratio %.3f (median of %d pair%s in turns, x%.3f to x%.3f; %.3f vs %.3f wall s per simulated s; the "
                    "page got %.1f frames/s) | <= 1.05 | %s |\n",
                    a.fps, n, lines, ratio, a.runs, a.runs == 1 ? "" : "s", lo, hi, plant::bench::median(pairs.with),
                    plant::bench::median(pairs.without), fps, ratio <= 1.05 ? "yes" : "**no**");
        std::fflush(stdout);
    }
    return 0;
}
