// plant_bench_opcua: what an OPC UA client subscribed to the plant costs the run.
//
// The bottling plant (one line, plants/bottling.plant) with an `opcua` link of 100 variables
// (its first 100 int, real, bool and void outputs by path) runs flat out with its server
// (node-opcua, a child process), once with no client and once with one client
// (bench/opcua_client.mjs, node-opcua-client in its own process) subscribed to all 100 at a
// sampling and publishing interval of 10 ms. The server gets every step's changes in both.
// The measured window is the wall time of the steps from simulated time `warmup` to
// `warmup + window`. The two cases run in pairs, in turns (bench/pairs.h): the ratio is the
// median of the pairs' ratios, step time with the client / step time without, and the same
// of the step thread's CPU time. Target <= 1.05.
//
//   plant_bench_opcua [--runs=3] [--warmup=60] [--window=240] [--rows]
#include "compiler.h"
#include "engine/engine.h"
#include "engine/events.h"
#include "opcua/kind.h"
#include "opcua/run_link.h"

#include "flags.h"
#include "pairs.h"
#include "panel/kind.h"

#include <signal.h>
#include <spawn.h>
#include <time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

extern char** environ;

namespace {

namespace fs = std::filesystem;
using plant::bench::Pairs;

struct Args {
    int runs = 3;
    double warmup = 60, window = 240;
    bool rows = false;
};

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }
// The step thread's own CPU time: what the steps cost it, apart from waiting for a core.
double cpu_now() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

[[noreturn]] void fail(const std::string& why) {
    std::fprintf(stderr, "opcua bench: %s\n", why.c_str());
    std::exit(1);
}

std::string read_file(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// plants/bottling.plant with an `opcua` component of 100 nodes, ns=2;i=1..100: its first
// int, real, bool and void outputs by path.
std::string plant_with_link(const plant::graph::Graph& g, const std::string& source) {
    using plant::graph::SlotType;
    const plant::engine::SlotIndex idx = plant::engine::slot_index(g);
    std::vector<std::string> all;
    for (const auto& [path, t] : idx)
        if (t.dir == plant::graph::Dir::Out && (t.type == SlotType::Int || t.type == SlotType::Real ||
                                               t.type == SlotType::Bool || t.type == SlotType::Void))
            all.push_back(path);
    std::sort(all.begin(), all.end());
    std::vector<std::string> paths;  // one per slot: a port and the slot it shows are one node
    std::set<std::vector<plant::graph::SlotId>> taken;
    for (const std::string& p : all)
        if (paths.size() < 100 && taken.insert(idx.at(p).slots).second) paths.push_back(p);
    std::string link = "    opcua bench {\n";
    for (size_t i = 0; i < paths.size(); ++i) link += "        node " + std::to_string(i + 1) + " => " + paths[i] + "\n";
    link += "    }\n}\n";
    const size_t end = source.rfind('}');
    if (end == std::string::npos) fail("plants/bottling.plant has no closing brace");
    return source.substr(0, end) + link;
}

struct Client {
    pid_t pid = -1;
    int in = -1, out = -1;  // its stdin (ours to close), its stdout
};

// Starts bench/opcua_client.mjs on `url` and waits for its "subscribed" line.
Client start_client(const std::string& url) {
    int to[2], from[2];
    if (pipe(to) != 0 || pipe(from) != 0) fail("pipe");
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, to[0], 0);
    posix_spawn_file_actions_adddup2(&fa, from[1], 1);
    posix_spawn_file_actions_addclose(&fa, to[1]);
    posix_spawn_file_actions_addclose(&fa, from[0]);
    const std::string script = PLANT_SOURCE_DIR "/bench/opcua_client.mjs";
    std::vector<std::string> argv_s = {"nice", "-n", "19", "node", script, url, "100"};
    std::vector<char*> argv;
    for (std::string& s : argv_s) argv.push_back(s.data());
    argv.push_back(nullptr);
    Client c;
    if (posix_spawnp(&c.pid, "nice", &fa, nullptr, argv.data(), environ) != 0) fail("cannot start node");
    posix_spawn_file_actions_destroy(&fa);
    close(to[0]);
    close(from[1]);
    c.in = to[1];
    c.out = from[0];
    std::string line;
    char ch = 0;
    while (read(c.out, &ch, 1) == 1 && ch != '\n') line += ch;
    if (line.rfind("subscribed ", 0) != 0) fail("the client did not subscribe: '" + line + "'");
    return c;
}

