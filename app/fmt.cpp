// `plant fmt`: formats plant files in place, checks them (--check) or prints them.
#include "app/fmt.h"

#include "app/cli.h"
#include "app/command.h"

#include "diag/diagnostic.h"
#include "fmt/diff.h"
#include "fmt/formatter.h"
#include "sema/modules.h"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <unistd.h>

namespace plant::formatter {
namespace {

namespace fs = std::filesystem;

constexpr const char* kAbout = R"(Formats plant files in one canonical layout: 4 spaces per brace, one space around
operators, after `:` and `,`; consecutive ports, instances and transitions in columns;
every comment kept where it is (docs/editors.md, "plant fmt"). Rewrites each FILE that
changes in place. A file with syntax errors is left alone and its diagnostics printed.
`-` as FILE formats standard input to standard output (for editors).)";
constexpr const char* kFooter = R"(Exit code: 0 done, 1 a file has errors, cannot be written or (--check) would change,
2 bad usage.
)";

// Every difference as a unified diff (`patch -p0` applies it). Two that do not show in a
// diff are named first: \r\n line ends and a byte-order mark (the formatter writes
// neither); the diff then shows what else would change.
void report_change(const std::string& name, std::string was, const std::string& now, std::ostream& out) {
    if (was.compare(0, 3, "\xEF\xBB\xBF") == 0) {
        out << name << ": would change: a byte-order mark at the start (plant fmt drops it)\n";
        was.erase(0, 3);
    }
    if (was.find("\r\n") != std::string::npos) {
        out << name << ": would change: \\r\\n line ends (plant fmt writes \\n)\n";
        std::string lf;
        for (size_t i = 0; i < was.size(); ++i)
            if (!(was[i] == '\r' && i + 1 < was.size() && was[i + 1] == '\n')) lf += was[i];
        was = std::move(lf);
    }
    out << unified_diff(was, now, name);
}

// Writes beside the file, then renames: an interrupted run leaves the file as it was.
bool replace_file(const std::string& path, const std::string& text) {
    std::string name = ".";  // appended, not "." + string: GCC 12 at -O3 flags that with a false -Wrestrict
    name += fs::path(path).filename().string();
    name += ".fmt-";
    name += std::to_string(::getpid());
    const fs::path tmp = fs::path(path).parent_path() / name;
    {
        std::ofstream f(tmp, std::ios::binary);
        f << text;
        if (!f.flush()) return false;
    }
    std::error_code ec;
    fs::permissions(tmp, fs::status(path, ec).permissions(), ec);
    fs::rename(tmp, path, ec);
    if (ec) fs::remove(tmp, ec);
    return !ec;
}

}  // namespace

int fmt_main(const std::vector<std::string>& args, std::istream& in, std::ostream& out, std::ostream& err) {
    app::Cli cli("fmt", "[--check] [--stdout] FILE...", kAbout, kFooter);
    bool check = false, to_stdout = false;
    cli.flag("--check", check,
             "change nothing; print what would change in each file as a unified\ndiff (every difference; `patch -p0` "
             "applies it); exit 1 if any");
    cli.flag("--stdout", to_stdout, "print the formatted text instead of rewriting the files");
    std::vector<std::string> files;
    cli.positionals(files);
    if (const int code = cli.parse(args, out, err); code >= 0) return code;
    if (files.empty()) return cli.usage_error(err, "no FILE given (`-` formats standard input)");
    int status = 0, changed = 0;
    for (const auto& f : files) {
        SourceMap sources;
        Sink sink;
        std::string text, why;
        const bool piped = f == "-";
        if (piped) {
            std::ostringstream ss;
            ss << in.rdbuf();
            text = ss.str();
        } else if (!sema::read_file(f, text, why)) {
            sink.report(DiagId::FileUnreadable, {}, "cannot read '" + f + "'" + why);
        }
        std::optional<std::string> formatted;
        if (!sink.has_errors()) formatted = format_text(piped ? "<stdin>" : f, text, sources, sink);
        if (auto sorted = sink.sorted(); !sorted.empty()) err << render_all_text(sorted, sources);
        if (!formatted) {
            status = 1;
            continue;
        }
        if (check) {
            if (*formatted != text) {
                report_change(piped ? "<stdin>" : f, text, *formatted, out);
                status = 1;
                ++changed;
            }
        } else if (piped || to_stdout) {
            out << *formatted;
        } else if (*formatted != text && !replace_file(f, *formatted)) {
            err << "plant fmt: error: cannot write '" << f << "'\n";
            status = 1;
        }
    }
    if (check && changed > 0)
        err << "plant fmt: " << changed << " of " << files.size() << " file" << (files.size() == 1 ? "" : "s")
            << " would change (`plant fmt FILE...` formats them)\n";
    return status;
}

}  // namespace plant::formatter

namespace plant::app {

extern const Command kFmtCommand{"fmt", "format plant files in the canonical layout (--check: only report)",
                                 [](const std::vector<std::string>& args) {
                                     return formatter::fmt_main(args, std::cin, std::cout, std::cerr);
                                 }};

}  // namespace plant::app
