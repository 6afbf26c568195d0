// `plant sweep SPEC`: many runs of one plant, each a child process `plant run ... --quiet`.
// The spec (YAML) is read into a Spec, checked against the plant once in-process, expanded
// into numbered runs; results are CSV rows, written as they come, then a summary and a plot.
// The local driver (sweep_main, -j N) and the MPI one (plant-sweep-mpi) share all of this.
#pragma once

#include <iosfwd>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace plant::sweep {

struct Loc {
    int line = 0, col = 0;  // 1-based; 0: the file as a whole
};

struct Value {
    std::string text;  // an expression with its unit, as `--set` takes it: "30 cm/s"
    Loc loc;
};

struct Param {
    std::string name;
    Loc loc;
    std::vector<Value> values;
};

// One output column: a summary counter, or a record's total or rate (per minute).
struct Output {
    enum Kind { Counter, Total, Rate } kind = Counter;
    std::string name;  // counter: issued, commissioned, on_line, lost, stalled, rtf; else the record
    Loc loc;
    std::string column() const;  // CSV header: "issued", "total:filled", "rate:filled"
};

struct Spec {
    std::string path;   // the spec file
    std::string plant;  // the plant file, relative to the spec's folder resolved
    Loc plant_loc;
    std::string run_for = "10 s";  // simulated time per run
    Loc for_loc;
    std::vector<Param> params;
    int replicates = 1;
    std::string perturb;  // replicate r > 0 adds r * perturb_by to this parameter
    std::string perturb_by;
    Loc perturb_loc, perturb_by_loc;
    std::vector<Output> outputs;
    double timeout = 600;  // wall seconds per run
    std::string plot;      // the column plotted (default: the first output that is not rtf)
    Loc plot_loc;
};

struct SpecError {
    Loc loc;
    std::string message;
};

// Parses the spec; false with located errors (never throws).
bool load_spec(const std::string& path, Spec& out, std::vector<SpecError>& errors);
// Compiles the plant once per distinct value (in-process): names, types and units of the
// parameters, the records named by outputs. False with errors located in the spec.
bool check_spec(const Spec& spec, const std::string& stdlib, std::vector<SpecError>& errors);
// "spec:3:5: error: ..." with the source line and a caret, one per error.
std::string render_errors(const std::string& path, const std::vector<SpecError>& errors);

// A number with an optional unit, as written: "1500 ms" -> (1500, "ms"). False if no number.
bool split_quantity(const std::string& text, double& number, std::string& unit);
// Seconds from "300 s", "2 min", "500 ms", "1 h"; false if not a time.
bool parse_seconds(const std::string& text, double& seconds);

struct Run {
    int index = 0;
    int replicate = 0;
    std::vector<std::string> values;  // one per parameter, as in the CSV
    std::vector<std::string> sets;    // NAME=VALUE for `plant run --set`
};
std::vector<Run> expand(const Spec& spec);

struct Result {
    int index = 0;
    std::string status;  // ok, nan, compile_error, failed, crashed, timeout, lost
    std::string message;
    std::vector<std::string> outputs;  // one per spec output ("" when the run failed)
    double wall = 0;
};

// Statuses kept by --resume; a `lost` run (killed from outside) is run again.
bool is_final(const std::string& status);

// The values of the summary `plant run --summary=json` prints: counters and records by name.
struct Summary {
    std::map<std::string, double> counters;
    std::map<std::string, double> totals, rates;
    bool nan = false;
};
bool parse_summary(const std::string& text, Summary& out);

struct Exec {
    std::string plant_exe;  // the `plant` binary
    std::string work_dir;   // where a child's stdout/stderr files go
    std::string run_for;    // --for
    double timeout = 600;
};

// Runs several children at once: start() forks, poll() reaps one that ended and turns its
// output into a Result. Timeouts are enforced while polling.
class Pool {
public:
    Pool(const Spec& spec, Exec exec) : spec_(spec), exec_(std::move(exec)) {}
    ~Pool();
    bool start(const Run& run, std::string& error);
    size_t busy() const { return children_.size(); }
    // Without blocking: true with the Result of a child that has ended.
    bool poll(Result& r);
    // Stops every running child (SIGKILL); each becomes a `lost` Result with `why`.
    std::vector<Result> stop_all(const std::string& why);

private:
    struct Child {
        int pid;
        int index;
        double started;
        bool timed_out;
    };
    Result finish(const Child& c, int status);
    const Spec& spec_;
    Exec exec_;
    std::vector<Child> children_;
};

