#include "serve/player.h"

#include "serve/report.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace plant::view {

namespace {
// Unix seconds, for the session's events file (who sent what, when).
double wall_clock() {
    return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}
}  // namespace

using json = nlohmann::json;

namespace {

constexpr double kFrameEvery = 1.0 / 60;  // publishing frames, wall seconds
constexpr double kStatusEvery = 0.2;
constexpr size_t kMaxQueue = 1024;       // commands waiting for the player
constexpr size_t kMaxLog = 10000;        // event-log lines kept for late pages

double wall_seconds() {
    using Clock = std::chrono::steady_clock;
    return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
}

}  // namespace

Player::Player(const graph::Graph& g, bool paused, double speed) : g_(g), paused_(paused), speed_(speed) {}

Player::~Player() { stop(); }

void Player::start() {
    stop_ = false;
    thread_ = std::thread([this] { loop(); });
}

void Player::stop() {
    stop_ = true;
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
}

bool Player::command(Command c) {
    {
        std::lock_guard lock(m_);
        if (queue_.size() >= kMaxQueue) return false;
        queue_.push_back(std::move(c));
    }
    cv_.notify_all();
    return true;
}

void Player::set_inspected(const std::set<std::string>& paths) {
    std::lock_guard lock(m_);
    if (paths == inspected_) return;
    inspected_ = paths;
    ++inspected_version_;
}

std::set<std::string> Player::inspected() const {
    std::lock_guard lock(m_);
    return inspected_;
}

std::shared_ptr<const std::string> Player::scene() const {
    std::lock_guard lock(m_);
    return scene_;
}

std::shared_ptr<const FramePub> Player::frame() const {
    std::lock_guard lock(m_);
    return frame_;
}

std::shared_ptr<const StatusPub> Player::status() const {
    std::lock_guard lock(m_);
    return status_;
}

std::vector<std::string> Player::log_since(size_t from, size_t& next, bool faults) const {
    std::lock_guard lock(m_);
    std::vector<std::string> out;
    const size_t end = log_first_ + log_.size();
    for (size_t i = std::max(from, log_first_); i < end; ++i)
        if (faults || !log_[i - log_first_].fault) out.push_back(log_[i - log_first_].json);
    next = end;
    return out;
}

std::string Player::events_file() const {
    std::lock_guard lock(m_);
    std::string out = "# events of a plant serve session: plant run FILE --events THIS_FILE replays it;\n"
                      "# plant report FILE THIS_FILE writes the session's report (docs/training.md)\n";
    for (const std::string& l : lines_) out += l + "\n";
    // Where the session stands: the report replays it to here. The last frame published may
    // lag the player by a few steps, and an event is logged before the step it feeds: the
    // end is never before an event of the file, so the replay applies every one of them.
    const double rate = g_.settings.rate > 0 ? g_.settings.rate : 150;
    return out + session_end_comment(std::max(frame_ ? frame_->frame.time : 0, logged_until_), 1 / rate) + "\n";
}

void Player::log(double time, std::string event_json, std::string line, bool to_file, bool fault) {
    std::lock_guard lock(m_);
    log_.push_back({std::move(event_json), fault});
    if (to_file) {
        lines_.push_back(std::move(line));
        logged_until_ = std::max(logged_until_, time);
    }
    if (log_.size() > kMaxLog) {
        log_.pop_front();
        ++log_first_;
    }
}

void Player::note(std::string comment) {
    std::lock_guard lock(m_);
    lines_.push_back(std::move(comment));
}

void Player::clear_log() {
    std::lock_guard lock(m_);
    log_first_ += log_.size();
    log_.clear();
    lines_.clear();
    logged_until_ = 0;
}

std::string Player::history_json() const {
    std::lock_guard lock(m_);
    return history_.json();
}

void Player::history_reset(size_t records) {
    std::lock_guard lock(m_);
    history_ = History(records);
}

void Player::history_add(double t, std::span<const double> values) {
    std::lock_guard lock(m_);
    history_.add(t, values);
}

