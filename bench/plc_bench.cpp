// plant_bench_plc: what a PLC polling the Modbus link costs the run.
//
// The bottling plant (one line) runs flat out with the link's server on a map of 100 input
// registers (its first 100 int, real, bool and void outputs by path), once with no client
// and once with one libmodbus client on its own thread reading all 100 registers every
// 10 ms of wall time over loopback. The measured window is the wall time of the steps from
// simulated time `warmup` to `warmup + window` (one line runs ~100x real time, so the
// window is long enough for a few hundred reads). The two cases run in pairs, in turns
// (bench/pairs.h): the ratio is the median of the pairs' ratios, step time with the client /
// step time without. Target <= 1.05.
//
//   plant_bench_plc [--runs=3] [--warmup=60] [--window=240] [--rows]
#include "compiler.h"
#include "engine/engine.h"
#include "engine/events.h"
#include "plc/server.h"

#include "flags.h"
#include "pairs.h"
#include "panel/kind.h"

#include <modbus/modbus.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

namespace {

using plant::bench::Pairs;

struct Args {
    int runs = 3;
    double warmup = 60, window = 240;
    bool rows = false;
};

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

// 100 input registers: the plant's first int, real, bool and void outputs by path.
plant::plc::Map hundred_registers(const plant::graph::Graph& g) {
    using plant::graph::SlotType;
    using plant::plc::Encoding;
    const plant::engine::SlotIndex idx = plant::engine::slot_index(g);
    std::vector<std::string> paths;
    for (const auto& [path, t] : idx)
        if (t.dir == plant::graph::Dir::Out && (t.type == SlotType::Int || t.type == SlotType::Real ||
                                               t.type == SlotType::Bool || t.type == SlotType::Void))
            paths.push_back(path);
    std::sort(paths.begin(), paths.end());
    plant::plc::Map m;
    for (const std::string& p : paths) {
        if (m.entries.size() == 100) break;
        const SlotType type = idx.at(p).type;
        const Encoding enc = type == SlotType::Int ? Encoding::Int16 : type == SlotType::Real ? Encoding::Scaled
                             : type == SlotType::Bool ? Encoding::Bit : Encoding::Count;
        plant::plc::Entry e;
        std::string error;
        plant::plc::make_entry(idx, {plant::plc::Table::InputRegister, int32_t(m.entries.size()), p, enc, 1000}, e, error);
        m.entries.push_back(e);
    }
    return m;
}

// Wall seconds per simulated second over the window; the client's reads in it.
double measure(const plant::graph::Graph& g, const plant::plc::Map& map, const Args& a, bool with_client, long& reads) {
    plant::engine::Engine e(g);
    plant::plc::Server server(g, map);
    std::string error;
    if (!server.start(error)) {
        std::fprintf(stderr, "plc bench: %s\n", error.c_str());
        std::exit(1);
    }
    std::atomic<bool> stop{false};
    std::atomic<long> count{0};
    std::thread client;
    if (with_client)
        client = std::thread([&] {
            modbus_t* ctx = modbus_new_tcp("127.0.0.1", server.port());
            if (!ctx || modbus_connect(ctx) != 0) {
                std::fprintf(stderr, "plc bench: cannot connect\n");
                std::exit(1);
            }
            uint16_t regs[100];
            double next = now();
            while (!stop) {
                if (modbus_read_input_registers(ctx, 0, 100, regs) == 100) ++count;
                next += 0.010;
                const double wait = next - now();
                if (wait > 0) std::this_thread::sleep_for(std::chrono::duration<double>(wait));
            }
            modbus_close(ctx);
            modbus_free(ctx);
        });
    auto step = [&] {
        server.before_step(e);
        e.step();
        server.after_step(e);
    };
    while (e.time() < a.warmup) step();
    const double t0 = now(), s0 = e.time();
    const long r0 = count;
    while (e.time() < s0 + a.window) step();
    const double wall = now() - t0;
    reads = count - r0;
    stop = true;
    if (client.joinable()) client.join();
    return wall / (e.time() - s0);
}

}  // namespace

int main(int argc, char** argv) {
    plant::panel::register_panel_kinds();  // the bottling line's operator panel
    Args a;
    plant::bench::Flags f("plant_bench_plc", "[FLAGS]",
                          "What one Modbus client polling 100 registers every 10 ms costs the bottling\n"
                          "plant's run, against the same run without it (bench/README.md).");
    f.pairs(a.runs, a.warmup, a.window, a.rows);
    if (const int code = f.parse(argc, argv); code >= 0) return code;
    plant::Compilation c;
    plant::CompileOptions opts;
    opts.stdlib_dir = PLANT_SOURCE_DIR "/stdlib";
    plant::compile_file(PLANT_SOURCE_DIR "/plants/bottling.plant", opts, c);
    if (!c.ok()) {
        std::fprintf(stderr, "plc bench: the bottling plant does not compile\n");
        return 1;
    }
    const plant::plc::Map map = hundred_registers(c.graph);
    Pairs pairs;
    long reads = 0;
    for (int r = 0; r < a.runs; ++r) {
        long got = 0;
        pairs.run(r, [&](bool client) {
            long n = 0;
            const double t = measure(c.graph, map, a, client, n);
            if (client) got = n;
            return t;
        });
        reads += got;
        std::fprintf(stderr, "plc bench: pair %d: %.4f vs %.4f wall s per simulated s, x%.3f (%ld reads)\n", r + 1,
                     pairs.without.back(), pairs.with.back(), pairs.ratios().back(), got);
    }
    const double ratio = pairs.ratio();
    const auto [lo, hi] = pairs.range();
    if (!a.rows) std::printf("| area | case | measured | target | met |\n|---|---|---|---|---|\n");
    std::printf("| plc link | step time, one Modbus client reading 100 registers every 10 ms / none (bottling, %zu entries; "
                "%ld reads; median of %d pair%s in turns, x%.3f to x%.3f) | x%.3f | <= 1.05 | %s |\n",
                map.entries.size(), reads / a.runs, a.runs, a.runs == 1 ? "" : "s", lo, hi, ratio,
                ratio <= 1.05 ? "yes" : "no");
    return 0;
}
