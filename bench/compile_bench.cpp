// plant_bench_compile: how the compiler scales with the number of object instances.
//
// For each size N and each form (see gen_plant.h) it writes a generated plant file to a
// temporary folder, then compiles it in a fresh child process per run (fork): the child
// times plant::compile_file (parse + check + lower) and the writing of the graph's text
// form, and sends the numbers back through a pipe; the parent reads the child's peak
// resident memory from wait4's rusage. Time is the median of the runs (a single run
// when the first one takes longer than --max-seconds); RSS is the largest of the runs.
//
// Modes for profiling (no fork, so valgrind/perf see the compile directly):
//   plant_bench_compile --gen N FORM OUT    write the generated plant only
//   plant_bench_compile --compile FILE      compile FILE once in this process
//                                           (--phases: then parse and elaborate timed apart)
#include "compiler.h"
#include "cpu_clock.h"
#include "engine/fd_io.h"
#include "flags.h"
#include "gen_plant.h"
#include "graph/text.h"
#include "sema/elaborate.h"
#include "sema/modules.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <optional>
#include <streambuf>
#include <string>
#include <string_view>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

#ifndef PLANT_BENCH_BUILD_TYPE
#define PLANT_BENCH_BUILD_TYPE "unknown"
#endif

namespace {

namespace fs = std::filesystem;
using plant::bench::Form;
using Clock = std::chrono::steady_clock;


double ms_since(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// CPU time of this process (user + system), in ms: steadier than wall time on a busy machine.
double cpu_ms() { return 1e3 * plant::bench::process_cpu_seconds(); }

// What a child sends back; plain data through a pipe.
struct RunResult {
    double compile_ms = 0;
    double compile_cpu_ms = 0;
    double text_ms = 0;
    int64_t text_bytes = 0;
    int64_t dos = 0;
    int64_t comps = 0;
    int64_t slots = 0;
    int64_t flows = 0;
    int64_t warnings = 0;
    int64_t errors = 0;
    long compile_hwm_kib = 0;  // VmHWM right after compile_file, before the graph text
    long maxrss_kib = 0;       // filled in by the parent: the whole child, graph text included
};

// Peak resident set size of this process so far (VmHWM), KiB; 0 if unknown.
long vm_hwm_kib() {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("VmHWM:", 0) == 0) return std::strtol(line.c_str() + 6, nullptr, 10);
    return 0;
}

// A stream buffer that only counts what is written to it.
class CountingBuf : public std::streambuf {
public:
    int64_t count() const { return count_; }

protected:
    int_type overflow(int_type ch) override {
        if (!traits_type::eq_int_type(ch, traits_type::eof())) ++count_;
        return traits_type::not_eof(ch);
    }
    std::streamsize xsputn(const char*, std::streamsize n) override {
        count_ += n;
        return n;
    }

private:
    int64_t count_ = 0;
};

// Compiles `plant_file` and times writing the graph text (into a counting sink). With a
// non-empty `text_file` the text is also saved there, untimed. Diagnostics of a failed
// compile go to stderr.
RunResult compile_once(const std::string& plant_file, const std::string& text_file, const std::string& stdlib) {
    RunResult r;
    plant::CompileOptions opts;
    opts.stdlib_dir = stdlib;
    plant::Compilation c;
    const double c0 = cpu_ms();
    const auto t0 = Clock::now();
    plant::compile_file(plant_file, opts, c);
    r.compile_ms = ms_since(t0);
    r.compile_cpu_ms = cpu_ms() - c0;
    r.compile_hwm_kib = vm_hwm_kib();
    r.warnings = c.sink.count(plant::Severity::Warning);
    r.errors = c.sink.count(plant::Severity::Error);
    if (!c.ok()) {
        std::fputs(plant::render_all_text(c.sink.sorted(), c.sources).c_str(), stderr);
        return r;
    }
    r.dos = static_cast<int64_t>(c.graph.dos.size());
    r.comps = static_cast<int64_t>(c.graph.comps.size());
    r.slots = static_cast<int64_t>(c.graph.slots.size());
    r.flows = static_cast<int64_t>(c.graph.flows.size());
    {
        // Into a counting sink: the writer's own cost, not the disk's (and no text in RSS).
        CountingBuf buf;
        std::ostream out(&buf);
        auto t1 = Clock::now();
        plant::graph::write_text(c.graph, out);
        out.flush();
        r.text_ms = ms_since(t1);
        r.text_bytes = buf.count();
    }
    if (!text_file.empty()) {
        std::ofstream out(text_file, std::ios::binary | std::ios::trunc);
        plant::graph::write_text(c.graph, out);
    }
    return r;
}

// One run in a fresh child process. nullopt when the child failed (its diagnostics
// are already on stderr).
std::optional<RunResult> run_in_child(const std::string& plant_file, const std::string& text_file,
                                      const std::string& stdlib) {
    int fds[2];
    if (::pipe(fds) != 0) {
        std::perror("plant_bench_compile: pipe");
        return std::nullopt;
    }
    std::fflush(stdout);
    std::fflush(stderr);
    pid_t pid = ::fork();
    if (pid < 0) {
        std::perror("plant_bench_compile: fork");
        return std::nullopt;
    }
    if (pid == 0) {
        ::close(fds[0]);
        RunResult r = compile_once(plant_file, text_file, stdlib);
        bool sent = plant::engine::write_all(fds[1], &r, sizeof r);
        std::fflush(stderr);
        ::_exit(r.errors == 0 && sent ? 0 : 1);  // no destructors: only the compile is measured
    }
    ::close(fds[1]);
    RunResult r;
    bool got = plant::engine::read_all(fds[0], &r, sizeof r);
    ::close(fds[0]);
    int status = 0;
    rusage ru{};
    while (::wait4(pid, &status, 0, &ru) < 0) {
        if (errno != EINTR) {
            std::perror("plant_bench_compile: wait4");
            return std::nullopt;
        }
    }
    if (WIFSIGNALED(status)) {
        std::fprintf(stderr, "plant_bench_compile: compiling %s died with signal %d\n", plant_file.c_str(),
                     WTERMSIG(status));
        return std::nullopt;
    }
    if (!got || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        std::fprintf(stderr, "plant_bench_compile: %s does not compile (%lld errors)\n", plant_file.c_str(),
                     static_cast<long long>(got ? r.errors : -1));
        return std::nullopt;
    }
    r.maxrss_kib = ru.ru_maxrss;  // KiB on Linux
    return r;
}

// Peak RSS of a forked child that does nothing: what every measurement includes anyway.
long fork_baseline_kib() {
    std::fflush(stdout);
    std::fflush(stderr);
    pid_t pid = ::fork();
    if (pid == 0) ::_exit(0);
    if (pid < 0) return -1;
    int status = 0;
    rusage ru{};
    if (::wait4(pid, &status, 0, &ru) < 0) return -1;
    return ru.ru_maxrss;
}

std::string cpu_model() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0) {
            auto colon = line.find(':');
            if (colon != std::string::npos) {
                auto s = line.substr(colon + 1);
                s.erase(0, s.find_first_not_of(" \t"));
                return s;
            }
        }
    return "unknown";
}

