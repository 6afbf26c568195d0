// plant_bench_bottling: the bundled bottling plant (plants/bottling.plant) at scale.
//
// For each target number N of bottles in circulation the plant is compiled with
// `lines = round(N / per_line)` lines side by side (each line holds about `per_line`
// bottles in circulation at its storage's pace), run for a warm-up and then for a
// measured window. Every run is a fresh forked child (a clean heap, its own peak RSS):
//
//   - real-time factor: simulated seconds of the window / wall seconds of the window;
//   - bottles in circulation: issued by the storages and not yet taken by an exit,
//     sampled every 0.1 s of the window (mean, min, max), and the number lost;
//   - the share of the bottle-steps a bottle spends off Bullet's solver (steady transport,
//     docs/runtime.md): its units off the solver after each step's check / (mean × steps);
//   - allocations: calls to operator new during the window (a counting allocator in
//     this binary) plus the times Bullet's allocator grew from the heap in it
//     (plant::engine::bullet_heap_requests) — the step must take none;
//   - peak RSS of the child, and for the largest N also the same lines with one bottle
//     per storage: (peak RSS - that) / bottles in the pools = memory per bottle;
//   - with --profile, where the window's step time goes (Engine::profile): the serial share
//     (wall time outside the parallel physics work / step time, per segment of the step) and
//     Amdahl's projection of the speed-up on 4, 8 and 16 threads; with several runs, those
//     of the run whose projection at 16 threads is the runs' median.
//
// Output: a Markdown table; with --rows only the rows of bench/run.sh's summary table.
//
// The lines are physics regions of their own, stepped on --threads threads (default: one per
// core; the results do not depend on it).
//
//   plant_bench_bottling [--counts=10,50,200,1000] [--runs=3] [--per-line=12]
//                        [--warmup=60] [--window=30] [--threads=N] [--plant=PATH] [--rows]
//                        [--no-memory] [--profile] [--no-huge-pages] [--steady-transport=on|off]
//
// --no-huge-pages: the plant's memory stays on 4 KiB pages (engine::Options::huge_pages), to
// compare. --steady-transport=off: every bottle stays on Bullet's solver
// (engine::Options::steady_transport, as `plant run --steady-transport off`), to compare.
#include "compiler.h"
#include "engine/engine.h"
#include "engine/fd_io.h"
#include "engine/runtime.h"
#include "engine/workers.h"

#include "bottling_plant.h"
#include "cpu_clock.h"
#include "flags.h"
#include "median.h"
#include "panel/kind.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <new>
#include <numeric>
#include <string>
#include <string_view>
#include <sys/resource.h>
#include <sys/wait.h>
#include <type_traits>
#include <unistd.h>
#include <vector>

// ---- The counting allocator: counts while `g_counting` is set. -------------------------