void Player::note_force(const engine::Event& ev, const std::string& line, const std::string& by, bool shown) {
    if (!ev.force) return;
    // A force on a slot replaces any earlier one on it; a release ends it.
    std::erase_if(forces_, [&](const ForceNote& n) {
        return std::any_of(n.slots.begin(), n.slots.end(),
                           [&](graph::SlotId s) { return std::find(ev.slots.begin(), ev.slots.end(), s) != ev.slots.end(); });
    });
    if (ev.mode == engine::ForceMode::None) return;
    // How, as the events-file line says it after the path ("open", "stuck 0.25").
    const size_t at = line.find(" " + ev.path + " ");
    const std::string how = at == std::string::npos ? "" : line.substr(at + ev.path.size() + 2);
    forces_.push_back({ev.path, how, by, ev.slots, ev.time, shown});
}

std::string Player::forced_json(bool shown_only) const {
    json out = json::array();
    for (const ForceNote& n : forces_)
        if (!shown_only || n.shown)
            out.push_back({{"path", n.path}, {"how", n.how}, {"by", n.by}, {"since", n.since}});
    if (shown_only && out.empty()) return {};
    return out.dump(-1, ' ', false, json::error_handler_t::replace);
}

double Player::achieved(double wall, double sim) {
    if (!pace_.empty() && sim < pace_.back().second) pace_.clear();  // a restart or a seek back
    pace_.emplace_back(wall, sim);
    while (pace_.size() > 2 && wall - pace_[1].first >= 2.0) pace_.pop_front();
    const auto& [w0, s0] = pace_.front();
    return wall - w0 > 0.1 ? (sim - s0) / (wall - w0) : 0;
}

void Player::new_scene(std::string scene) {
    auto s = std::make_shared<const std::string>(std::move(scene));
    std::lock_guard lock(m_);
    scene_ = std::move(s);
    ++scene_version_;
}

void Player::put_frame(const FrameTracker& t) {
    auto f = std::make_shared<FramePub>();
    f->seq = t.seq();
    f->frame = t.frame();
    f->body_seq = t.body_seq();
    f->gfx_seq = t.gfx_seq();
    f->paused = paused_;
    std::lock_guard lock(m_);
    frame_ = std::move(f);
}

void Player::put_status(StatusPub::View instructor, StatusPub::View trainee) {
    auto s = std::make_shared<StatusPub>();
    s->instructor = std::move(instructor);
    s->trainee = std::move(trainee);
    std::lock_guard lock(m_);
    status_ = std::move(s);
}

void Player::reanchor(double wall_now, double sim_now) {
    anchor_wall_ = wall_now;
    anchor_sim_ = sim_now;
}

double Player::paced_target(double wall_now) const { return anchor_sim_ + (wall_now - anchor_wall_) * speed_; }

void Player::command_now(Command& c) {
    const double now = wall_seconds();
    switch (c.kind) {
    case Command::Kind::Pause:
        paused_ = true;
        pace_.clear();
        return;
    case Command::Kind::Run:
        paused_ = false;
        before_run();
        reanchor(now, sim_time());
        pace_.clear();
        return;
    case Command::Kind::Step: step_once_ = true; return;
    case Command::Kind::Speed:
        speed_ = c.value;
        reanchor(now, sim_time());
        pace_.clear();
        return;
    default: handle(c, now);
    }
}

void Player::loop() {
    double last_frame = -1e9, last_status = -1e9;
    publish_frame();
    publish_status();
    reanchor(wall_seconds(), 0);
    while (!stop_) {
        std::vector<Command> cmds;
        {
            std::lock_guard lock(m_);
            cmds.swap(queue_);
        }
        for (Command& c : cmds) command_now(c);
        const double now = wall_seconds();
        const bool moved = advance(now);
        const double after = wall_seconds();
        if (after - last_frame >= kFrameEvery || (moved && paused_)) {
            publish_frame();
            last_frame = after;
        }
        if (after - last_status >= kStatusEvery || (moved && paused_)) {
            publish_status();
            last_status = after;
        }
        if (!moved) {
            // Nothing due: sleep until the next step is, a frame is to be published, or a
            // command arrives (at most 5 ms, so pacing stays fine-grained).
            std::unique_lock lock(m_);
            cv_.wait_for(lock, std::chrono::milliseconds(paused_ ? 20 : 2),
                         [this] { return stop_.load() || !queue_.empty(); });
        }
    }
    // Where the player stopped, for what is asked after (the session's events file ends here).
    publish_frame();
    publish_status();
}

// ---- live ----

