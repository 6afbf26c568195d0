// `plant sweep SPEC`: the command line, the checks before any run, and the local driver
// (-j N children at a time). Under mpirun it hands over to plant-sweep-mpi.
#include "sweep.h"

#include "app/cli.h"
#include "app/command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <thread>
#include <unistd.h>

namespace plant::sweep {

namespace {

constexpr const char* kAbout = R"(Runs the plant a sweep spec names once per combination of parameter values and
replicate, each run a child process (`plant run ... --quiet`), and writes, in --out:
  results.csv   a row per run: run, replicate, the values, the outputs, status,
                message, wall_s (rows appended as runs finish; sorted by run at the end)
  summary.md    a row per combination: the outputs' means over the replicates
  plot.gp, plot.dat, plot.svg
                one output over one or two varied parameters (gnuplot)
Every parameter name, value and unit is checked before the first run. A run that
fails (compile error, crash, time-out, NaN) is a row with its status; the sweep goes on.
While it runs it shows runs done of the total, how many were not ok and the time left
(one line on a terminal, a line every 10 s in a log). One sweep at a time in an --out
folder: another one there is refused while the first runs. Ctrl-C stops the runs going
on and says how many finished; --resume completes the sweep. When the plotted output is
the same in every run (a --for too short?) the sweep warns.)";
constexpr const char* kFooter = R"(Under mpirun (Open MPI), rank 0 hands runs out to the other ranks and writes the files.
The spec format and a worked example: docs/sweeps.md.
)";

// The sweep's command line, read into `o`; `jobs` and the times are checked after parsing.
struct SweepLine {
    app::Cli cli{"sweep", "SPEC [options]\n       mpirun -n N plant sweep SPEC [options]", kAbout, kFooter};
    std::string jobs, timeout;
    std::vector<std::string> specs;
    explicit SweepLine(Options& o) {
        cli.value("-j,--jobs", jobs, "runs at a time (default: one per core); the results do not depend on it", "N",
                  "a number");
        cli.value("--out", o.out_dir, "where the files go (default: sweep-NAME for SPEC NAME.sweep)", "DIR", "a DIR");
        cli.value("--for", o.run_for, "simulated time per run, instead of the spec's (e.g. 5s)", "TIME",
                  "a time (s, ms, min, h), e.g. --for 5s");
        cli.value("--timeout", timeout, "wall time per run before it is stopped (default: the spec's, else 600 s)", "T",
                  "a time, e.g. --timeout 60s");
        cli.flag("--resume", o.resume,
                 "keep the rows already in DIR/results.csv and run only the rest\n(runs marked lost, killed from "
                 "outside, run again)");
        cli.value("--stdlib", o.stdlib, "where `import std.x` looks", "DIR", "a DIR");
        cli.positionals(specs);
    }
};


std::string self_exe() {
    std::error_code ec;
    const auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
    return ec ? std::string() : p.string();
}

}  // namespace

int parse_options(const std::vector<std::string>& args, Options& o, std::ostream& out, std::ostream& err) {
    SweepLine l(o);
    if (const int code = l.cli.parse(args, out, err); code >= 0) return code;
    long n = 0;
    if (!l.jobs.empty() && !app::whole_number(l.jobs, 1, 1024, n))
        return l.cli.usage_error(err, "-j: '" + l.jobs + "' is not a number from 1 to 1024");
    o.jobs = int(n);
    double s = 0;
    if (!o.run_for.empty() && !parse_seconds(o.run_for, s))
        return l.cli.usage_error(err, "--for needs a time (s, ms, min, h), e.g. --for 5s");
    if (!l.timeout.empty() && !parse_seconds(l.timeout, o.timeout))
        return l.cli.usage_error(err, "--timeout needs a time, e.g. --timeout 60s");
    if (l.specs.size() > 1) return l.cli.usage_error(err, "sweep takes one SPEC");
    if (l.specs.empty()) return l.cli.usage_error(err, "sweep needs a SPEC file");
    o.spec_path = l.specs[0];
    return -1;
}

