// The thread behind `plant serve`: it runs the plant (live) or plays a recording (replay),
// paced to the wall clock at a chosen speed, and publishes what the pages see — frames,
// status, the event log — for the network thread to send. Pages act on it only through
// commands; external inputs are events applied before the next step through
// engine::apply_event, the same code `plant run --event` uses.
#pragma once

#include "engine/engine.h"
#include "engine/run.h"
#include "engine/events.h"
#include "faults/drill.h"
#include "serve/history.h"
#include "serve/record.h"
#include "serve/view.h"

#include <atomic>
#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <span>
#include <string>
#include <thread>
#include <vector>

namespace plant::view {

struct Command {
    enum class Kind { Pause, Run, Step, Restart, Speed, Event, Seek, Drill, DrillCancel };
    Kind kind = Kind::Pause;
    double value = 0;  // speed, seek time, DrillCancel: the drill's number
    engine::Event event;
    faults::Drill drill;  // Drill: one the instructor scheduled (faults/drill.h)
    int client = 0;
    std::string role;  // of the page that sent it ("instructor", "trainee"), for the events file
};

// What the pages see, replaced as a whole (readers keep the one they took).
struct FramePub {
    uint64_t seq = 0;
    Frame frame;
    std::vector<uint64_t> body_seq, gfx_seq;
    bool paused = false;
};
// Each as the instructor sees it and as a trainee does: without what is forced (the status's
// `forced`, the inspector's `forced`), which would give a fault away.
struct StatusPub {
    struct View {
        std::string status;                          // without "inspect"
        std::map<std::string, std::string> inspect;  // object path -> its inspect JSON
    };
    View instructor, trainee;
};

class Player {
public:
    virtual ~Player();
    void start();
    void stop();

    // From the network thread. False when the queue is full (the client is told).
    bool command(Command c);
    void set_inspected(const std::set<std::string>& paths);

    uint64_t scene_version() const { return scene_version_.load(); }
    std::shared_ptr<const std::string> scene() const;
    std::shared_ptr<const FramePub> frame() const;
    std::shared_ptr<const StatusPub> status() const;
    // Event-log lines (event messages, JSON) from index `from` on; `next` is the index after
    // the last line (the log restarts with the run). Without `faults`, forces and releases
    // are left out (a trainee's page).
    std::vector<std::string> log_since(size_t from, size_t& next, bool faults = true) const;
    // The events file of the session so far (for `plant run --events`), ending with the
    // plant time it has reached (`# end`).
    std::string events_file() const;
    // The run's series from t = 0 (history.h), and a number bumped when they start anew (a
    // restart, a seek): a page that has an older one is sent the new one whole.
    std::string history_json() const;
    uint64_t history_version() const { return history_version_.load(); }
    virtual bool live() const = 0;
    const graph::Graph& graph() const { return g_; }
    const engine::SlotIndex& slots() const { return slots_; }

protected:
    explicit Player(const graph::Graph& g, bool paused, double speed);
    // Restart, Event and Seek (the others are the same for every player), on the player
    // thread, under no lock; `now` is the wall clock.
    virtual void handle(Command& c, double now) = 0;
    virtual double sim_time() const = 0;  // where the paced clock stands now
    virtual void before_run() {}          // a replay at its end starts again
    // Advances towards the paced time; returns false when there was nothing to do.
    virtual bool advance(double wall_now) = 0;
    virtual void publish_frame() = 0;
    virtual void publish_status() = 0;

    void reanchor(double wall_now, double sim_now);
    double paced_target(double wall_now) const;
    void put_frame(const FrameTracker& t);
    void put_status(StatusPub::View instructor, StatusPub::View trainee);
    // An event applied at plant time `time` (the end of the step it feeds): to the pages' log,
    // and (`to_file`) to the session's events file; `fault`: a force or a release, which
    // trainees' pages are not sent.
    void log(double time, std::string event_json, std::string line, bool to_file, bool fault);
    void clear_log();
    // A comment line for the session's events file alone (a drill as scheduled: `# drill N
    // by WHO: LINE`, serve/report.h), which a replay skips.
    void note(std::string comment);
    // The series start anew (a restart, a seek); history_ready() then tells the pages, once the
    // samples up to now are in: a page polls the version (server.cpp) and is sent the series
    // whole, never the part a seek had added so far (it would not be sent the rest).
    void history_reset(size_t records);
    void history_ready() { ++history_version_; }
    void history_add(double t, std::span<const double> values);
    bool history_due(double t) const { return history_.due(t); }
    // Forced slots as the events that forced them say (who, since when): for the page's list;
    // `shown`: a drill's that trainees may see (faults/drill.h).
    void note_force(const engine::Event& ev, const std::string& line, const std::string& by, bool shown = false);
    void clear_forces() { forces_.clear(); }
    // Every force (`shown_only`: those trainees may see; "" when there is none of them).
    std::string forced_json(bool shown_only = false) const;
    // The speed achieved over the last two seconds of wall time.
    double achieved(double wall_now, double sim_now);
    void new_scene(std::string scene);
    std::set<std::string> inspected() const;
    // Bumped whenever the set changes, so a step can tell without taking the lock.
    uint64_t inspected_version() const { return inspected_version_.load(); }

    const graph::Graph& g_;
    engine::SlotIndex slots_;
    bool paused_;
    bool step_once_ = false;
    double speed_;
    double anchor_wall_ = 0, anchor_sim_ = 0;

private:
    void loop();
    void command_now(Command& c);
    mutable std::mutex m_;
    std::condition_variable cv_;
    std::vector<Command> queue_;
    std::set<std::string> inspected_;
    std::atomic<uint64_t> inspected_version_{0};
    std::shared_ptr<const std::string> scene_;
    std::shared_ptr<const FramePub> frame_;
    std::shared_ptr<const StatusPub> status_;
    History history_;                 // under m_: the network thread reads it
    std::atomic<uint64_t> history_version_{0};
    struct ForceNote {
        std::string path, how, by;
        std::vector<graph::SlotId> slots;
        double since = 0;
        bool shown = false;
    };
    std::vector<ForceNote> forces_;                // the player thread's own
    std::deque<std::pair<double, double>> pace_;  // (wall, sim) over the last two seconds
    struct LogLine {
        std::string json;
        bool fault;
    };
    std::deque<LogLine> log_;         // the last kMaxLog event messages, for late pages
    std::vector<std::string> lines_;  // the session's events file, whole
    double logged_until_ = 0;         // the latest plant time an event of lines_ was applied at
    size_t log_first_ = 0;
    std::atomic<uint64_t> scene_version_{0};
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

// `scheduled`: timed events from the command line (plant serve --event / --events), applied
// at their times in every run, logged and saved like the page's. `link` (may be null): an
// external link (engine/run.h) stepped with the run; not in lock-step.
// `drills`: a drill file's (plant serve --drill), which the instructor's page adds to.
std::unique_ptr<Player> make_live_player(const graph::Graph& g, engine::Options opt, ModelDirs dirs, bool paused,
                                         double speed, std::vector<engine::Event> scheduled = {},
                                         engine::RunLink* link = nullptr, std::vector<faults::Drill> drills = {});
std::unique_ptr<Player> make_replay_player(Recording rec, bool paused, double speed);

}  // namespace plant::view
