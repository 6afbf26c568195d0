#include "app/run_flags.h"

#include "app/summary.h"
#include "engine/events.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <algorithm>
#include <ostream>

namespace plant::app {

void add_run_flags(Cli& cli, RunFlags& f) {
    cli.value("--for", f.duration, "simulated time (s, ms, min; default 10 s)", "10s");
    cli.value("--rate", f.rate, "physics rate (Hz, kHz; default the plant's settings.rate)", "150Hz");
    cli.value("--trace", f.trace, "write a CSV trace", "FILE");
    cli.flag("--trace-bodies", f.trace_bodies, "the trace's bodies columns (with the two below: any subset;\ndefault all)");
    cli.flag("--trace-places", f.trace_places, "the trace's places columns");
    cli.flag("--trace-slots", f.trace_slots, "the trace's slots columns");
    cli.value("--trace-rate", f.trace_rate, "sample rate of the trace (default every step)", "50Hz");
    f.event_option = cli.values("--event", f.event, "a timed external input to the slot PATH; repeatable",
                                "\"5s PATH [VALUE]\"");
    f.events_option = cli.values("--events", f.events, "one event per line, # comments", "FILE");
    cli.flag("--realtime", f.realtime, "not faster than real time");
    cli.value("--broadphase", f.broadphase, "Bullet's broadphase (default dbvt)", "dbvt|sap");
    cli.value("--threads", f.threads,
              "threads for a plant in several physics regions\n(default: one per core; the results do not depend on it)",
              "N");
    cli.value("--steady-transport", f.steady,
              "bottles in steady transport leave Bullet's solver (default on,\nas the plant's "
              "settings.steady_transport; docs/runtime.md)",
              "on|off");
    cli.flag("--quiet", f.quiet, "no progress line");
    cli.value("--summary", f.summary, "text (default), or json for programs (docs/runtime.md)", "text|json");
}

bool run_options(const graph::Graph& g, const Cli& cli, const RunFlags& f, engine::RunOptions& o, std::string& error) {
    using namespace engine;
    if (!f.duration.empty() && !parse_duration(f.duration, o.duration, error)) return false;
    if (!f.rate.empty()) {
        if (!parse_frequency(f.rate, o.rate, error)) return false;
        if (o.rate < graph::kMinRate || o.rate > graph::kMaxRate) {
            error = fmt::format("--rate {}: the physics rate must lie between 1 Hz and 1 MHz", f.rate);
            return false;
        }
    }
    if (!f.trace_rate.empty()) {
        if (!parse_frequency(f.trace_rate, o.trace_rate, error)) return false;
        if (o.trace_rate > graph::kMaxRate) {
            error = fmt::format("--trace-rate {}: at most 1 MHz", f.trace_rate);
            return false;
        }
    }
    o.trace = f.trace;
    o.select.bodies = f.trace_bodies;
    o.select.places = f.trace_places;
    o.select.slots = f.trace_slots;
    o.realtime = f.realtime;
    o.quiet = f.quiet;
    if (f.broadphase == "sap") o.broadphase = Broadphase::Sap;
    else if (!f.broadphase.empty() && f.broadphase != "dbvt") {
        error = fmt::format("--broadphase: '{}' is neither dbvt nor sap", f.broadphase);
        return false;
    }
    long n = 0;
    if (!f.threads.empty() && !whole_number(f.threads, 1, 256, n)) {
        error = fmt::format("--threads: '{}' is not a number of threads from 1 to 256", f.threads);
        return false;
    }
    o.threads = int(n);
    if (!f.steady.empty() && f.steady != "on" && f.steady != "off") {
        error = fmt::format("--steady-transport: '{}' is neither on nor off", f.steady);
        return false;
    }
    o.steady = f.steady != "off";
    if (f.summary != "text" && f.summary != "json") {
        error = fmt::format("--summary takes text or json, not '{}'", f.summary);
        return false;
    }
    // --event and --events in the order given: at equal times a later one acts later.
    SlotIndex slots;
    size_t next_event = 0, next_file = 0;
    for (const CLI::Option* opt : cli.app().parse_order()) {
        if (opt != f.event_option && opt != f.events_option) continue;
        if (slots.empty()) slots = slot_index(g);
        if (opt == f.events_option) {
            if (!load_events(g, slots, f.events[next_file++], o.events, error)) return false;
            continue;
        }
        Event ev;
        if (!parse_event(g, slots, f.event[next_event++], ev, error)) return false;
        o.events.push_back(std::move(ev));
    }
    o.events = run_events(g, std::move(o.events));  // the plant file's own first
    return true;
}

int run_and_report(const graph::Graph& g, const engine::RunOptions& o, const std::string& summary, std::ostream& out,
                   std::ostream& err, engine::RunObserver* observer, engine::RunLink* link) {
    return engine::run(g, o, err, observer, link, [&](const engine::RunSummary& s) {
        if (summary == "json") write_summary_json(s, out);
        else write_summary_text(s, out);
    });
}

int run_main(const graph::Graph& g, const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
             engine::RunObserver* observer, engine::RunLink* link) {
    Cli cli("run", "FILE [options]", "");
    cli.errors_as("plant run", "");
    cli.unknown_word("flag");
    RunFlags f;
    add_run_flags(cli, f);
    std::vector<std::string> words;
    cli.positionals(words);
    if (const int code = cli.parse(args, out, err); code >= 0) return code;
    if (!words.empty()) return cli.usage_error(err, fmt::format("unexpected argument '{}'", words[0]));
    engine::RunOptions o;
    std::string error;
    if (!run_options(g, cli, f, o, error)) return cli.usage_error(err, error);
    return run_and_report(g, o, f.summary, out, err, observer, link);
}

}  // namespace plant::app