namespace {

class LivePlayer final : public Player {
public:
    LivePlayer(const graph::Graph& g, engine::Options opt, ModelDirs dirs, bool paused, double speed,
               std::vector<engine::Event> scheduled, engine::RunLink* link, std::vector<faults::Drill> drills)
        : Player(g, paused, speed), opt_(opt), dirs_(std::move(dirs)), tracker_(g), tally_(g),
          scheduled_(std::move(scheduled)), link_(link) {
        slots_ = engine::slot_index(g);
        for (faults::Drill& d : drills) drills_.add(std::move(d));  // noted in the events file by restart()
        std::stable_sort(scheduled_.begin(), scheduled_.end(),
                         [](const engine::Event& a, const engine::Event& b) { return a.time < b.time; });
        restart();
    }
    // The player's thread calls this class's overrides: it stops before they go.
    ~LivePlayer() override { stop(); }
    bool live() const override { return true; }

private:
    void restart() {
        engine_ = std::make_unique<engine::Engine>(g_, opt_);
        planned_ = engine::plant_events(g_);
        next_planned_ = next_scheduled_ = 0;
        tally_.reset();
        pending_.clear();
        watched_.clear();
        watched_version_ = ~uint64_t(0);
        clear_log();
        clear_forces();
        drills_.reset();
        note_drills();
        history_reset(g_.records.size());
        history_add(0, history_sample(*engine_, tally_));
        history_ready();
        new_scene(scene_json(g_, dirs_, false, 0));
    }

    double sim_time() const override { return engine_->time(); }

    void handle(Command& c, double now) override {
        if (c.kind == Command::Kind::Restart) {
            restart();
            reanchor(now, 0);
        } else if (c.kind == Command::Kind::Event) {
            pending_.push_back({std::move(c.event), c.client, std::move(c.role)});
        } else if (c.kind == Command::Kind::Drill) {
            c.drill.by = "page " + std::to_string(c.client);
            c.drill.role = c.role;
            drills_.add(std::move(c.drill));
            note(drill_comment(drills_.list().size() - 1));
        } else if (c.kind == Command::Kind::DrillCancel) {
            cancel_drill(int(c.value), c.client, c.role);
        }  // Seek: live runs cannot seek (refused by the server)
    }

    // Applies an event before the next step and logs it: the pages see every event, the
    // session's events file gets all but the plant file's own (a replay applies those again).
    // In the session's events file each line follows a comment that says who sent it and
    // when on the wall clock (serve/report.h), which `plant report` reads and a replay skips.
    // `shown`: a drill's force that trainees see (faults/drill.h); every other is hidden.
    void apply(engine::Event& ev, const std::string& by, bool to_file, int client = -1, const std::string& role = {},
               bool shown = false) {
        engine::apply_event(*engine_, ev);
        const std::string line = engine::format_event(g_, ev, engine_->dt());
        const std::string noted = session_comment(by, role, wall_clock()) + "\n" + line;
        json j{{"type", "event"}, {"line", line}, {"time", ev.time}, {"by", by}};
        if (client >= 0) j["client"] = client;
        if (!to_file) j["planned"] = true;
        log(ev.time, j.dump(-1, ' ', false, json::error_handler_t::replace), noted, to_file, ev.force && !shown);
        note_force(ev, line, by, shown);
    }