std::string today() {
    std::time_t t = std::time(nullptr);
    std::tm tm{};
    ::localtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%d", &tm);
    return buf;
}

std::string with_commas(int64_t v) {
    const std::string digits = std::to_string(v < 0 ? -v : v);
    std::string out = v < 0 ? "-" : "";
    for (size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

struct Row {
    Form form;
    int64_t instances;
    plant::bench::GenStats gen;
    RunResult result;  // counts from the first run, rss the largest
    double median_ms;
    double median_cpu_ms;
    double text_ms;
    int runs;
};

// The two phases of compile_file timed apart (as compile.cpp calls them): loading and
// parsing every module, then checking and lowering. Wall ms.
void print_phases(const std::string& file, const std::string& stdlib) {
    plant::SourceMap sources;
    plant::Sink sink;
    const auto t0 = Clock::now();
    plant::sema::Program program = plant::sema::load_program(file, stdlib, sources, sink);
    const double parse_ms = ms_since(t0);
    if (sink.has_errors()) return;
    const auto t1 = Clock::now();
    plant::graph::Graph g = plant::sema::elaborate(program, sources, sink);
    const double elab_ms = ms_since(t1);
    std::printf("%s: phases: load + parse %.1f ms, elaborate (check + lower) %.1f ms (%zu slots)\n", file.c_str(),
                parse_ms, elab_ms, g.slots.size());
}

// --compile FILE: one in-process compile, for profilers; then the phases apart.
int compile_mode(const std::string& file, const std::string& stdlib, bool phases) {
    RunResult r = compile_once(file, "", stdlib);
    if (r.errors > 0) return 1;
    std::printf("%s: compile %.1f ms (%.1f ms CPU, peak RSS %.1f MiB), graph text %.1f ms (%s bytes), %s DOs, %s comps, %s slots, %s flows, %lld warnings\n",
                file.c_str(), r.compile_ms, r.compile_cpu_ms, static_cast<double>(r.compile_hwm_kib) / 1024.0, r.text_ms, with_commas(r.text_bytes).c_str(), with_commas(r.dos).c_str(),
                with_commas(r.comps).c_str(), with_commas(r.slots).c_str(), with_commas(r.flows).c_str(),
                static_cast<long long>(r.warnings));
    if (phases) print_phases(file, stdlib);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<int> sizes{1'000, 10'000, 100'000};
    std::vector<Form> forms{Form::Loop, Form::Flat};
    int runs = 3;
    double max_seconds = 20;
    std::string keep, forms_text, compile_file;
    bool table_rows = false;  // --rows: only the rows of bench/run.sh's summary table
    bool gen = false, phases = false;
    std::string stdlib = plant::default_stdlib_dir();

    plant::bench::Flags f("plant_bench_compile",
                          "[FLAGS]\n       plant_bench_compile --gen N loop|flat OUT\n"
                          "       plant_bench_compile --compile FILE [--phases]",
                          "Compiler scaling: generates plants of N instances, compiles each in a fresh child\n"
                          "process and prints a table of compile time, graph size and peak RSS per size.\n"
                          "--gen writes one generated plant and exits; --compile compiles FILE once in this\n"
                          "process (for valgrind), and with --phases times parsing and elaboration apart.\n"
                          "Exit code: 0, or 1 when a generated plant does not compile (diagnostics on stderr).");
    f.wholes("--sizes", sizes, 1, 10000000, "instance counts (default 1000,10000,100000)");
    f.text("--forms", forms_text, "LIST", "loop, flat or both, comma separated (default loop,flat)");
    f.whole("--runs", runs, 1, 1000, "runs per size; the median time is shown (default 3)");
    f.positive("--max-seconds", max_seconds, "S", "a size whose first run takes longer gets one run only (default 20)");
    f.text("--keep", keep, "DIR", "write the generated files (and graph texts) to DIR and keep them");
    f.text("--stdlib", stdlib, "DIR", "standard library folder (default: the bundled one)");
    f.flag("--rows", table_rows, true, "only the rows of bench/run.sh's table");
    f.flag("--gen", gen, true, "write one generated plant of N instances in a form to OUT, and exit");
    f.text("--compile", compile_file, "FILE", "compile FILE once in this process, and exit");
    f.flag("--phases", phases, true, "with --compile: time parsing and elaboration apart");
    std::vector<std::string> words;
    f.words(words);
    if (const int code = f.parse(argc, argv); code >= 0) return code;
    if (!forms_text.empty()) {
        forms.clear();
        for (const std::string& item : plant::bench::comma_items(forms_text)) {
            Form form;
            if (!plant::bench::parse_form(item, form))
                return f.error("--forms: '" + item + "' in '" + forms_text + "' is not loop or flat");
            forms.push_back(form);
        }
    }
    if (gen) {
        long n = 0;
        Form form;
        if (words.size() != 3) return f.error("--gen needs N, a form and an output file after it");
        if (!plant::app::whole_number(words[0], 1, 100000000, n))
            return f.error("--gen: '" + words[0] + "' is not a whole number from 1 to 100000000");
        if (!plant::bench::parse_form(words[1], form)) return f.error("--gen: '" + words[1] + "' is not loop or flat");
        plant::bench::GenStats st;
        if (!plant::bench::write_plant_file(words[2], n, form, st)) {
            std::fprintf(stderr, "plant_bench_compile: cannot write %s\n", words[2].c_str());
            return 1;
        }
        std::printf("%s: %ld instances, %s lines, %s bytes\n", words[2].c_str(), n, with_commas(st.lines).c_str(),
                    with_commas(st.bytes).c_str());
        return 0;
    }
    if (!words.empty()) return f.error("unexpected word '" + words.front() + "'");
    if (phases && compile_file.empty()) return f.error("--phases goes with --compile FILE");
    if (!compile_file.empty()) return compile_mode(compile_file, stdlib, phases);

    // The working folder.
    fs::path dir;
    if (!keep.empty()) {
        dir = keep;
        std::error_code ec;
        fs::create_directories(dir, ec);
        if (ec) {
            std::fprintf(stderr, "plant_bench_compile: cannot create %s: %s\n", keep.c_str(), ec.message().c_str());
            return 1;
        }
    } else {
        std::string tmpl = (fs::temp_directory_path() / "plant_bench.XXXXXX").string();
        if (!::mkdtemp(tmpl.data())) {
            std::perror("plant_bench_compile: mkdtemp");
            return 1;
        }
        dir = tmpl;
    }

    if (!table_rows) {  // --rows prints only the rows, at the end
        std::printf("# plant_bench_compile: %s, %s (%u threads available), build %s\n", today().c_str(),
                    cpu_model().c_str(), std::thread::hardware_concurrency(), PLANT_BENCH_BUILD_TYPE);
        if (double load[3]; ::getloadavg(load, 3) == 3)
            std::printf("# load average %.2f %.2f %.2f on %ld online CPUs%s\n", load[0], load[1], load[2],
                        ::sysconf(_SC_NPROCESSORS_ONLN),
                        load[0] > static_cast<double>(::sysconf(_SC_NPROCESSORS_ONLN)) * 0.5
                            ? " (busy machine: trust the CPU ms columns more than wall ms)"
                            : "");
        if (std::string_view(PLANT_BENCH_BUILD_TYPE) != "Release")
            std::printf("# warning: not a Release build; numbers are not comparable\n");
        const long baseline = fork_baseline_kib();
        std::printf("# each run compiles in a fresh forked child; peak RSS includes the fork baseline of %.1f MiB\n",
                    static_cast<double>(baseline) / 1024.0);
    }
    std::fflush(stdout);

    int status = 0;
    std::vector<Row> rows;
    for (Form form : forms) {
        for (const int64_t n : sizes) {
            const std::string stem = fmt::format("grid_{}_{}", plant::bench::form_name(form), n);
            const std::string plant_file = (dir / (stem + ".plant")).string();
            // The graph text is saved (untimed) only for --keep.
            const std::string text_file = keep.empty() ? "" : (dir / (stem + ".graph")).string();
            Row row{form, n, {}, {}, 0, 0, 0, 0};
            if (!plant::bench::write_plant_file(plant_file, n, form, row.gen)) {
                std::fprintf(stderr, "plant_bench_compile: cannot write %s\n", plant_file.c_str());
                status = 1;
                break;
            }
            std::vector<double> times, cpu_times, text_times;
            bool failed = false;
            for (int k = 0; k < runs; ++k) {
                auto r = run_in_child(plant_file, k == 0 ? text_file : "", stdlib);
                if (!r) {
                    failed = true;
                    break;
                }
                if (k == 0) row.result = *r;
                row.result.maxrss_kib = std::max(row.result.maxrss_kib, r->maxrss_kib);
                row.result.compile_hwm_kib = std::max(row.result.compile_hwm_kib, r->compile_hwm_kib);
                times.push_back(r->compile_ms);
                cpu_times.push_back(r->compile_cpu_ms);
                text_times.push_back(r->text_ms);
                if (k == 0 && r->compile_ms > max_seconds * 1000.0) break;
            }
            if (failed) {
                status = 1;
                break;
            }
            std::sort(times.begin(), times.end());
            std::sort(cpu_times.begin(), cpu_times.end());
            std::sort(text_times.begin(), text_times.end());
            row.median_ms = times[times.size() / 2];
            row.median_cpu_ms = cpu_times[cpu_times.size() / 2];
            row.text_ms = text_times[text_times.size() / 2];
            row.runs = static_cast<int>(times.size());
            rows.push_back(row);
            std::fprintf(stderr, "  %s %lld: %.1f ms (%d run%s)\n", std::string(plant::bench::form_name(form)).c_str(),
                         static_cast<long long>(n), row.median_ms, row.runs, row.runs == 1 ? "" : "s");
            if (!keep.empty()) continue;
            std::error_code ec;
            fs::remove(plant_file, ec);
        }
        if (status != 0) break;
    }
    if (keep.empty()) {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }

    // (time ratio) / (size ratio) against the previous size of the same form; < 0: none.
    auto growth_of = [&](size_t i, double Row::*field) {
        if (i == 0 || rows[i - 1].form != rows[i].form || rows[i - 1].*field <= 0) return -1.0;
        return (rows[i].*field / rows[i - 1].*field) /
               (static_cast<double>(rows[i].instances) / static_cast<double>(rows[i - 1].instances));
    };
    auto growth_text = [&](size_t i, double Row::*field) {
        const double g = growth_of(i, field);
        return g < 0 ? std::string("-") : fmt::format("{:.2f}", g);
    };
    if (table_rows) {
        for (size_t i = 0; i < rows.size(); ++i) {
            const Row& r = rows[i];
            const bool ten_k = r.instances == 10000;
            const bool met = ten_k ? r.median_ms < 1000 : growth_of(i, &Row::median_cpu_ms) < 1.5;
            std::printf("| compiler | %s instances, %s form (%s source lines) | %.0f ms (CPU %.0f ms), peak RSS "
                        "%.0f MiB; growth per size step %s | %s | %s |\n",
                        with_commas(r.instances).c_str(), std::string(plant::bench::form_name(r.form)).c_str(),
                        with_commas(r.gen.lines).c_str(), r.median_ms, r.median_cpu_ms,
                        double(r.result.compile_hwm_kib) / 1024.0, growth_text(i, &Row::median_cpu_ms).c_str(),
                        ten_k ? "< 1 s at 10k; linear" : "linear", met ? "yes" : "**no**");
        }
        return status;
    }
    std::printf("\n| form | instances | source lines | source KiB | DOs | slots | flows | warnings | runs "
                "| compile ms (median) | ms / 1k inst | growth | compile CPU ms | growth (CPU) "
                "| graph text ms | graph text MiB | peak RSS MiB (compile) | peak RSS MiB (+ text) |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (size_t i = 0; i < rows.size(); ++i) {
        const Row& r = rows[i];
        std::printf("| %s | %s | %s | %s | %s | %s | %s | %lld | %d | %.1f | %.2f | %s | %.1f | %s | %.1f | %.1f | %.1f | %.1f |\n",
                    std::string(plant::bench::form_name(r.form)).c_str(), with_commas(r.instances).c_str(),
                    with_commas(r.gen.lines).c_str(), with_commas(r.gen.bytes / 1024).c_str(),
                    with_commas(r.result.dos).c_str(), with_commas(r.result.slots).c_str(),
                    with_commas(r.result.flows).c_str(), static_cast<long long>(r.result.warnings), r.runs,
                    r.median_ms, r.median_ms / (static_cast<double>(r.instances) / 1000.0),
                    growth_text(i, &Row::median_ms).c_str(), r.median_cpu_ms, growth_text(i, &Row::median_cpu_ms).c_str(), r.text_ms,
                    static_cast<double>(r.result.text_bytes) / (1024.0 * 1024.0),
                    static_cast<double>(r.result.compile_hwm_kib) / 1024.0,
                    static_cast<double>(r.result.maxrss_kib) / 1024.0);
    }
    std::printf("\ngrowth = (time ratio) / (size ratio) against the previous size of the same form; "
                "1.0 is linear, 10 is quadratic for 10x steps.\n");
    return status;
}
