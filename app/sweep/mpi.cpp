// plant-sweep-mpi: `plant sweep` under mpirun (Open MPI). Rank 0 checks the spec, hands out
// run indices one at a time to whichever rank asks and writes every file; the other ranks
// run what they are given, each run a child process as in the local driver, and send back
// the CSV row. With one rank, rank 0 runs everything itself.
#include "sweep.h"

#include <mpi.h>
#ifdef PLANT_HAS_PANEL
#include "panel/kind.h"
#endif

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <thread>
#include <unistd.h>

using namespace plant::sweep;

namespace {

enum Tag { kResult = 1, kWork = 2, kStop = 3, kAlive = 4 };

// A worker says it is alive every second while a run goes on; one silent for 10 s has died
// (its process, or its node): its run is reported lost and the others go on. This needs
// mpirun to keep the job going after a rank dies: --mca orte_enable_recovery 1.
constexpr double kAliveEvery = 1.0, kDeadAfter = 10.0;

double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string plant_exe() {
    std::error_code ec;
    const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
    return (self.parent_path() / "plant").string();
}

// One run in a child process, as the local driver does with -j 1; a worker tells rank 0
// it is alive while the run goes on. Rank 0 alone (-n 1) stops it on Ctrl-C: a lost run.
Result run_one(const Spec& spec, const Run& run, const std::string& work, bool heartbeat) {
    Pool pool(spec, Exec{plant_exe(), work, spec.run_for, spec.timeout});
    std::string error;
    Result r;
    if (!pool.start(run, error)) {
        r.index = run.index;
        r.status = "failed";
        r.message = error;
        r.outputs.assign(spec.outputs.size(), "");
        return r;
    }
    double next = now() + kAliveEvery;
    while (!pool.poll(r)) {
        if (const int sig = InterruptWatch::interrupted(); sig && !heartbeat)
            return pool.stop_all(fmt::format("the sweep was interrupted ({})", signal_name(sig))).at(0);
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        if (heartbeat && now() >= next) {
            MPI_Send(nullptr, 0, MPI_CHAR, 0, kAlive, MPI_COMM_WORLD);
            next = now() + kAliveEvery;
        }
    }
    return r;
}

// Ctrl-C (or mpirun's SIGTERM): every finished row is in results.csv; say so and how to go on.
[[noreturn]] void interrupted(const Options& o, Prepared& p, Progress& progress, int sig) {
    progress.end();
    std::error_code ec;
    std::filesystem::remove_all(std::filesystem::path(p.csv_path).parent_path() / "work", ec);
    p.lock.reset();  // MPI_Abort runs no destructor
    std::cerr << interrupted_message(o, p, sig) << std::flush;
    MPI_Abort(MPI_COMM_WORLD, 128 + sig);
    std::_Exit(128 + sig);
}

int coordinator(const Options& o, Prepared& p, int size) {
    const std::string dir = std::filesystem::path(p.csv_path).parent_path().string();
    std::vector<int> todo;
    for (const Run& r : p.runs)
        if (!p.rows.count(r.index)) todo.push_back(r.index);
    fmt::print(std::cerr, "plant sweep: {} runs ({} done already) on {} MPI rank{}\n", p.runs.size(),
               p.runs.size() - todo.size(), size > 1 ? size - 1 : 1, size > 2 ? "s" : "");
    InterruptWatch watch;
    Progress progress(std::cerr, ::isatty(STDERR_FILENO) == 1, p.runs.size(), p.rows.size(), p.rows_not_ok);
    size_t next = 0;
    int dead = 0, running = 0;
    auto record = [&](const std::string& row, int index, const std::string& status) {
        if (!append_row(p.csv_path, row)) fmt::print(std::cerr, "plant sweep: error: cannot write {}\n", p.csv_path);
        p.rows[index] = row;
        if (status == "lost" && InterruptWatch::interrupted()) return;  // not finished: --resume runs it
        progress.finished(status == "ok", std::max(0, running));
    };
    if (size == 1) {
        for (int i : todo) {
            const Result r = run_one(p.spec, p.runs[i], dir + "/work", false);
            record(csv_row(p.spec, p.runs[i], r), i, r.status);
            if (const int sig = InterruptWatch::interrupted()) interrupted(o, p, progress, sig);
        }
    } else {
        int stopped = 0;
        std::vector<int> current(size, -1);  // the run each rank has
        std::vector<double> heard(size, now());
        std::vector<bool> done(size, false);
        while (stopped < size - 1) {
            int flag = 0;
            MPI_Status st;
            MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
            if (const int sig = InterruptWatch::interrupted()) {
                // The ranks' runs are lost (mpirun stops the ranks): --resume runs them again.
                for (int k = 1; k < size; ++k) {
                    const int i = current[k];
                    if (done[k] || i < 0) continue;
                    Result r;
                    r.index = i;
                    r.status = "lost";
                    r.message = fmt::format("the sweep was interrupted ({})", signal_name(sig));
                    r.outputs.assign(p.spec.outputs.size(), "");
                    record(csv_row(p.spec, p.runs[i], r), i, r.status);
                }
                interrupted(o, p, progress, sig);
            }
            if (!flag) {
                // A blocking receive would spin a core that the runs need.
                progress.tick(running);
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
                for (int k = 1; k < size; ++k) {
                    if (done[k] || now() - heard[k] < kDeadAfter) continue;
                    done[k] = true;
                    ++stopped;
                    ++dead;
                    const int i = current[k];
                    fmt::print(std::cerr, "plant sweep: MPI rank {} stopped answering{}\n", k,
                               i >= 0 ? fmt::format("; its run {} is lost", i) : "");
                    if (i < 0) continue;
                    --running;
                    Result r;
                    r.index = i;
                    r.status = "lost";
                    r.message = fmt::format("MPI rank {} died during the run", k);
                    r.outputs.assign(p.spec.outputs.size(), "");
                    record(csv_row(p.spec, p.runs[i], r), i, r.status);
                }
                continue;
            }
            const int src = st.MPI_SOURCE;
            heard[src] = now();
            if (st.MPI_TAG == kAlive) {
                MPI_Recv(nullptr, 0, MPI_CHAR, src, kAlive, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
                continue;
            }
            int len = 0;
            MPI_Get_count(&st, MPI_CHAR, &len);
            std::string msg(len, '\0');
            MPI_Recv(msg.data(), len, MPI_CHAR, src, kResult, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            if (done[src]) continue;  // declared dead, yet it answered: its run is in the CSV as lost
            if (!msg.empty()) {
                // "STATUS\nROW"
                const size_t nl = msg.find('\n');
                --running;
                record(msg.substr(nl + 1), current[src], msg.substr(0, nl));
            }
            if (next < todo.size()) {
                ++running;
                current[src] = todo[next++];
                MPI_Send(&current[src], 1, MPI_INT, src, kWork, MPI_COMM_WORLD);
            } else {
                current[src] = -1;
                MPI_Send(nullptr, 0, MPI_INT, src, kStop, MPI_COMM_WORLD);
                done[src] = true;
                ++stopped;
            }
        }
    }
    progress.end();
    std::error_code ec;
    std::filesystem::remove(dir + "/work", ec);
    if (!finish_outputs(p.spec, dir, p.rows, std::cerr)) return 1;
    fmt::print(std::cout, "{} runs, {} not ok; {}/results.csv, summary.md{}\n", p.runs.size(), progress.failed(), dir,
               p.spec.params.size() >= 1 && p.spec.params.size() <= 2 ? ", plot.svg" : "");
    if (dead > 0) {
        // MPI_Finalize would wait for the dead rank: the files are written, end the job here.
        fmt::print(std::cerr, "plant sweep: {} MPI rank{} died; --resume runs the lost run{} again\n", dead,
                   dead == 1 ? "" : "s", dead == 1 ? "" : "s");
        std::cout.flush();
        MPI_Abort(MPI_COMM_WORLD, 3);
    }
    return 0;
}

int worker(const Options& o, int rank) {
    Spec spec;
    std::vector<SpecError> errors;
    if (!load_spec(o.spec_path, spec, errors)) return 1;  // rank 0 has read it: cannot happen on a shared disk
    if (!o.run_for.empty()) spec.run_for = o.run_for;
    if (o.timeout > 0) spec.timeout = o.timeout;
    const std::vector<Run> runs = expand(spec);
    // A work folder of this rank's own on its machine's disk.
    const char* tmp = std::getenv("TMPDIR");
    const std::string work = fmt::format("{}/plant-sweep-{}-{}", tmp ? tmp : "/tmp", ::getpid(), rank);
    std::filesystem::create_directories(work);
    std::string msg;  // empty: the first request
    for (;;) {
        MPI_Send(msg.data(), int(msg.size()), MPI_CHAR, 0, kResult, MPI_COMM_WORLD);
        MPI_Status st;
        int index = -1;
        MPI_Recv(&index, 1, MPI_INT, 0, MPI_ANY_TAG, MPI_COMM_WORLD, &st);
        if (st.MPI_TAG == kStop) break;
        const Run& run = runs.at(index);
        const Result r = run_one(spec, run, work, true);
        msg = r.status + "\n" + csv_row(spec, run, r);
    }
    std::error_code ec;
    std::filesystem::remove_all(work, ec);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
#ifdef PLANT_HAS_PANEL
    plant::panel::register_panel_kinds();  // the plugin kinds the plants it sweeps use (docs/architecture.md)
#endif
    MPI_Init(&argc, &argv);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    const std::vector<std::string> args(argv + 1, argv + argc);
    Options o;
    std::ostringstream quiet;  // the other ranks would only repeat rank 0's usage errors
    int code = parse_options(args, o, rank == 0 ? static_cast<std::ostream&>(std::cout) : quiet,
                             rank == 0 ? static_cast<std::ostream&>(std::cerr) : quiet);
    if (code >= 0) {  // --help (0) or a usage error: every rank read the same arguments
        MPI_Finalize();
        return code;
    }
    code = 0;
    Prepared p;
    if (code == 0 && rank == 0) code = prepare(o, p, std::cerr);
    // Every rank learns whether rank 0 found the spec good.
    MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (code == 0) code = rank == 0 ? coordinator(o, p, size) : worker(o, rank);
    MPI_Finalize();
    return code;
}
