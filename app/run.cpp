// `plant run FILE`: a headless run (engine/run.h) with the plant's parameters, the run's
// flags (app/run_flags.h) and those of the parts this build has (links, the recorder).
#include "app/command.h"
#include "app/compile.h"
#include "app/parts.h"
#include "app/run_flags.h"
#include "engine/link_chain.h"

#include <filesystem>
#include <iostream>

namespace plant::app {

namespace {

constexpr const char* kRunAbout =
    R"(Runs FILE (a .plant, or a .graph written by `plant build`) headless and prints a summary:
objects issued, taken, on the line, lost and stalled; records; warnings; wall time and
the real-time factor.)";

int run_command(const std::vector<std::string>& args) {
    Cli cli("run", "FILE [options]", kRunAbout, "See docs/runtime.md (\"plant run\") for the event values and the trace format.\n");
    cli.unknown_word("flag");
    RunFlags rf;
    add_run_flags(cli, rf);
    CompileFlags cf;
    add_compile_flags(cli, cf);
    std::vector<std::unique_ptr<Part>> all = parts();
    bool links = false, lockstep = false;
    for (auto& p : all) {
        p->add_flags(cli, Where::Run);
        links = links || !p->link_name().empty();
    }
    if (links)
        cli.flag("--lockstep", lockstep,
                 "step only as a client grants steps: a Modbus client, or an\nOPC UA client calling Link.Advance "
                 "(docs/plc.md)");
    std::vector<std::string> files;
    cli.positionals(files);
    if (const int code = cli.parse(args, std::cout, std::cerr); code >= 0) return code;
    if (const int code = check_compile_flags(cli, cf, std::cerr); code >= 0) return code;
    if (files.size() != 1) return cli.usage_error(std::cerr, "run takes one FILE (.plant or .graph)");
    std::string error;
    for (auto& p : all)
        if (!p->check(Where::Run, error)) return cli.usage_error(std::cerr, error);

    graph::Graph g;
    int code = 0;
    if (!load_graph(cli, files[0], cf, g, code)) return code;
    engine::RunOptions o;
    if (!run_options(g, cli, rf, o, error)) return cli.usage_error(std::cerr, error);

    // The links the run serves: those asked for or declared; --lockstep alone starts the
    // plant's PLC link, and takes exactly one.
    const RunPlace place{std::filesystem::path(files[0]).parent_path().string(), stdlib_of(cf), "plant run"};
    // A link that never waits (the drills) is served beside them and counts for neither.
    std::vector<Part*> served, beside;
    for (auto& p : all)
        if (!p->link_name().empty() && p->wanted(g)) (p->waits() ? served : beside).push_back(p.get());
    if (lockstep && served.empty())
        for (auto& p : all)
            if (p->lockstep_default()) served.push_back(p.get());
    if (lockstep && served.size() > 1)
        return cli.usage_error(std::cerr, "--lockstep: the plant is served over " + served[0]->link_name() + " and " +
                                              served[1]->link_name() +
                                              "; lock-step takes one link (leave out --modbus-port, or the opcua component)");
    served.insert(served.end(), beside.begin(), beside.end());
    std::vector<std::unique_ptr<engine::RunLink>> started;
    std::vector<engine::RunLink*> chain_of;
    for (Part* p : served) {
        started.push_back(p->start(g, lockstep, place, std::cerr, error));
        if (!started.back()) {
            std::cerr << "plant run: error: " << error << "\n";
            return 1;
        }
        chain_of.push_back(started.back().get());
    }
    engine::LinkChain chain(chain_of);
    engine::RunLink* link = chain_of.size() > 1 ? &chain : chain_of.empty() ? nullptr : chain_of[0];

    std::unique_ptr<engine::RunObserver> observer;
    for (auto& p : all) {
        std::unique_ptr<engine::RunObserver> mine;
        if (!p->observer(g, place, mine, error, code)) {
            std::cerr << "plant run: error: " << error << "\n";
            return code;
        }
        if (mine) observer = std::move(mine);
    }
    return run_and_report(g, o, rf.summary, std::cout, std::cerr, observer.get(), link);
}

}  // namespace

extern const Command kRunCommand{"run", "run a plant (.plant or .graph) headless and print a summary", run_command};

}  // namespace plant::app