    bool advance(double now) override {
        watch_inspected();
        bool step = false;
        if (paused_) {
            step = step_once_;
            step_once_ = false;
        } else if (speed_ == 0) {
            step = true;
        } else {
            const double target = paced_target(now);
            if (target - engine_->time() > 0.25) reanchor(now, engine_->time());  // cannot keep up: no burst
            step = engine_->time() + engine_->dt() <= paced_target(now) + 1e-12;
        }
        if (!step) return false;
        // The plant file's own timed inputs (its scheduled faults), then the command line's,
        // as `plant run` applies them; then the pages' events, applied before the step they
        // feed, at the time that step ends: exactly what `plant run --events` does with the
        // logged line.
        for (; next_planned_ < planned_.size() && engine::due(*engine_, planned_[next_planned_]); ++next_planned_)
            apply(planned_[next_planned_], "plant file", false);
        for (; next_scheduled_ < scheduled_.size() && engine::due(*engine_, scheduled_[next_scheduled_]); ++next_scheduled_)
            apply(scheduled_[next_scheduled_], "command line", true);
        // Drills that fire now (a time, a condition on the last step, a repair): logged as the
        // timed events they become, so a replay needs no drill.
        fired_.clear();
        drills_.due(*engine_, fired_);
        for (faults::Drills::Fired& f : fired_) {
            const faults::Drill& d = drills_.list()[f.drill];
            apply(f.event, fmt_drill(f), true, -1, d.role, d.shown);
        }
        for (Pending& p : pending_) {
            p.event.time = double(engine_->steps() + 1) * engine_->dt();
            apply(p.event, "page " + std::to_string(p.client), true, p.client, p.role);
        }
        pending_.clear();
        // The link's clients (an OPC UA server) after the page's, logged alike: the session's
        // events file replays them.
        if (link_) {
            link_->before_step(*engine_);
            const double t = double(engine_->steps() + 1) * engine_->dt();
            for (const engine::Event* ev : link_->applied()) {
                const std::string line = engine::format_event(g_, *ev, engine_->dt());
                const json j{{"type", "event"}, {"line", line}, {"time", t}, {"by", "OPC UA link"}, {"client", "link"}};
                log(t, j.dump(-1, ' ', false, json::error_handler_t::replace),
                    session_comment("OPC UA link", "", wall_clock()) + "\n" + line, true, ev->force);
                note_force(*ev, line, "OPC UA link");
            }
        }
        engine_->step();
        if (link_) link_->after_step(*engine_);
        tally_.step(*engine_);
        if (history_due(engine_->time())) history_add(engine_->time(), history_sample(*engine_, tally_));
        return true;
    }

    // Outputs of newly inspected objects are refreshed from now on (watching changes no result).
    void watch_inspected() {
        if (inspected_version() == watched_version_) return;
        watched_version_ = inspected_version();
        for (const std::string& p : inspected())
            if (watched_.insert(p).second)
                for (graph::SlotId sl : object_slots(g_, p)) engine_->watch(sl);
    }

    void publish_frame() override {
        tracker_.take(*engine_);
        put_frame(tracker_);
    }

    // Each drill as scheduled, in the session's events file: the report names a drill's
    // fault by its line.
    std::string drill_comment(size_t i) const {
        const faults::Drill& d = drills_.list()[i];
        return session_drill_comment(int(i + 1), d.role.empty() ? d.by : d.by + " (" + d.role + ")", d.text);
    }
    void note_drills() {
        for (size_t i = 0; i < drills_.list().size(); ++i) {
            note(drill_comment(i));
            note_cancelled(i);
        }
    }

    // A waiting drill dropped before it fires: it touches no plant state, so the session's
    // events file gets only a comment (which a replay skips and the report reads), and the
    // instructors' logs a line (a trainee's page never hears of drills); one that cannot be
    // cancelled (it fired, or there is no such drill) is said so in their logs.
    void cancel_drill(int number, int client, const std::string& role) {
        const std::string by = "page " + std::to_string(client);
        std::string why;
        const double t = engine_->time();
        const bool ok = drills_.cancel(number, t, role.empty() ? by : by + " (" + role + ")", why);
        json j{{"type", "drill"}, {"id", number}, {"time", t}, {"by", by}, {"client", client}};
        if (ok) j["state"] = "cancelled";
        else j["refused"] = why;
        const std::string comment = session_drill_cancel_comment(number, t, engine_->dt(), by, role, wall_clock());
        log(t, j.dump(-1, ' ', false, json::error_handler_t::replace), comment, ok, true);
    }
    // A drill cancelled in an earlier run of the session stays so after a restart: the new
    // events file says it from the start.
    void note_cancelled(size_t i) {
        const faults::Drill& d = drills_.list()[i];
        if (d.state == faults::Drill::State::Cancelled)
            note(session_drill_cancel_comment(int(i + 1), 0, engine_->dt(), d.cancelled_by, "", wall_clock()));
    }

    static std::string fmt_drill(const faults::Drills::Fired& f) {
        return "drill " + std::to_string(f.drill + 1) + (f.repair ? " repair" : "");
    }

    // The drills and their state, for the instructor's page.
    std::string drills_json() const {
        json out = json::array();
        for (size_t i = 0; i < drills_.list().size(); ++i) {
            const faults::Drill& d = drills_.list()[i];
            out.push_back({{"id", i + 1}, {"text", d.text}, {"state", faults::word(d.state)}, {"shown", d.shown},
                           {"by", d.by}, {"fired", d.fired}, {"ended", d.ended}});
        }
        return out.dump(-1, ' ', false, json::error_handler_t::replace);
    }

