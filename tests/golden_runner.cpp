// Golden-file tests: every tests/golden/**/NAME.plant is compiled and its outputs are
// compared with the files beside it:
//   NAME.graph  the compiled graph's text form (when it compiles)
//   NAME.err    the rendered diagnostics (present exactly when there are any)
//   NAME.trace  the runtime trace (CSV), for a case that has a NAME.run file holding
//               the `plant run` flags to use (e.g. `--for 2s --trace-rate 10Hz`)
//   NAME.schedule the logic phase in order (`plant info --schedule`), for a case that
//               has one (create it empty, then --update fills it)
// A case with a NAME.set file is compiled with one `--set` per non-empty line of it
// (`k=4 kg/s`), as `plant check --set k=4kg/s NAME.plant` would.
// A file named fail_*.plant must produce errors, any other must not. Every graph must
// round-trip (write -> load -> write is identical), and every registered diagnostic code
// must appear in at least one .err file.
// Cases under fmt/ are for the formatter (`plant fmt`), not compiled as above:
//   fmt/NAME.plant  the input; fmt/NAME.fmt its formatted text, or fmt/NAME.err the
//                   diagnostics (fail_NAME.plant: a syntax error, the file is refused).
// Each must format idempotently and compile to the same graph and AST before and after.
//
//   plant_golden DIR            check; prints a diff-like report, exit 1 on mismatch
//   plant_golden --update DIR   rewrite the expected files; review with `git diff`
#include "faults/kind.h"
#include "faults/operable.h"
#include "panel/kind.h"
#include "opcua/kind.h"
#include "plc/kind.h"
#include "compiler.h"
#include "app/run_flags.h"
#include "engine/run.h"
#include "fmt/formatter.h"
#include "fmt_compare.h"
#include "graph/network.h"
#include "graph/text.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

bool write(const fs::path& p, const std::string& text) {
    std::ofstream out(p, std::ios::binary);
    out << text;
    return static_cast<bool>(out);
}

// First differing line, for a readable failure.
std::string first_difference(const std::string& want, const std::string& got) {
    std::istringstream a(want), b(got);
    std::string la, lb;
    for (int line = 1;; ++line) {
        bool ea = !std::getline(a, la), eb = !std::getline(b, lb);
        if (ea && eb) return "(files differ only in line endings)";
        if (ea || eb || la != lb)
            return "line " + std::to_string(line) + ":\n    expected: " + (ea ? "<end of file>" : la) +
                   "\n    actual:   " + (eb ? "<end of file>" : lb);
    }
}

struct Result {
    int cases = 0, failed = 0, updated = 0;
    std::set<std::string> codes_seen;
};

void expect_file(const fs::path& path, const std::string& actual, bool update, Result& r, bool& ok,
                 const std::string& what) {
    bool exists = fs::exists(path);
    if (update) {
        if (actual.empty()) {
            if (exists) fs::remove(path), ++r.updated;
        } else if (!exists || read(path) != actual) {
            write(path, actual);
            ++r.updated;
        }
        return;
    }
    if (actual.empty() && !exists) return;
    if (actual.empty()) {
        std::cout << "  " << path.generic_string() << ": expected " << what << " but there was none\n";
        ok = false;
        return;
    }
    if (!exists) {
        std::cout << "  " << path.generic_string() << ": missing (" << what << " produced)\n";
        ok = false;
        return;
    }
    std::string want = read(path);
    if (want != actual) {
        std::cout << "  " << path.generic_string() << ": " << what << " differs at " << first_difference(want, actual) << "\n";
        ok = false;
    }
}

// A formatter case: NAME.fmt (or NAME.err), idempotence, the same compiled form.
void fmt_case(const fs::path& f, const fs::path& base, bool update, Result& r, bool& ok) {
    const std::string text = read(f);
    plant::SourceMap sources;
    plant::Sink sink;
    const auto formatted = plant::formatter::format_text(f.generic_string(), text, sources, sink);
    const auto sorted = sink.sorted();
    for (const auto& d : sorted) r.codes_seen.insert(std::string(plant::info(d.id).code));
    const bool must_fail = f.filename().string().rfind("fail_", 0) == 0;
    if (must_fail == formatted.has_value()) {
        std::cout << "  " << f.generic_string() << ": " << (must_fail ? "formatted, expected a syntax error" : "refused") << "\n";
        ok = false;
    }
    expect_file(base.string() + ".err", sorted.empty() ? "" : plant::render_all_text(sorted, sources), update, r, ok, "diagnostics");
    expect_file(base.string() + ".fmt", formatted.value_or(""), update, r, ok, "formatted text");
    if (!formatted) return;
    plant::SourceMap again_sources;
    plant::Sink again_sink;
    if (plant::formatter::format_text("again", *formatted, again_sources, again_sink) != formatted) {
        std::cout << "  " << f.generic_string() << ": formatting the formatted text changes it\n";
        ok = false;
    }
    const plant::sema::Overlay overlay{{fs::weakly_canonical(f).string(), *formatted}};
    if (plant::testing::compiled_form(f.generic_string(), nullptr) != plant::testing::compiled_form(f.generic_string(), &overlay)) {
        std::cout << "  " << f.generic_string() << ": the formatted text compiles differently\n";
        ok = false;
    }
    if (plant::testing::without_blanks(text) != plant::testing::without_blanks(*formatted)) {
        std::cout << "  " << f.generic_string() << ": formatting changed more than blanks\n";
        ok = false;
    }
}

}  // namespace

