// Drills in `plant run` (docs/training.md, "Drills"): --drill FILE schedules faults at a
// time, now, or when a condition holds (faults/drill.h), as `plant serve --drill` does; a
// link of the run, so what fires is applied at the step boundary through apply_event with
// the run's other external inputs. --drill-events OUT writes what fired as the timed events
// it became, an events file: `plant run FILE --events OUT` replays the run without the drill.
#include "app/parts.h"

#include "engine/events.h"
#include "engine/times.h"
#include "faults/drill.h"

#include <fmt/format.h>

#include <fstream>

namespace plant::app {

namespace {

class DrillLink final : public engine::RunLink {
public:
    DrillLink(const graph::Graph& g, std::vector<faults::Drill> drills, const std::string& out) : g_(g) {
        for (faults::Drill& d : drills) drills_.add(std::move(d));
        fired_.reserve(drills_.list().size() * 2);
        applied_.reserve(drills_.list().size() * 2);
        if (!out.empty()) out_.open(out, std::ios::binary);
        if (out_) out_ << "# the events a drill applied in a plant run: plant run FILE --events THIS_FILE replays it\n";
        // Each drill as scheduled, as a served session's events file says it (serve/report.h).
        for (size_t i = 0; out_ && i < drills_.list().size(); ++i)
            out_ << "# drill " << i + 1 << " by " << drills_.list()[i].by << ": " << drills_.list()[i].text << "\n";
    }
    ~DrillLink() override {
        if (out_) out_ << view_end() << "\n";
    }
    bool ok() const { return out_.is_open() ? bool(out_) : true; }
    bool wait(std::string&) override { return true; }
    void before_step(engine::Engine& e) override {
        fired_.clear();
        applied_.clear();
        drills_.due(e, fired_);
        for (const faults::Drills::Fired& f : fired_) {
            engine::apply_event(e, f.event);
            if (out_)
                out_ << "# by drill " << f.drill + 1 << (f.repair ? " repair" : "") << "\n"
                     << engine::format_event(g_, f.event, e.dt()) << "\n";
        }
        for (const faults::Drills::Fired& f : fired_) applied_.push_back(&f.event);
        if (out_ && !fired_.empty()) out_.flush();
    }
    std::span<const engine::Event* const> applied() const override { return applied_; }
    void after_step(const engine::Engine& e) override {
        time_ = e.time();
        dt_ = e.dt();
    }
    std::vector<graph::SlotId> forceable() const override {
        std::vector<graph::SlotId> out;
        for (const faults::Drill& d : drills_.list())
            if (d.event.force) out.insert(out.end(), d.event.slots.begin(), d.event.slots.end());
        return out;
    }

private:
    std::string view_end() const { return fmt::format("# end {}s", engine::time_text(time_, dt_)); }
    const graph::Graph& g_;
    faults::Drills drills_;
    std::vector<faults::Drills::Fired> fired_;
    std::vector<const engine::Event*> applied_;
    std::ofstream out_;
    double time_ = 0, dt_ = 0;
};

class DrillPart : public Part {
public:
    void add_flags(Cli& cli, Where where) override {
        if (where != Where::Run) return;  // plant serve reads its own --drill (app/serve.cpp)
        cli.values("--drill", files_,
                   "drills, one per line: at a time, now, or `when PATH >= N`;\n`repaired by INPUT` or "
                   "`repaired by hand PATH` (docs/training.md; repeatable)",
                   "FILE");
        cli.value("--drill-events", out_, "write what the drills applied as an events file\n(--events replays it)",
                  "FILE", "a FILE");
    }
    bool check(Where where, std::string& error) override {
        if (where == Where::Run && !out_.empty() && files_.empty()) {
            error = "--drill-events needs --drill FILE";
            return false;
        }
        return true;
    }
    std::string link_name() const override { return "drill"; }
    bool waits() const override { return false; }
    bool wanted(const graph::Graph&) const override { return !files_.empty(); }
    std::unique_ptr<engine::RunLink> start(const graph::Graph& g, bool, const RunPlace&, std::ostream&,
                                           std::string& error) override {
        const engine::SlotIndex slots = engine::slot_index(g);
        std::vector<faults::Drill> drills;
        for (const std::string& f : files_)
            if (!faults::load_drills(g, slots, f, drills, error)) {
                error = "--drill: " + error;
                return nullptr;
            }
        auto link = std::make_unique<DrillLink>(g, std::move(drills), out_);
        if (!link->ok()) {
            error = fmt::format("--drill-events: cannot write '{}'", out_);
            return nullptr;
        }
        return link;
    }

private:
    std::vector<std::string> files_;
    std::string out_;
};

}  // namespace

std::unique_ptr<Part> make_drill_part() { return std::make_unique<DrillPart>(); }

}  // namespace plant::app