    void publish_status() override {
        StatusExtra x;
        x.paused = paused_;
        x.speed = speed_;
        x.rtf = paused_ ? 0 : achieved(wall_seconds(), engine_->time());
        StatusPub::View trainee;
        x.forced = forced_json(true);  // only drills' shown forces ("" none: no "forced")
        trainee.status = status_json(*engine_, tally_, x);
        x.forced = forced_json();
        StatusPub::View instructor;
        instructor.status = status_json(*engine_, tally_, x);
        if (!drills_.empty() && !instructor.status.empty() && instructor.status.back() == '}') {
            instructor.status.pop_back();
            instructor.status += ",\"drills\":" + drills_json() + "}";
        }
        for (const std::string& p : inspected()) {
            instructor.inspect[p] = inspect_json(*engine_, p);
            trainee.inspect[p] = inspect_json(*engine_, p, false);
        }
        put_status(std::move(instructor), std::move(trainee));
    }

    engine::Options opt_;
    ModelDirs dirs_;
    std::unique_ptr<engine::Engine> engine_;
    FrameTracker tracker_;
    engine::RecordTally tally_;
    struct Pending {
        engine::Event event;
        int client = 0;
        std::string role;
    };
    std::vector<Pending> pending_;
    std::vector<engine::Event> planned_;    // engine::plant_events, by time
    std::vector<engine::Event> scheduled_;  // the command line's, by time
    size_t next_planned_ = 0, next_scheduled_ = 0;
    faults::Drills drills_;
    std::vector<faults::Drills::Fired> fired_;
    std::set<std::string> watched_;
    uint64_t watched_version_ = ~uint64_t(0);
    engine::RunLink* link_ = nullptr;
};

// ---- replay ----

const graph::Graph& empty_graph() {
    static const graph::Graph g;
    return g;
}

class ReplayPlayer final : public Player {
public:
    ReplayPlayer(Recording rec, bool paused, double speed)
        : Player(empty_graph(), paused, speed), rec_(std::move(rec)), tracker_(shape_graph()) {
        json s = json::parse(rec_.scene, nullptr, false);
        s["mode"] = "replay";
        s["duration"] = rec_.duration;
        new_scene(s.dump(-1, ' ', false, json::error_handler_t::replace));
        cur_ = Frame::sized(rec_.bodies, rec_.graphics);
        records_ = s.contains("records") && s["records"].is_array() ? s["records"].size() : 0;
        samples_.reserve(rec_.statuses.size());
        for (const auto& c : rec_.statuses) samples_.push_back(sample_of(c));
        seek(0);
    }
    ~ReplayPlayer() override { stop(); }
    bool live() const override { return false; }

private:
    // A graph with the recording's counts of bodies and graphics, for the tracker.
    const graph::Graph& shape_graph() {
        shape_.bodies.resize(rec_.bodies);
        for (auto& b : shape_.bodies) b.mode = graph::BodyMode::Dynamic;
        shape_.graphics.resize(rec_.graphics);
        return shape_;
    }

    // A recorded status as a history sample: the counters, then the records.
    std::vector<double> sample_of(const Recording::Chunk& c) const {
        std::vector<double> v(kCounters + records_, 0.0);
        const json j = json::parse(c.data, nullptr, false);
        if (!j.is_object()) return v;
        if (auto it = j.find("counters"); it != j.end() && it->is_object())
            for (size_t k = 0; k < kCounters; ++k)
                if (auto x = it->find(kCounterNames[k]); x != it->end() && x->is_number()) v[k] = x->get<double>();
        if (auto it = j.find("records"); it != j.end() && it->is_array())
            for (size_t k = 0; k < records_ && k < it->size(); ++k)
                if ((*it)[k].is_number()) v[kCounters + k] = (*it)[k].get<double>();
        return v;
    }
    // The history up to time t, from the recorded statuses.
    void sample_until(double t) {
        for (; next_sample_ < rec_.statuses.size() && rec_.statuses[next_sample_].time <= t + 1e-9; ++next_sample_)
            if (history_due(rec_.statuses[next_sample_].time))
                history_add(rec_.statuses[next_sample_].time, samples_[next_sample_]);
    }