// Ends the client (its stdin closed); the notifications it counted.
long stop_client(Client& c) {
    close(c.in);
    std::string text;
    char buf[256];
    for (ssize_t n; (n = read(c.out, buf, sizeof buf)) > 0;) text.append(buf, size_t(n));
    close(c.out);
    int status = 0;
    waitpid(c.pid, &status, 0);
    const size_t at = text.find("notifications ");
    return at == std::string::npos ? -1 : std::atol(text.c_str() + at + 14);
}

// Wall seconds per simulated second over the window; the step thread's CPU seconds per
// simulated second; the client's notifications.
double measure(const plant::graph::Graph& g, const Args& a, bool with_client, double& cpu, long& notified) {
    plant::engine::Engine e(g);
    plant::opcua::LinkFlags flags;
    flags.port_given = true;  // port 0: a free one
    std::ostringstream said;
    std::string error;
    std::unique_ptr<plant::opcua::ServerLink> link = plant::opcua::start_link(g, flags, "", "bench", said, error);
    if (!link) fail(error);
    const std::string text = said.str();
    const size_t at = text.find("opc.tcp://");
    if (at == std::string::npos) fail("no endpoint in '" + text + "'");
    const std::string url = text.substr(at, text.find(' ', at) - at);
    Client client;
    if (with_client) client = start_client(url);
    auto step = [&] {
        link->before_step(e);
        e.step();
        link->after_step(e);
    };
    while (e.time() < a.warmup) step();
    const double t0 = now(), c0 = cpu_now(), s0 = e.time();
    while (e.time() < s0 + a.window) step();
    const double wall = now() - t0;
    cpu = (cpu_now() - c0) / (e.time() - s0);
    notified = with_client ? stop_client(client) : 0;
    return wall / (e.time() - s0);
}

}  // namespace

int main(int argc, char** argv) {
    plant::panel::register_panel_kinds();  // the bottling line's operator panel
    Args a;
    plant::bench::Flags f("plant_bench_opcua", "[FLAGS]",
                          "What one OPC UA client subscribed to 100 variables at 10 ms costs the bottling\n"
                          "plant's run, against the same run without it (bench/README.md).");
    f.pairs(a.runs, a.warmup, a.window, a.rows);
    if (const int code = f.parse(argc, argv); code >= 0) return code;
    signal(SIGPIPE, SIG_IGN);
    plant::opcua::register_opcua_kind();
    plant::CompileOptions opts;
    opts.stdlib_dir = PLANT_SOURCE_DIR "/stdlib";
    plant::Compilation plain;
    plant::compile_file(PLANT_SOURCE_DIR "/plants/bottling.plant", opts, plain);
    if (!plain.ok()) fail("the bottling plant does not compile");
    // The plant with its link, compiled from a file of its own (it imports only std).
    const fs::path dir = fs::temp_directory_path() / ("plant_bench_opcua." + std::to_string(getpid()));
    fs::create_directories(dir);
    const fs::path file = dir / "bottling_bench.plant";
    std::ofstream(file) << plant_with_link(plain.graph, read_file(PLANT_SOURCE_DIR "/plants/bottling.plant"));
    plant::Compilation c;
    plant::compile_file(file.string(), opts, c);
    fs::remove_all(dir);
    if (!c.ok()) fail("the bottling plant with its link does not compile: " + c.sink.all().front().message);
    Pairs wall, cpu;
    long notified = 0;
    for (int r = 0; r < a.runs; ++r) {
        long got = 0;
        double cpu_with = 0, cpu_without = 0;
        wall.run(r, [&](bool client) {
            long n = 0;
            const double t = measure(c.graph, a, client, client ? cpu_with : cpu_without, n);
            if (client) got = n;
            return t;
        });
        cpu.add(cpu_with, cpu_without);
        notified += got;
        std::fprintf(stderr, "opcua bench: pair %d: %.4f vs %.4f wall s, %.4f vs %.4f CPU s of the step thread per simulated s "
                     "(x%.3f, x%.3f; %ld notifications)\n", r + 1, wall.without.back(), wall.with.back(), cpu_without,
                     cpu_with, wall.ratios().back(), cpu.ratios().back(), got);
    }
    const double ratio = wall.ratio();
    const auto [lo, hi] = wall.range();
    if (!a.rows) std::printf("| area | case | measured | target | met |\n|---|---|---|---|---|\n");
    std::printf("| opcua link | step time, one OPC UA client subscribed to 100 variables at 10 ms / none (bottling, node-opcua "
                "server; %ld notifications; median of %d pair%s in turns, x%.3f to x%.3f; the step thread's CPU time x%.3f) "
                "| x%.3f | <= 1.05 | %s |\n",
                notified / a.runs, a.runs, a.runs == 1 ? "" : "s", lo, hi, cpu.ratio(), ratio, ratio <= 1.05 ? "yes" : "no");
    return 0;
}