namespace {

using plant::bench::median;
bool g_counting = false;
long g_allocs = 0;

void* counted(std::size_t n) {
    if (g_counting) ++g_allocs;
    if (void* p = std::malloc(n ? n : 1)) return p;
    throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t n) { return counted(n); }
void* operator new[](std::size_t n) { return counted(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace {

struct Args {
    std::vector<int> counts{10, 50, 200, 1000};
    int runs = 3;
    double per_line = 12;
    double warmup = 60;  // simulated seconds before the window: every line has filled up
    double window = 30;  // simulated seconds measured
    std::string plant = std::string(PLANT_SOURCE_DIR) + "/plants/bottling.plant";
    bool rows = false;
    bool memory = true;  // the memory rows after the largest N
    int threads = 0;     // 0: one per core
    bool profile = false;
    bool huge_pages = true;
    bool steady = true;  // engine::Options::steady_transport
};

struct Sample {
    bool ok = false;
    double wall = 0, cpu = 0;  // seconds, over the window
    double mean = 0;           // bottles in circulation
    long min = 0, max = 0, lost = 0, allocs = 0, pool = 0;
    long news = 0;             // of allocs: operator new (the rest: Bullet's heap blocks)
    long rss_kib = 0;          // peak of the child
    long steps = 0;
    double dt = 0;                 // the step, simulated seconds
    int regions = 0, threads = 0;  // physics regions and the threads that stepped them
    double off = 0;                // share of the bottle-steps off Bullet's solver (steady transport)
    double rested = 0;             // ... of them resting, per step
    plant::engine::StepProfile prof;  // with --profile
    // Unit-steps on the solver over the window, by why (steady transport's first failed test).
    std::array<int64_t, plant::engine::kOnSolverReasons> why{};
    int64_t on_solver() const { return std::accumulate(why.begin(), why.end(), int64_t{0}); }  // all of them
    // With --profile, the units on and off the solver by where they are: the object (its type)
    // whose field each rides, sampled every 0.1 s of the window; the first row is the units in
    // no field, the last those in the plant's own fields and in every type past the others.
    // Plain arrays: a Sample crosses a pipe.
    struct Where {
        char name[40] = {};
        int64_t on = 0, off = 0;
        std::array<int64_t, plant::engine::kOnSolverReasons> why{};
    };
    static constexpr int kWhere = 16;
    std::array<Where, kWhere> where{};
    int where_rows = 0;
    long where_samples = 0;
};
static_assert(std::is_trivially_copyable_v<Sample>, "a Sample crosses a pipe as bytes");

// The row of Sample::where for each field (by its object's type), naming the rows.
std::vector<int> where_row_of_field(const plant::graph::Graph& g, Sample& s) {
    using namespace plant::graph;
    auto name = [&s](int row, std::string_view n) {
        const size_t len = std::min(n.size(), sizeof s.where[row].name - 1);
        std::copy_n(n.data(), len, s.where[row].name);
    };
    name(0, "(in no field)");
    s.where_rows = 1;
    std::vector<int> row_of_type(g.do_types.size(), -1), row_of_field(g.fields.size(), 0);
    for (FieldId f : ids_of(g.fields)) {
        const OptId<DoType> t = g.dos[g.comps[g.fields[f].comp].owner].type;
        if (!t.valid()) {  // the plant's own field
            row_of_field[size_t(f.v)] = Sample::kWhere - 1;
            continue;
        }
        int& row = row_of_type[size_t(t.v)];
        if (row < 0 && s.where_rows < Sample::kWhere - 1) {
            row = s.where_rows++;
            name(row, g.str(g.do_types[t].name));
        }
        row_of_field[size_t(f.v)] = row < 0 ? Sample::kWhere - 1 : row;
    }
    name(Sample::kWhere - 1, "(other objects)");
    s.where_rows = Sample::kWhere;
    return row_of_field;
}

// One sample of where the units are (after a step): on the solver by why, off it.
void count_where(plant::engine::Engine& e, const std::vector<int>& row_of_field, Sample& s) {
    const plant::engine::Runtime& r = e.internals();
    const plant::engine::Steady& S = r.steady;
    auto row = [&](plant::graph::BodyId u) {
        const plant::graph::FieldId f = r.st.ride_field[u];
        return f.valid() && r.st.ride_step[u] + 1 >= r.st.step ? row_of_field[size_t(f.v)] : 0;
    };
    for (plant::graph::BodyId u : ids_of(e.graph().bodies))
        if (const plant::engine::OnSolver w = S.why_of[u]; w != plant::engine::OnSolver::kCount) {
            Sample::Where& at = s.where[size_t(row(u))];
            ++at.on;
            ++at.why[size_t(w)];
        }
    S.each_coasting([&](plant::graph::BodyId u) { ++s.where[size_t(row(u))].off; });
    ++s.where_samples;
}

double now_wall() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

// One run, in the calling (child) process.
Sample run_once(const Args& a, int lines, int bottles_per_line, double warmup, double window) {
    Sample s;
    plant::graph::Graph g;
    if (!plant::bench::compile_bottling(a.plant, lines, bottles_per_line, g)) return s;
    plant::engine::Options eo;
    eo.threads = a.threads;
    eo.huge_pages = a.huge_pages;
    eo.steady_transport = a.steady;
    plant::engine::Engine e(g, eo);
    s.regions = e.regions();
    s.threads = e.threads();
    s.dt = e.dt();
    for (const auto& src : g.sources) s.pool += src.pool_num;
    auto circulating = [&] { return plant::bench::circulating(e, g); };
    const long warm = std::lround(warmup / e.dt()), steps = std::lround(window / e.dt());
    const long every = std::max(1L, std::lround(0.1 / e.dt()));
    for (long i = 0; i < warm; ++i) e.step();
    const std::vector<int> row_of_field = a.profile ? where_row_of_field(g, s) : std::vector<int>{};
    e.profile().on = a.profile;
    e.profile().reset();
    s.min = circulating();
    double sum = 0;
    long samples = 0;
    const double w0 = now_wall(), c0 = plant::bench::process_cpu_seconds();
    g_allocs = 0;
    const int64_t coasted0 = e.internals().steady.coasted, rested0 = e.internals().steady.rested;
    const auto why0 = e.internals().steady.why();
    const uint64_t bullet0 = plant::engine::bullet_heap_requests();
    g_counting = true;
    for (long i = 0; i < steps; ++i) {
        e.step();
        if (i % every == 0) {  // no allocation here: plain arithmetic
            const long n = circulating();
            sum += double(n);
            ++samples;
            s.min = std::min(s.min, n);
            s.max = std::max(s.max, n);
            if (a.profile) count_where(e, row_of_field, s);
        }
    }
    g_counting = false;
    s.wall = now_wall() - w0;
    s.cpu = plant::bench::process_cpu_seconds() - c0;
    s.prof = e.profile();
    s.news = g_allocs;
    s.allocs = g_allocs + long(plant::engine::bullet_heap_requests() - bullet0);
    s.steps = steps;
    s.mean = samples ? sum / double(samples) : 0;
    if (s.mean > 0) s.off = double(e.internals().steady.coasted - coasted0) / (s.mean * double(steps));
    s.rested = double(e.internals().steady.rested - rested0) / double(steps);
    const auto why1 = e.internals().steady.why();
    for (size_t k = 0; k < s.why.size(); ++k) s.why[k] = why1[k] - why0[k];
    for (size_t d = 0; d < g.dos.size(); ++d)
        if (e.lost_at(plant::graph::DoId(int32_t(d))) >= 0) ++s.lost;
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    s.rss_kib = ru.ru_maxrss;
    s.ok = true;
    return s;
}

// The same in a forked child; the result comes back through a pipe.
Sample run_child(const Args& a, int lines, int bottles_per_line, double warmup, double window) {
    int fd[2];
    if (pipe(fd) != 0) return {};
    std::fflush(nullptr);
    const pid_t pid = fork();
    if (pid == 0) {
        close(fd[0]);
        Sample s = run_once(a, lines, bottles_per_line, warmup, window);
        _exit(plant::engine::write_all(fd[1], &s, sizeof s) ? 0 : 1);
    }
    close(fd[1]);
    Sample s;  // larger than PIPE_BUF: it may come in parts
    if (!plant::engine::read_all(fd[0], &s, sizeof s)) s.ok = false;
    close(fd[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) s.ok = false;
    return s;
}

// A job's loop by its lambda's enclosing function: "void ...::run(int, F&) [with F =
// plant::engine::Physics::assign_worlds()::<lambda(int)>]" is "engine::Physics::assign_worlds".
std::string job_name(const char* pretty) {
    if (pretty == nullptr) return "(unnamed)";
    std::string s = pretty;
    if (const size_t f = s.find("F = "); f != std::string::npos) s = s.substr(f + 4);
    if (const size_t l = s.find("::<lambda"); l != std::string::npos) s.resize(l);
    std::string out;
    int depth = 0;
    for (char c : s) {  // argument lists dropped
        if (c == '(') ++depth;
        if (depth == 0) out += c;
        if (c == ')') --depth;
    }
    for (std::string_view cut : {"plant::", "{anonymous}::"})
        for (size_t at; (at = out.find(cut)) != std::string::npos;) out.erase(at, cut.size());
    return out;
}

// Where the jobs' wall time goes on the threads of the run (--profile): each loop's wall time
// against the least it could take there, max(items / threads, longest item).
void print_jobs(const plant::engine::StepProfile& p, int threads) {
    using Job = plant::engine::StepProfile::Job;
    std::vector<const Job*> jobs;
    for (const Job& j : p.jobs)
        if (j.name != nullptr) jobs.push_back(&j);
    std::sort(jobs.begin(), jobs.end(), [](const Job* a, const Job* b) { return a->wall_ns > b->wall_ns; });
    const double steps = double(p.steps);
    std::printf("| job on %d threads | runs per step | wall us per step | items' processor us per step | longest "
                "item us | least wall on %d threads us | wall / least |\n|---|---:|---:|---:|---:|---:|---:|\n",
                threads, threads);
    for (const Job* j : jobs) {
        const double least = std::max(j->work_ns / threads, j->longest_ns);
        std::printf("| %s | %.2f | %.1f | %.1f | %.1f | %.1f | %.2f |\n", job_name(j->name).c_str(),
                    double(j->calls) / steps, j->wall_ns / steps / 1e3, j->work_ns / steps / 1e3,
                    j->longest_ns / steps / 1e3, least / steps / 1e3, least > 0 ? j->wall_ns / least : 0.0);
    }
    std::printf("\n");
}

// Why the bottles on the solver are there (--profile): per step, the units that failed each
// test of steady transport first, against the bottles in circulation.
void print_on_solver(const Sample& s) {
    using plant::engine::OnSolver;
    const int64_t on = s.on_solver();
    if (s.steps == 0 || on == 0) return;
    const double steps = double(s.steps);
    std::printf("Off the solver: %.1f units per step, %.1f of them resting (held still, in a queue or at a pin).\n\n",
                s.off * s.mean, s.rested);
    std::printf("Why bottles are on the solver (%.1f per step of %.1f in circulation; a unit counts under the first "
                "test of steady transport it fails):\n\n| why | units per step | %% of those on the solver |\n"
                "|---|---:|---:|\n",
                double(on) / steps, s.mean);
    std::vector<size_t> order(s.why.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) { return s.why[x] > s.why[y]; });
    for (size_t k : order)
        if (s.why[k] > 0)
            std::printf("| %s | %.1f | %.1f |\n", plant::engine::on_solver_name(OnSolver(k)), double(s.why[k]) / steps,
                        100.0 * double(s.why[k]) / double(on));
    std::printf("\n");
}

// Where the bottles on the solver are (--profile): per object type whose field they ride, the
// units on and off the solver per sample, and the reasons that keep most of them on it.
void print_where(const Sample& s) {
    using plant::engine::OnSolver;
    if (s.where_samples == 0) return;
    int64_t on = 0;
    for (int k = 0; k < s.where_rows; ++k) on += s.where[size_t(k)].on;
    if (on == 0) return;
    const double n = double(s.where_samples);
    std::printf("Where they are (sampled every 0.1 s: the object whose field a unit rides, by its type):\n\n| object | "
                "units per step on the solver | off it | %% of its units on the solver | %% of all on the solver | "
                "mostly (a unit under the first test it fails) |\n|---|---:|---:|---:|---:|---|\n");
    std::vector<int> order;
    for (int k = 0; k < s.where_rows; ++k)
        if (s.where[size_t(k)].on + s.where[size_t(k)].off > 0) order.push_back(k);
    std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return s.where[size_t(x)].on > s.where[size_t(y)].on; });
    for (int k : order) {
        const Sample::Where& w = s.where[size_t(k)];
        std::vector<size_t> why(w.why.size());
        for (size_t i = 0; i < why.size(); ++i) why[i] = i;
        std::stable_sort(why.begin(), why.end(), [&](size_t x, size_t y) { return w.why[x] > w.why[y]; });
        std::string mostly;
        for (size_t i = 0; i < 3 && w.on > 0 && w.why[why[i]] > 0; ++i)
            mostly += (i ? "; " : "") + std::string(plant::engine::on_solver_name(OnSolver(why[i]))) + " " +
                      std::to_string(int(std::lround(100.0 * double(w.why[why[i]]) / double(w.on)))) + " %";
        std::printf("| %s | %.1f | %.1f | %.0f | %.0f | %s |\n", w.name, double(w.on) / n, double(w.off) / n,
                    100.0 * double(w.on) / double(w.on + w.off), 100.0 * double(w.on) / double(on), mostly.c_str());
    }
    std::printf("\n");
}

// What a bottle-step's processor time is spent on (--profile): the solver's job (the physics
// worlds' items: the conveyor law and Bullet's step for the units on the solver) per unit on
// it, and everything else (the serial segments and the other jobs' items: steady transport's
// check and mover, the body index, graphics, triggers, regions, logic) per bottle in
// circulation. The latter is what a bottle-step would cost were no bottle on the solver.
void print_split(const Sample& s) {
    const plant::engine::StepProfile& p = s.prof;
    double solver = 0, longest = 0;
    for (const auto& j : p.jobs)
        if (j.name != nullptr && job_name(j.name) == "engine::Physics::step") {
            solver += j.work_ns;
            longest = std::max(longest, j.longest_ns);
        }
    const double steps = double(p.steps), total = p.serial_total() + p.work_ns;
    if (steps <= 0 || s.mean <= 0 || total <= 0) return;
    // Units on the solver per step: those steady transport found there (the table of why), or
    // with it off every bottle in circulation.
    const int64_t why = s.on_solver();
    const double on = why > 0 ? double(why) / double(s.steps) : s.mean;
    std::printf("What a bottle-step costs (processor time, %.1f bottles in circulation, %.1f of them on the solver): "
                "the physics worlds' job %.0f us per step (%.1f %%), %.2f us per unit on the solver; everything else "
                "%.0f us per step, %.2f us per bottle in circulation (what a bottle-step would cost with none on the "
                "solver); in all %.2f us per bottle-step.\n\n",
                s.mean, on, solver / steps / 1e3, 100 * solver / total, on > 0 ? solver / steps / 1e3 / on : 0.0,
                (total - solver) / steps / 1e3, (total - solver) / steps / 1e3 / s.mean, total / steps / 1e3 / s.mean);
    // The ceiling the solver alone sets: were everything else free, the physics worlds' job on
    // these threads would still take max(its items / threads, its longest item) a step.
    const double least = std::max(solver / std::max(1, s.threads), longest) / steps;  // ns per step
    if (least > 0 && s.dt > 0)
        std::printf("The solver's ceiling: were everything but the physics worlds' job free, that job alone on %d "
                    "thread%s takes at least %.0f us a step (its items' time / threads, or its longest item), a step "
                    "being %.0f us of plant time: at best %.2fx real time.\n\n",
                    s.threads, s.threads == 1 ? "" : "s", least / 1e3, s.dt * 1e6, s.dt * 1e9 / least);
}

// The serial share of the window's steps and its Amdahl projection (--profile).
// `runs`: the projections at 16 threads of the runs it is the median of ("" for one run).
void print_profile(const Sample& s, int n, bool rows, const std::string& runs) {
    using plant::engine::StepProfile;
    const StepProfile& p = s.prof;
    if (!p.on || p.steps == 0 || p.step_ns <= 0) return;
    // Processor times (a busy machine's waits left out): the serial segments on the calling
    // thread, and the parallel items, laid out on 2 threads as max(items / 2, longest item).
    const double serial = p.serial_total(), share = p.share(1);
    const double two = serial + p.projected_ns[1];
    int order[StepProfile::kSegments];
    for (int i = 0; i < StepProfile::kSegments; ++i) order[i] = i;
    std::sort(order, order + StepProfile::kSegments, [&](int x, int y) { return p.serial_ns[x] > p.serial_ns[y]; });
    std::string parts;
    for (int k = 0; k < StepProfile::kSegments && k < 4; ++k) {
        const int i = order[k];
        char buf[160];
        std::snprintf(buf, sizeof buf, "%s%s %.1f %%", parts.empty() ? "" : ", ", StepProfile::name(i),
                      100 * p.serial_ns[i] / two);
        parts += buf;
    }
    const double steps = double(p.steps);
    const double wall_share = std::max(0.0, 1 - p.jobs_ns / p.step_ns);
    if (rows) {
        std::printf("| step | serial share at %d bottles in circulation on 2 threads: processor time outside the "
                    "parallel physics work / step time (%.0f us serial, %.0f us of parallel items per step, less the profile's "
                    "clock reads, %.0f ns each; "
                    "largest: %s; by the wall clock on %d threads %.1f %%) | %.1f %% | <= 3 %% | %s |\n",
                    n, serial / steps / 1e3, p.work_ns / steps / 1e3, p.read_ns, parts.c_str(), s.threads, 100 * wall_share,
                    100 * share, share <= 0.03 ? "yes" : "**no**");
        const std::string of = runs.empty() ? "" : "; of the run whose projection at 16 threads is the median of the runs': " + runs;
        std::printf("| step | Amdahl projection from it (1 thread = serial + the items; a job no shorter than its "
                    "longest item%s) | 4 threads %.1fx, 8 threads %.1fx, 16 threads %.1fx | >= 10x at 16 | %s |\n",
                    of.c_str(), p.speedup(2), p.speedup(3), p.speedup(4), p.speedup(4) >= 10 ? "yes" : "**no**");
        return;
    }
    if (!runs.empty())
        std::printf("\nProfiled runs' projections at 16 threads: %s; the run with the median is the one below.\n", runs.c_str());
    std::printf("\nWhere a step goes at %d bottles (%lld steps; processor times, each timed stretch less one read of "
                "the thread's clock: %.0f ns here): %.0f us serial, %.0f us of parallel "
                "items per step (the longest item's share: see the projection); on 2 threads the serial share is "
                "%.1f %%. By the wall clock on %d threads: %.0f us per step, %.1f %% outside the parallel jobs.\n\n",
                n, (long long)p.steps, p.read_ns, serial / steps / 1e3, p.work_ns / steps / 1e3, 100 * share, s.threads,
                p.step_ns / steps / 1e3, 100 * wall_share);
    std::printf("| segment (serial) | us per step | %% of the step on 2 threads |\n|---|---:|---:|\n");
    for (int k = 0; k < StepProfile::kSegments; ++k) {
        const int i = order[k];
        std::printf("| %s | %.1f | %.2f |\n", StepProfile::name(i), p.serial_ns[i] / steps / 1e3,
                    100 * p.serial_ns[i] / two);
    }
    std::printf("\nAmdahl: ");
    for (int i = 1; i < StepProfile::kProjected; ++i)
        std::printf("%s%d threads %.2fx (serial %.1f %%)", i > 1 ? ", " : "", StepProfile::threads_of(i),
                    p.speedup(i), 100 * p.share(i));
    std::printf("\n\n");
    print_jobs(p, s.threads);
    print_split(s);
    print_on_solver(s);
    print_where(s);
}

// Of several profiled runs, the one whose projection at 16 threads is their median (the lower of
// the middle two for an even count): its serial share, jobs and units are printed together, as
// one run measured them, and with more than one run the projections of all are named (stderr).
// `all` names them all, in rising order ("" for one run).
const Sample& median_profiled(std::vector<Sample>& runs, std::string& all) {
    using plant::engine::StepProfile;
    auto x16 = [](const Sample& s) { return s.prof.speedup(StepProfile::kProjected - 1); };
    std::stable_sort(runs.begin(), runs.end(), [&](const Sample& a, const Sample& b) { return x16(a) < x16(b); });
    const Sample& mid = runs[(runs.size() - 1) / 2];
    all.clear();
    if (runs.size() > 1)
        for (const Sample& r : runs) {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%s%.1fx", all.empty() ? "" : ", ", x16(r));
            all += buf;
        }
    return mid;
}

// The command line into `a`: -1 to go on, else the exit code (bench/flags.h).
int parse(int argc, char** argv, Args& a) {
    plant::bench::Flags f("plant_bench_bottling", "[FLAGS]",
                          "The bottling plant at N bottles in circulation (N / --per-line copies of the line side by\n"
                          "side): real-time factor, processor time per bottle-step, memory and allocations\n"
                          "(bench/README.md).");
    f.wholes("--counts", a.counts, 1, 1000000, "bottles in circulation, one row each (default 10,50,200,1000)");
    f.whole("--runs", a.runs, 1, 1000, "runs per count, each a fresh process; the median is shown (default 3)");
    f.positive("--per-line", a.per_line, "N", "bottles in circulation per line (default 12)");
    f.not_negative("--warmup", a.warmup, "S", "simulated seconds before the window (default 60)");
    f.positive("--window", a.window, "S", "simulated seconds measured (default 30)");
    f.whole("--threads", a.threads, 1, 256, "threads for the plant's physics regions (default: one per core)");
    f.text("--plant", a.plant, "PATH", "the plant file (default plants/bottling.plant)");
    f.flag("--rows", a.rows, true, "only the rows of bench/run.sh's table");
    f.flag("--no-memory", a.memory, false, "no memory rows");
    f.flag("--profile", a.profile, true,
           "where a step goes: serial segments, jobs, units on the solver (of the run with the median projection at 16 threads)");
    f.flag("--no-huge-pages", a.huge_pages, false, "no huge pages for the plant's memory");
    std::string steady;
    f.choice("--steady-transport", steady, {"on", "off"}, "steady transport on or off (default on)");
    const int code = f.parse(argc, argv);
    if (code < 0 && !steady.empty()) a.steady = steady == "on";
    return code;
}

}  // namespace

int main(int argc, char** argv) {
    plant::panel::register_panel_kinds();  // the bottling line's operator panel
    Args a;
    if (const int code = parse(argc, argv, a); code >= 0) return code;
    if (!a.rows) {
        std::printf("# plant_bench_bottling (%s build): %s\n\n", PLANT_BENCH_BUILD_TYPE, a.plant.c_str());
        std::printf("150 Hz, feed_every = 1 s, %g s warm-up, then %g s measured; medians of %d runs, each a "
                    "fresh process.\n\n",
                    a.warmup, a.window, a.runs);
        std::printf("| target N | lines | regions / threads | pool | in circulation mean (min-max) | lost | off the solver | "
                    "wall s | CPU s | real-time factor | CPU us per bottle-step | allocations in window (of them operator "
                    "new) | peak RSS MiB |\n");
        std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    }
    int status = 0;
    Sample last;
    int last_lines = 0;
    for (int n : a.counts) {
        const int lines = std::max(1, int(std::lround(double(n) / a.per_line)));
        const int per_line_pool = 40;  // the plant's default: enough for warm-up + window
        std::vector<double> rtf, wall, cpu, mean, off;
        Sample s;
        std::vector<Sample> profiled;  // with --profile: each run's, to print the median run's
        long allocs = 0, news = 0, lost = 0;
        for (int r = 0; r < a.runs; ++r) {
            std::fprintf(stderr, "bottling N=%d (%d lines) run %d/%d\n", n, lines, r + 1, a.runs);
            s = run_child(a, lines, per_line_pool, a.warmup, a.window);
            if (!s.ok) {
                status = 1;
                break;
            }
            rtf.push_back(a.window / s.wall);
            wall.push_back(s.wall);
            cpu.push_back(s.cpu);
            mean.push_back(s.mean);
            off.push_back(s.off);
            allocs = std::max(allocs, s.allocs);
            news = std::max(news, s.news);
            lost = std::max(lost, s.lost);
            if (a.profile) profiled.push_back(s);
        }
        if (!s.ok) continue;
        const double us = median(cpu) * 1e6 / (double(s.steps) * median(mean));
        const char* target = n == 50 ? ">= 20x" : n == 1000 || n == 5000 ? ">= 1x" : "-";
        const bool met = n == 50 ? median(rtf) >= 20 : n == 1000 || n == 5000 ? median(rtf) >= 1 : true;
        if (a.rows && a.profile) {
            // The profile's rows only (bench/run.sh runs the plant's rows without it).
        } else if (a.rows) {
            // The hour's load: a 5,000-bottle target holds on a quiet machine (bench/README.md).
            std::string load;
            if (n >= 5000)
                if (FILE* f = std::fopen("/proc/loadavg", "r")) {
                    char buf[64] = {};
                    if (std::fgets(buf, sizeof buf, f)) {
                        const std::string_view v = buf;
                        size_t cut = 0;
                        for (int k = 0; k < 3 && cut != std::string_view::npos; ++k) cut = v.find(' ', cut + 1);
                        load = "; load average after: " + std::string(v.substr(0, cut));
                    }
                    std::fclose(f);
                }
            std::printf("| bottling plant | %d bottles in circulation (%d line%s, %d thread%s; measured mean %.0f, "
                        "%ld lost; %.0f %% of the bottle-steps off the solver%s) | %.1fx real time (%.1f CPU us per "
                        "bottle-step) | %s | %s |\n",
                        n, lines, lines == 1 ? "" : "s", s.threads, s.threads == 1 ? "" : "s", median(mean), lost,
                        100 * median(off), load.c_str(), median(rtf), us, target,
                        *target == '-' ? "-" : met ? "yes" : "**no**");
        } else {
            std::printf("| %d | %d | %d / %d | %ld | %.1f (%ld-%ld) | %ld | %.1f %% | %.2f | %.2f | %.1f | %.2f | %ld (%ld) | "
                        "%.1f |\n",
                        n, lines, s.regions, s.threads, s.pool, median(mean), s.min, s.max, lost, 100 * median(off),
                        median(wall), median(cpu), median(rtf), us, allocs, news, double(s.rss_kib) / 1024);
        }
        if (a.profile) {
            std::string all;
            const Sample& mid = median_profiled(profiled, all);
            print_profile(mid, n, a.rows, all);
        }
        std::fflush(stdout);
        last = s;
        last.allocs = allocs;  // the memory rows report the largest count of the runs, as the table
        last.news = news;
        last_lines = lines;
    }
    // Memory per bottle: the largest plant against the same lines with one bottle each.
    if (last.ok && a.memory) {
        std::fprintf(stderr, "bottling %d lines, one bottle per storage (memory baseline)\n", last_lines);
        const Sample base = run_child(a, last_lines, 1, 0.0, 1.0);
        if (base.ok && last.pool > base.pool) {
            const double per = double(last.rss_kib - base.rss_kib) / double(last.pool - base.pool);
            const double all = double(last.rss_kib) / std::max(1.0, last.mean);
            if (a.rows) {
                std::printf("| memory | peak RSS per bottle (%ld bottles in the pools, %d line%s) | %.1f KiB "
                            "(whole process: %.1f MiB, %.0f KiB per bottle in circulation) | %s | %s |\n",
                            last.pool, last_lines, last_lines == 1 ? "" : "s", per, double(last.rss_kib) / 1024, all,
                            // issue 30's target, for the 1,000-bottle plant
                            last_lines >= 83 ? "<= 10 KiB" : "-", last_lines < 83 ? "-" : per <= 10 ? "yes" : "**no**");
                std::printf("| memory | allocations by the runtime in the measured steps (operator new) | %ld | 0 "
                            "| %s |\n",
                            last.news, last.news == 0 ? "yes" : "**no**");
                std::printf("| memory | times Bullet's recycled pools grew from the heap in the measured steps (new "
                            "peaks, %ld steps after a %g s warm-up) | %ld | 0 | %s |\n",
                            last.steps, a.warmup, last.allocs - last.news, last.allocs == last.news ? "yes" : "**no**");
            } else {
                std::printf("\nMemory: %.1f KiB per bottle (peak RSS %.1f MiB with %ld bottles in the pools, %.1f "
                            "MiB with %ld); %.0f KiB of the whole process per bottle in circulation.\n",
                            per, double(last.rss_kib) / 1024, last.pool, double(base.rss_kib) / 1024, base.pool,
                            all);
            }
        } else {
            status = 1;
        }
    }
    return status;
}