int main(int argc, char** argv) {
    plant::plc::register_modbus_kind();  // the plugin kinds this program has (docs/architecture.md)
    plant::opcua::register_opcua_kind();
    plant::faults::register_faults_kind();
    plant::panel::register_panel_kinds();
    plant::faults::register_operable_kind();
    bool update = false;
    std::string dir, sources;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--update") update = true;
        else if (a.rfind("--sources=", 0) == 0) sources = a.substr(10);
        else dir = a;
    }
    if (dir.empty()) {
        std::cerr << "usage: plant_golden [--update] [--sources=SRC] DIR\n"
                     "  cases are DIR/**/NAME.plant, their goldens beside them; with --sources, the\n"
                     "  cases are SRC/**/NAME.plant (shipped plants) and their goldens DIR/**/NAME.*\n";
        return 2;
    }
    std::error_code ec;
    for (const std::string& d : {dir, sources})
        if (!d.empty() && !fs::is_directory(d, ec)) {
            std::cerr << "plant_golden: '" << d << "' is not a folder\n";
            return 2;
        }
    // Paths in diagnostics are relative to the case folder: stable across machines.
    const fs::path out_dir = fs::absolute(dir);
    fs::current_path(sources.empty() ? dir : sources);
    std::vector<fs::path> files;
    for (const auto& e : fs::recursive_directory_iterator("."))
        if (e.is_regular_file() && e.path().extension() == ".plant") files.push_back(e.path().lexically_normal());
    std::sort(files.begin(), files.end());

    Result r;
    plant::CompileOptions opts;
    opts.stdlib_dir = plant::default_stdlib_dir();
    for (const auto& f : files) {
        // Files under a folder named `lib` are imported by other cases, not cases themselves.
        if (f.generic_string().find("/lib/") != std::string::npos || f.generic_string().rfind("lib/", 0) == 0) continue;
        ++r.cases;
        bool ok = true;
        if (sources.empty() && f.generic_string().rfind("fmt/", 0) == 0) {
            fs::path base = f;
            fmt_case(f, base.replace_extension(), update, r, ok);
            if (!ok) {
                ++r.failed;
                std::cout << "FAIL " << f.generic_string() << "\n";
            }
            continue;
        }
        // Goldens (and a case's .set and .run files) beside the case, or under DIR for --sources.
        fs::path base = sources.empty() ? f : out_dir / f;
        base.replace_extension();
        fs::create_directories(base.parent_path());
        plant::CompileOptions case_opts = opts;
        if (fs::exists(base.string() + ".set")) {
            std::istringstream lines(read(base.string() + ".set"));
            for (std::string line; std::getline(lines, line);)
                if (!line.empty()) case_opts.overrides.push_back(line);
        }
        plant::Compilation c;
        plant::compile_file(f.generic_string(), case_opts, c);
        auto sorted = c.sink.sorted();
        for (const auto& d : sorted) r.codes_seen.insert(std::string(plant::info(d.id).code));
        std::string err = sorted.empty() ? "" : plant::render_all_text(sorted, c.sources);
        std::string graph = c.ok() ? plant::graph::to_text(c.graph) : "";
        const bool must_fail = f.filename().string().rfind("fail_", 0) == 0;
        if (must_fail != !c.ok()) {
            std::cout << "  " << f.generic_string() << ": " << (must_fail ? "expected errors, compiled cleanly"
                                                                          : "unexpected errors:\n" + err) << "\n";
            ok = false;
        }
        if (!graph.empty()) {
            plant::graph::Graph loaded;
            std::istringstream in(graph);
            std::string load_error;
            if (!plant::graph::read_text(in, loaded, load_error)) {
                std::cout << "  " << f.generic_string() << ": graph text does not load: " << load_error << "\n";
                ok = false;
            } else if (plant::graph::to_text(loaded) != graph || !loaded.same_as(c.graph)) {
                std::cout << "  " << f.generic_string() << ": graph text does not round-trip\n";
                ok = false;
            }
        }
        std::string trace;
        if (fs::exists(base.string() + ".run") && c.ok()) {
            std::istringstream flags(read(base.string() + ".run"));
            std::vector<std::string> args;
            for (std::string w; flags >> w;) args.push_back(w);
            fs::path tmp = fs::temp_directory_path() / ("plant_golden_" + std::to_string(::getpid()) + ".csv");
            args.insert(args.end(), {"--trace", tmp.string(), "--quiet"});
            std::ostringstream out, err;
            if (plant::app::run_main(c.graph, args, out, err) != 0) {
                std::cout << "  " << f.generic_string() << ": run failed: " << err.str() << "\n";
                ok = false;
            }
            trace = read(tmp);
            fs::remove(tmp);
        }
        expect_file(base.string() + ".trace", trace, update, r, ok, "trace");
        if (fs::exists(base.string() + ".schedule"))
            expect_file(base.string() + ".schedule",
                        c.ok() ? plant::graph::network_text(c.graph, plant::graph::analyse_network(c.graph)) : "", update,
                        r, ok, "schedule");
        expect_file(base.string() + ".graph", graph, update, r, ok, "graph");
        expect_file(base.string() + ".err", err, update, r, ok, "diagnostics");
        if (!ok) {
            ++r.failed;
            std::cout << "FAIL " << f.generic_string() << "\n";
        }
    }

    // Every registered code is exercised by at least one case (of the golden folder).
    int uncovered = 0;
    for (const auto& info : plant::all_diagnostics())
        if (sources.empty() && !r.codes_seen.count(std::string(info.code))) {
            std::cout << "  diagnostic " << info.code << " (" << info.summary << ") has no golden case\n";
            ++uncovered;
        }
    if (update) std::cout << "updated " << r.updated << " file(s); review with `git diff tests/`\n";
    std::cout << "golden: " << r.cases - r.failed << " passed, " << r.failed << " failed"
              << (uncovered ? ", " + std::to_string(uncovered) + " diagnostic code(s) without a case" : "") << "\n";
    return (r.failed || uncovered) && !update ? 1 : 0;
}