// The CSV: header, a row per result (values of the run, then outputs, status, message, wall).
std::string csv_header(const Spec& spec);
std::string csv_row(const Spec& spec, const Run& run, const Result& r);
// A row's status column ("" when the row is cut short).
std::string status_of(const Spec& spec, const std::string& row);
// Rows of an existing CSV by run index (header checked); false with a message.
bool read_csv(const std::string& path, const Spec& spec, std::map<int, std::string>& rows,
              std::map<int, std::string>& status, std::string& error);
// Rewrites the CSV sorted by run index; summary.md; plot.gp/plot.dat (+ plot.svg via gnuplot).
bool finish_outputs(const Spec& spec, const std::string& dir, const std::map<int, std::string>& rows,
                    std::ostream& err);

// The command line shared by both drivers.
struct Options {
    std::string spec_path, out_dir, run_for, stdlib;
    int jobs = 0;  // 0: one per core
    bool resume = false;
    double timeout = 0;  // 0: the spec's
};
// -1 to go on; else the exit code, with --help printed on `out` (0) or the error on `err`.
int parse_options(const std::vector<std::string>& args, Options& o, std::ostream& out, std::ostream& err);

// The --out folder's lock (DIR/.lock, flock(2)): held while a sweep runs there, released by
// the kernel however the sweep ends; a lock file left by a killed sweep is taken over.
class OutLock {
public:
    OutLock() = default;
    ~OutLock();
    OutLock(const OutLock&) = delete;
    OutLock& operator=(const OutLock&) = delete;
    // False with `error` when another live sweep holds DIR; `note` says when a killed
    // sweep's lock was taken over.
    bool acquire(const std::string& dir, std::string& error, std::string& note);

private:
    int fd_ = -1;
    std::string path_;
};

// Everything before the first run: spec, checks, out dir (locked), CSV header or resumed rows.
struct Prepared {
    Spec spec;
    std::vector<Run> runs;
    std::map<int, std::string> rows;  // finished rows kept (resume)
    size_t rows_not_ok = 0;           // of those, how many are not ok
    std::string csv_path;
    std::unique_ptr<OutLock> lock;
};
int prepare(const Options& o, Prepared& p, std::ostream& err);
// Appends a row to the CSV and flushes it to disk.
bool append_row(const std::string& csv_path, const std::string& row);

// "about 4 min 10 s": a duration for people.
std::string format_duration(double seconds);

// What a running sweep prints about itself (progress.cpp): on a terminal one line rewritten
// in place, in a log a plain line at most every 10 s and at the end.
class Progress {
public:
    Progress(std::ostream& err, bool terminal, size_t total, size_t done_before, size_t failed_before);
    void finished(bool ok, size_t running);  // a run ended
    void tick(size_t running);               // while waiting: the terminal line's time left
    void clear();                            // before another message on a terminal
    void end();                              // the last line stays
    size_t done() const { return done_; }
    size_t failed() const { return failed_; }
    std::string line(size_t running) const;  // "12/60 runs done, 1 not ok, 2 running, about 4 min left"

private:
    void show(size_t running, bool force);
    std::ostream& err_;
    bool terminal_;
    size_t total_, done_, failed_, done_before_;
    double started_, last_ = 0;
    bool shown_ = false;
};

// SIGINT and SIGTERM while the runs go on: the first is noted (interrupted() returns it) so
// the driver can stop its runs and say how far it got; a second ends the process at once.
class InterruptWatch {
public:
    InterruptWatch();
    ~InterruptWatch();
    InterruptWatch(const InterruptWatch&) = delete;
    InterruptWatch& operator=(const InterruptWatch&) = delete;
    static int interrupted();  // the signal, or 0
};

// "Ctrl-C, SIGINT", "SIGTERM".
const char* signal_name(int sig);
// The message said when a sweep stops before its end: runs finished, and how to complete it.
std::string interrupted_message(const Options& o, const Prepared& p, int signal);

// When every ok run gave the plotted output the same value (a flat plot, e.g. a --for too
// short for anything to happen): a warning for the user; nothing otherwise.
std::optional<std::string> flat_plot_warning(const Spec& spec, const std::map<int, std::string>& rows);

int sweep_main(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace plant::sweep
