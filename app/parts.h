// What an optional library adds to the commands: flags of its own on `plant run`, `plant
// serve` or `plant info`, and what they do there — a link the run serves (the Modbus and
// OPC UA links), an observer of the run (the recorder), a map `plant info` prints. The parts
// of a build are listed by CMake (app/CMakeLists.txt, commands.cpp.in), so no command
// names a library that may be missing.
#pragma once

#include "app/cli.h"
#include "engine/run.h"
#include "graph/graph.h"

#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace plant::app {

enum class Where { Run, Serve, Info };

// Where a run is: for a link's messages and files.
struct RunPlace {
    std::string plant_dir;  // the plant file's folder
    std::string stdlib;     // the standard library's folder
    std::string tag;        // "plant run", "plant serve"
};

class Part {
public:
    virtual ~Part() = default;
    // Its flags on the command `where` (none: it does not take part there).
    virtual void add_flags(Cli& cli, Where where) = 0;
    // After parsing: false with `error` for a bad value.
    virtual bool check(Where where, std::string& error) = 0;

    // A link: its name ("Modbus"), "" when the part is none.
    virtual std::string link_name() const { return ""; }
    // Whether the run serves it: a flag of its own given, or the plant declares one.
    virtual bool wanted(const graph::Graph&) const { return false; }
    // Whether a --lockstep with no link wanted starts this one (Modbus: the plant's PLC).
    virtual bool lockstep_default() const { return false; }
    // Whether its link can hold the run in lock-step (false: the drills, which only add
    // events; they run beside a lock-step link and do not count as one).
    virtual bool waits() const { return true; }
    // The link, started; null with `error`.
    virtual std::unique_ptr<engine::RunLink> start(const graph::Graph&, bool /*lockstep*/, const RunPlace&,
                                                   std::ostream& /*err*/, std::string& error) {
        error = "not a link";
        return nullptr;
    }

    // An observer of `plant run` when its flags ask for one (a recording), or null; false
    // with `error` (and the exit code in `code`) when it cannot start.
    virtual bool observer(const graph::Graph&, const RunPlace&, std::unique_ptr<engine::RunObserver>& out,
                          std::string& /*error*/, int& /*code*/) {
        out = nullptr;
        return true;
    }

    // `plant info`: what its flags ask to print of `g`.
    virtual void info(const graph::Graph&, std::ostream&) {}
};

// A fresh instance of every part this build has (commands.cpp.in).
std::vector<std::unique_ptr<Part>> parts();

}  // namespace plant::app