int prepare(const Options& o, Prepared& p, std::ostream& err) {
    std::vector<SpecError> errors;
    if (!load_spec(o.spec_path, p.spec, errors) || !check_spec(p.spec, o.stdlib, errors)) {
        err << render_errors(o.spec_path, errors);
        fmt::print(err, "plant sweep: {} error{} in the spec; no run started\n", errors.size(),
                   errors.size() == 1 ? "" : "s");
        return 1;
    }
    if (!o.run_for.empty()) p.spec.run_for = o.run_for;
    if (o.timeout > 0) p.spec.timeout = o.timeout;
    p.runs = expand(p.spec);
    namespace fs = std::filesystem;
    std::string dir = o.out_dir;
    if (dir.empty()) dir = "sweep-" + fs::path(o.spec_path).stem().string();
    std::error_code ec;
    fs::create_directories(fs::path(dir) / "work", ec);
    if (ec) {
        fmt::print(err, "plant sweep: error: cannot create '{}': {}\n", dir, ec.message());
        return 2;
    }
    // One sweep at a time in DIR, before anything in it is read or written.
    p.lock = std::make_unique<OutLock>();
    std::string lock_error, lock_note;
    if (!p.lock->acquire(dir, lock_error, lock_note)) {
        fmt::print(err, "plant sweep: error: {}\n", lock_error);
        return 2;
    }
    if (!lock_note.empty()) fmt::print(err, "plant sweep: {}\n", lock_note);
    // What a killed sweep left in the work folder is of no use: the folder is ours now.
    fs::remove_all(fs::path(dir) / "work", ec);
    fs::create_directories(fs::path(dir) / "work", ec);
    p.csv_path = dir + "/results.csv";
    if (fs::exists(p.csv_path) && !o.resume) {
        fmt::print(err, "plant sweep: error: {} exists: --resume to complete it, or another --out\n", p.csv_path);
        return 2;
    }
    std::map<int, std::string> rows, status;
    std::string error;
    if (!read_csv(p.csv_path, p.spec, rows, status, error)) {
        fmt::print(err, "plant sweep: error: {}\n", error);
        return 2;
    }
    for (const auto& [i, row] : rows)
        if (i >= 0 && size_t(i) < p.runs.size() && is_final(status[i])) {
            p.rows[i] = row;
            p.rows_not_ok += status[i] != "ok";
        }
    // Start the file again with the kept rows: a lost run's old row must not stay beside its new one.
    std::string text = csv_header(p.spec) + "\n";
    for (const auto& [i, row] : p.rows) text += row + "\n";
    if (!append_row(p.csv_path + ".tmp", text.substr(0, text.size() - 1)) ||
        std::rename((p.csv_path + ".tmp").c_str(), p.csv_path.c_str()) != 0) {
        fmt::print(err, "plant sweep: error: cannot write {}\n", p.csv_path);
        return 2;
    }
    return 0;
}

const char* signal_name(int sig) { return sig == SIGINT ? "Ctrl-C, SIGINT" : sig == SIGTERM ? "SIGTERM" : "a signal"; }

std::string interrupted_message(const Options& o, const Prepared& p, int signal) {
    size_t finished = 0;
    for (const auto& [i, row] : p.rows) finished += is_final(status_of(p.spec, row));
    auto arg = [](const std::string& a) {
        return a.find_first_of(" '\"$\\") == std::string::npos ? a : "'" + a + "'";
    };
    std::string again = "plant sweep " + arg(o.spec_path);
    if (!o.out_dir.empty()) again += " --out " + arg(o.out_dir);
    if (!o.run_for.empty()) again += " --for " + arg(o.run_for);
    if (o.timeout > 0) again += fmt::format(" --timeout {:g}s", o.timeout);
    again += " --resume";
    return fmt::format("plant sweep: interrupted ({}): {} of {} runs finished, in {}; `{}` runs the other {}\n",
                       signal_name(signal), finished, p.runs.size(), p.csv_path, again, p.runs.size() - finished);
}