    // The state at time t: from the last full frame at or before it, forward.
    void seek(double t) {
        t = std::clamp(t, 0.0, rec_.duration);
        history_reset(records_);
        next_sample_ = 0;
        sample_until(t);
        history_ready();
        size_t k = 0;
        for (size_t i = 0; i < rec_.frames.size() && rec_.frames[i].time <= t + 1e-9; ++i)
            if (rec_.frames[i].full) k = i;
        next_ = k;
        apply_until(t);
        time_ = t;
        clear_log();
        next_event_ = 0;
        emit_events(t);
    }
    void apply_until(double t) {
        bool full = false;
        for (; next_ < rec_.frames.size() && rec_.frames[next_].time <= t + 1e-9; ++next_)
            decode_frame(rec_.frames[next_].data, cur_, full);
    }
    void emit_events(double t) {
        for (; next_event_ < rec_.events.size() && rec_.events[next_event_].time <= t + 1e-9; ++next_event_) {
            const json j = json::parse(rec_.events[next_event_].data, nullptr, false);
            const std::string line = j.is_object() ? j.value("line", std::string()) : std::string();
            // "12.3s force PATH open", "12.3s release PATH": a fault, not for trainees.
            const size_t sp = line.find(' ');
            const std::string_view what = sp == std::string::npos ? std::string_view() : std::string_view(line).substr(sp + 1);
            log(rec_.events[next_event_].time, rec_.events[next_event_].data, line, true,
                what.starts_with("force ") || what.starts_with("release "));
        }
    }

    double sim_time() const override { return time_; }
    void before_run() override {
        if (time_ >= rec_.duration) seek(0);
    }

    void handle(Command& c, double now) override {
        if (c.kind == Command::Kind::Restart || c.kind == Command::Kind::Seek) {
            seek(c.kind == Command::Kind::Seek ? c.value : 0);
            reanchor(now, time_);
            moved_ = true;
        }  // Event: refused by the server, a replay is read-only
    }

    bool advance(double now) override {
        double t = time_;
        if (paused_) {
            if (!step_once_ && !moved_) return false;
            if (step_once_ && next_ < rec_.frames.size()) t = rec_.frames[next_].time;
            step_once_ = false;
        } else {
            t = speed_ == 0 ? time_ + 1.0 / 30 : paced_target(now);
        }
        moved_ = false;
        if (t >= rec_.duration) {
            t = rec_.duration;
            paused_ = true;
        }
        if (t <= time_ && next_ >= rec_.frames.size()) return false;
        apply_until(t);
        emit_events(t);
        sample_until(t);
        time_ = t;
        return true;
    }

    void publish_frame() override {
        tracker_.put(cur_);
        put_frame(tracker_);
    }

    void publish_status() override {
        // The last status recorded at or before now, with the player's own state.
        const Recording::Chunk* last = nullptr;
        for (const auto& s : rec_.statuses)
            if (s.time <= time_ + 1e-9) last = &s;
        json j = last ? json::parse(last->data, nullptr, false) : json::object();
        if (!j.is_object()) j = json::object();
        j["type"] = "status";
        j["time"] = time_;
        j["paused"] = paused_;
        j["speed"] = speed_;
        j["rtf"] = paused_ ? 0 : achieved(wall_seconds(), time_);
        StatusPub::View instructor, trainee;
        instructor.status = j.dump(-1, ' ', false, json::error_handler_t::replace);
        j.erase("forced");
        trainee.status = j.dump(-1, ' ', false, json::error_handler_t::replace);
        put_status(std::move(instructor), std::move(trainee));
    }

    Recording rec_;
    size_t records_ = 0;                       // the scene's records
    std::vector<std::vector<double>> samples_;  // each recorded status as a history sample
    size_t next_sample_ = 0;
    graph::Graph shape_;
    FrameTracker tracker_;
    Frame cur_;
    size_t next_ = 0, next_event_ = 0;
    double time_ = 0;
    bool moved_ = false;
};

}  // namespace

std::unique_ptr<Player> make_live_player(const graph::Graph& g, engine::Options opt, ModelDirs dirs, bool paused,
                                         double speed, std::vector<engine::Event> scheduled, engine::RunLink* link,
                                         std::vector<faults::Drill> drills) {
    return std::make_unique<LivePlayer>(g, opt, std::move(dirs), paused, speed, std::move(scheduled), link,
                                        std::move(drills));
}

std::unique_ptr<Player> make_replay_player(Recording rec, bool paused, double speed) {
    return std::make_unique<ReplayPlayer>(std::move(rec), paused, speed);
}

}  // namespace plant::view
