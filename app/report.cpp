// `plant report PLANT EVENTS`: the session report (serve/report.h) — replays a session's
// events file headless and writes report.md, report.html and the plot into a folder.
#include "app/command.h"
#include "app/compile.h"
#include "engine/events.h"
#include "serve/report.h"

#include <filesystem>
#include <iostream>

namespace plant::app {

namespace {

constexpr const char* kReportAbout =
    R"(Replays a training session's events file (a page's /events, `plant serve`) on PLANT
headless and writes a report into --out: per fault when it was set and released, the
throughput before, while it held and after, objects lost and stalled, what each person did
and when; report.md, a printable report.html with a plot, and session.events.)";

int report_command(const std::vector<std::string>& args) {
    Cli cli("report", "PLANT EVENTS [options]", kReportAbout);
    cli.unknown_word("flag");
    std::string out, until;
    cli.value("--out", out, "where the report goes (default: report-NAME for EVENTS NAME.events)", "DIR", "a DIR");
    cli.value("--for", until, "the session's length, when its events file has no '# end TIME' line", "TIME");
    CompileFlags cf;
    add_compile_flags(cli, cf);
    std::vector<std::string> files;
    cli.positionals(files);
    if (const int code = cli.parse(args, std::cout, std::cerr); code >= 0) return code;
    if (const int code = check_compile_flags(cli, cf, std::cerr); code >= 0) return code;
    if (files.size() != 2) return cli.usage_error(std::cerr, "report takes a PLANT (.plant or .graph) and its EVENTS file");
    double seconds = 0;
    std::string error;
    if (!until.empty() && !engine::parse_duration(until, seconds, error)) return cli.usage_error(std::cerr, "--for: " + error);
    if (out.empty()) out = "report-" + std::filesystem::path(files[1]).stem().string();
    graph::Graph g;
    int code = 0;
    if (!load_graph(cli, files[0], cf, g, code)) return code;
    return view::report_main(g, files[0], files[1], out, seconds, std::cout, std::cerr);
}

}  // namespace

extern const Command kReportCommand{"report", "a training session's report from its events file (faults, throughput, "
                                              "who did what)", report_command};

}  // namespace plant::app