int sweep_main(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
    Options o;
    if (const int code = parse_options(args, o, out, err); code >= 0) return code;  // --help: 0
    // Under mpirun: the MPI driver, a separate binary so that `plant` does not link libmpi.
    if (std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_RANK")) {
        const std::string mpi = (std::filesystem::path(self_exe()).parent_path() / "plant-sweep-mpi").string();
        std::vector<std::string> argv = {mpi};
        argv.insert(argv.end(), args.begin(), args.end());
        std::vector<char*> cargv;
        for (std::string& a : argv) cargv.push_back(a.data());
        cargv.push_back(nullptr);
        ::execv(mpi.c_str(), cargv.data());
        fmt::print(err, "plant sweep: error: under mpirun, but cannot run {} (built with Open MPI only)\n", mpi);
        return 2;
    }
    Prepared p;
    if (const int code = prepare(o, p, err)) return code;
    const std::string dir = std::filesystem::path(p.csv_path).parent_path().string();
    const int jobs = o.jobs > 0 ? o.jobs : int(std::max(1u, std::thread::hardware_concurrency()));
    Exec ex{self_exe(), dir + "/work", p.spec.run_for, p.spec.timeout};
    InterruptWatch watch;
    Pool pool(p.spec, ex);
    size_t next = 0;
    const size_t total = p.runs.size();
    fmt::print(err, "plant sweep: {} runs ({} done already), {} at a time\n", total, p.rows.size(), jobs);
    Progress progress(err, ::isatty(STDERR_FILENO) == 1, total, p.rows.size(), p.rows_not_ok);
    auto skip = [&] {
        while (next < total && p.rows.count(int(next))) ++next;
    };
    auto record = [&](const Result& r) {
        const std::string row = csv_row(p.spec, p.runs[size_t(r.index)], r);
        if (!append_row(p.csv_path, row)) {
            progress.clear();
            fmt::print(err, "plant sweep: error: cannot write {}\n", p.csv_path);
            return false;
        }
        p.rows[r.index] = row;
        return true;
    };
    skip();
    while (next < total || pool.busy() > 0) {
        while (next < total && pool.busy() < size_t(jobs) && !InterruptWatch::interrupted()) {
            std::string error;
            if (!pool.start(p.runs[next], error)) {
                progress.clear();
                fmt::print(err, "plant sweep: error: {}\n", error);
                return 1;
            }
            ++next;
            skip();
        }
        if (const int sig = InterruptWatch::interrupted()) {
            // The runs going on are stopped and written as lost: --resume runs them again.
            for (const Result& r : pool.stop_all(fmt::format("the sweep was interrupted ({})", signal_name(sig))))
                if (!record(r)) return 1;
            progress.end();
            std::error_code ec;
            std::filesystem::remove_all(dir + "/work", ec);
            err << interrupted_message(o, p, sig);
            return 128 + sig;
        }
        Result r;
        if (!pool.poll(r)) {
            progress.tick(pool.busy());
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
            continue;
        }
        if (!record(r)) return 1;
        if (r.status != "ok") {
            progress.clear();
            fmt::print(err, "plant sweep: run {}: {}: {}\n", r.index, r.status, r.message);
        }
        progress.finished(r.status == "ok", pool.busy());
    }
    progress.end();
    std::error_code ec;
    std::filesystem::remove(dir + "/work", ec);
    if (!finish_outputs(p.spec, dir, p.rows, err)) return 1;
    fmt::print(out, "{} runs, {} not ok; {}/results.csv, summary.md{}\n", total, progress.failed(), dir,
               p.spec.params.size() >= 1 && p.spec.params.size() <= 2 ? ", plot.svg" : "");
    return 0;
}

}  // namespace plant::sweep

namespace plant::app {

extern const Command kSweepCommand{"sweep", "many runs of a plant over parameter values, -j N or under mpirun; CSV, "
                                            "summary and plot",
                                   [](const std::vector<std::string>& args) {
                                       return sweep::sweep_main(args, std::cout, std::cerr);
                                   }};

}  // namespace plant::app
