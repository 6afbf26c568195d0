#include "opcua/bridge.h"

#include "engine/interrupt.h"
#include "graph/range.h"
#include "graph/utf8.h"
#include "opcua/channel.h"

#include <fmt/format.h>

#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace plant::opcua {

using engine::ForceMode;
using graph::SlotType;
using Clock = std::chrono::steady_clock;

namespace {

// What clients asked of one node since the step thread last took it.
struct Pending {
    bool set = false;  // a value to apply
    double value = 0;
    std::string text;  // string nodes
    int32_t fires = 0; // methods: calls (each fires the input once)
    bool force = false;
    ForceMode mode = ForceMode::None;
    double force_value = 0;
    std::string force_text;
};

struct Reply {
    uint32_t request = 0, status = 0;
    double steps = 0;
};

struct Target {  // an Advance answered once the plant has run `steps` steps
    uint32_t request = 0;
    int64_t steps = 0;
};

constexpr size_t kMaxTargets = 1024;  // Advance calls waiting at once; more: BadTooManyOperations
constexpr size_t kMaxReplies = 4 * kMaxTargets;

// The most a node's record takes in a step: its force mode and its value.
size_t record_bound(const Node& n) {
    const size_t force = 1 + 4 + 1;
    switch (n.cls) {
    case NodeClass::Method: return force;
    case NodeClass::Counter: return force + 1 + 4 + 8;
    case NodeClass::Variable: break;
    }
    return force + (n.type == SlotType::String ? 1 + 4 + 4 + kMaxText : 1 + 4 + 8);
}

bool send_all(int fd, const uint8_t* p, size_t n) {
    while (n > 0) {
        const ssize_t k = ::send(fd, p, n, MSG_NOSIGNAL);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) return false;
        p += k;
        n -= size_t(k);
    }
    return true;
}

}  // namespace

struct Bridge::Impl {
    const graph::Graph& g;
    Link link;
    BridgeOptions opt;
    int fd = -1;
    std::thread reader, writer;
    std::atomic<bool> dead{false};

    // Shared between the threads, under mu.
    std::mutex mu;
    std::condition_variable wake_writer, granted, answered;
    std::vector<Pending> pending;
    std::vector<uint8_t> fill;    // steps not yet sent; fill_used bytes of it
    size_t fill_used = 0;
    std::vector<Reply> replies;
    std::vector<Target> targets;  // in order of their steps
    int64_t budget = 0;           // lock-step: steps granted and not yet run
    int64_t steps_now = 0;        // steps run, as of the last after_step
    bool closing = false;
    bool writer_done = false;
    bool handshaken = false;
    std::string ready, failure;   // the server's ready answer; why the channel ended
    BridgeStats stats;

    // The step thread's own, sized once.
    std::vector<Pending> taken;
    std::vector<int32_t> carry;          // method calls still to apply, one per step
    std::vector<engine::Event> events, force_events;
    std::vector<const engine::Event*> applied_now;
    std::vector<uint8_t> scratch;        // the step's records before they go into `fill`
    std::vector<double> last_value;
    std::vector<std::string> last_text;
    std::vector<uint8_t> last_forced;
    std::vector<uint64_t> count;         // counters: steps active so far
    bool need_full = true;               // the next step sends every node's value
    uint32_t dropped_since = 0;
    int64_t last_steps = -1;
    const engine::Engine* watched = nullptr;

    // The writer's own.
    std::vector<uint8_t> drain;
    std::vector<Reply> replies_out;

    Impl(const graph::Graph& graph, Link l, BridgeOptions o) : g(graph), link(std::move(l)), opt(o) {
        const size_t n = link.nodes.size();
        pending.resize(n);
        taken.resize(n);
        carry.assign(n, 0);
        last_value.assign(n, 0);
        last_text.resize(n);
        last_forced.assign(n, 0);
        count.assign(n, 0);
        size_t step = 1 + 8 + 8 + 1 + 4;  // a header and a 'D' record
        for (size_t i = 0; i < n; ++i) {
            const Node& node = link.nodes[i];
            step += record_bound(node);
            for (std::string* s : {&pending[i].text, &taken[i].text, &pending[i].force_text, &taken[i].force_text, &last_text[i]})
                s->reserve(kMaxText + 1);  // within its capacity: no allocation per step
            engine::Event ev;
            ev.path = node.path;
            ev.slots = node.slots;
            ev.value.reserve(1);
            ev.text.reserve(kMaxText + 1);
            events.push_back(ev);
            ev.force = true;
            force_events.push_back(ev);
        }
        scratch.resize(step);
        const size_t cap = std::max(opt.buffer != 0 ? opt.buffer : size_t(1) << 20, opt.buffer != 0 ? step : 8 * step);
        fill.resize(cap);
        drain.resize(cap);
        replies.reserve(kMaxReplies);
        replies_out.reserve(kMaxReplies);
        targets.reserve(kMaxTargets);
        applied_now.reserve(2 * n);
    }

    ~Impl() {
        finish(1);
        close_all();
    }

    // ---- the reader thread: the server's frames ----

    void reply(uint32_t request, uint32_t status, double steps = 0) {  // under mu
        replies.push_back({request, status, steps});
        ++stats.requests;
        if (status != status::Good) ++stats.refused;
        wake_writer.notify_one();
    }

    // A number written to node `i`, as the slot takes it; a status other than Good when not.
    uint32_t check_value(size_t i, double& v) const {
        const Node& n = link.nodes[i];
        if (!std::isfinite(v)) return status::BadOutOfRange;
        if (n.type == SlotType::Bool || n.type == SlotType::Void) v = v != 0 ? 1 : 0;
        if (n.type == SlotType::Int) {
            if (v != std::floor(v)) return status::BadTypeMismatch;
            if (std::fabs(v) > 9007199254740992.0) return status::BadOutOfRange;
        }
        if (n.dir == graph::Dir::In)  // graph/range.h: a belt's speed within 100 km/s, ...
            for (graph::SlotId s : n.slots)
                if (!graph::input_range(g, s, &v).empty()) return status::BadOutOfRange;
        return status::Good;
    }

    void request(char type, Reader& r) {
        const uint32_t id = r.u32();
        const uint32_t node = type == 'A' ? 0 : r.u32();
        std::lock_guard lock(mu);
        if (!r.good()) return reply(id, status::BadInvalidArgument);  // cut short
        if (type != 'A' && node >= link.nodes.size()) return reply(id, status::BadNodeIdUnknown);
        const Node* n = type == 'A' ? nullptr : &link.nodes[node];
        switch (type) {
        case 'W': {
            double v = r.f64();
            if (!r.good()) return reply(id, status::BadInvalidArgument);
            if (n->cls != NodeClass::Variable || n->dir != graph::Dir::In) return reply(id, status::BadNotWritable);
            if (n->type == SlotType::String) return reply(id, status::BadTypeMismatch);
            if (const uint32_t s = check_value(node, v); s != status::Good) return reply(id, s);
            pending[node].set = true;
            pending[node].value = v;
            return reply(id, status::Good);
        }
        case 'Y': {
            const std::string_view text = r.text();
            if (!r.good()) return reply(id, status::BadInvalidArgument);
            if (n->cls != NodeClass::Variable || n->dir != graph::Dir::In) return reply(id, status::BadNotWritable);
            if (n->type != SlotType::String) return reply(id, status::BadTypeMismatch);
            if (text.size() > kMaxText) return reply(id, status::BadOutOfRange);
            // It would reach traces and the viewer as is (graph/utf8.h, as the Modbus link checks).
            if (graph::invalid_utf8(text) != std::string_view::npos) return reply(id, status::BadDataEncodingInvalid);
            pending[node].set = true;
            pending[node].text.assign(text);
            return reply(id, status::Good);
        }
        case 'M':
            if (n->cls != NodeClass::Method) return reply(id, status::BadInvalidArgument);
            ++pending[node].fires;
            return reply(id, status::Good);
        case 'F': {
            const uint8_t mode = r.u8();
            double v = r.f64();
            const std::string_view text = r.text();
            if (!r.good() || mode > uint8_t(ForceMode::Invert)) return reply(id, status::BadInvalidArgument);
            const ForceMode m = ForceMode(mode);
            if (m == ForceMode::Invert && n->type != SlotType::Bool) return reply(id, status::BadInvalidArgument);
            if (m == ForceMode::Stuck && n->type == SlotType::String && text.size() > kMaxText)
                return reply(id, status::BadOutOfRange);
            if (m == ForceMode::Stuck && n->type == SlotType::String && graph::invalid_utf8(text) != std::string_view::npos)
                return reply(id, status::BadDataEncodingInvalid);
            if (m == ForceMode::Stuck && n->type != SlotType::String)
                if (const uint32_t s = check_value(node, v); s != status::Good) return reply(id, s);
            Pending& p = pending[node];
            p.force = true;
            p.mode = m;
            p.force_value = v;
            p.force_text.assign(text.substr(0, kMaxText));
            return reply(id, status::Good);
        }
        case 'A': {
            const uint32_t steps = r.u32();
            if (!r.good()) return reply(id, status::BadInvalidArgument);
            if (!opt.lockstep) return reply(id, status::BadInvalidState, double(steps_now));
            if (steps == 0) return reply(id, status::Good, double(steps_now));
            if (targets.size() >= kMaxTargets) return reply(id, status::BadTooManyOperations, double(steps_now));
            budget += steps;
            targets.push_back({id, steps_now + budget});
            ++stats.requests;
            granted.notify_all();
            return;
        }
        default: return;
        }
    }

    void read_loop() {
        std::vector<uint8_t> payload;
        std::string why;
        for (;;) {
            char type = 0;
            if (!read_frame(fd, type, payload, why)) break;
            Reader r(payload.data(), payload.size());
            if (type == 'R' || type == 'E') {
                std::lock_guard lock(mu);
                (type == 'R' ? ready : failure) = std::string(reinterpret_cast<const char*>(payload.data()), payload.size());
                handshaken = true;
                if (type == 'E') dead = true;  // before the handshake returns: wait() sees it
                answered.notify_all();
                if (type == 'E') break;
                continue;
            }
            request(type, r);
        }
        std::lock_guard lock(mu);
        if (failure.empty()) failure = why;
        dead = true;
        answered.notify_all();
        granted.notify_all();
        wake_writer.notify_all();
    }

    // ---- the writer thread: buffered steps and answers to the server ----

    void write_loop() {
        std::unique_lock lock(mu);
        for (;;) {
            wake_writer.wait(lock, [&] { return fill_used > 0 || !replies.empty() || closing || dead; });
            if (dead) break;
            const size_t used = fill_used;
            fill.swap(drain);
            fill_used = 0;
            replies.swap(replies_out);
            const bool last = closing && used == 0 && replies_out.empty();
            lock.unlock();
            bool ok = true;
            if (used > 0) {
                uint8_t head[kFrameHeader];
                Writer w(head, sizeof head);
                w.put_u32(uint32_t(used + 1));
                w.put_u8('S');
                ok = send_all(fd, head, sizeof head) && send_all(fd, drain.data(), used);
            }
            for (const Reply& rep : replies_out) {
                uint8_t buf[kFrameHeader + 16];
                Writer w(buf, sizeof buf);
                w.put_u32(1 + 16);
                w.put_u8('K');
                w.put_u32(rep.request);
                w.put_u32(rep.status);
                w.put_f64(rep.steps);
                ok = ok && send_all(fd, buf, w.size());
            }
            replies_out.clear();
            lock.lock();
            stats.bytes += int64_t(used);
            if (!ok || last) break;
        }
        if (fd >= 0) ::shutdown(fd, SHUT_WR);  // the server reads the end of the run
        writer_done = true;
        wake_writer.notify_all();
    }

    // ---- control ----

    void attach(int socket) {
        fd = socket;
        reader = std::thread([this] { read_loop(); });
        writer = std::thread([this] { write_loop(); });
    }

    bool handshake(const std::string& config, double timeout, std::string& out, std::string& error) {
        const std::vector<uint8_t> f = frame('C', config);
        if (!send_all(fd, f.data(), f.size())) {
            error = "the OPC UA server went away before its configuration";
            return false;
        }
        std::unique_lock lock(mu);
        const bool done = answered.wait_for(lock, std::chrono::duration<double>(timeout), [&] { return handshaken || dead; });
        if (done && handshaken && failure.empty()) {
            out = ready;
            return true;
        }
        error = !done ? fmt::format("the OPC UA server was not ready within {:g} s", timeout)
                : failure.empty() ? std::string("the OPC UA server went away") : failure;
        return false;
    }

    void finish(double timeout) {
        if (!writer.joinable()) return;
        {
            std::unique_lock lock(mu);
            closing = true;
            wake_writer.notify_all();
            granted.notify_all();
            // A server that reads nothing more would hold the writer in send() forever.
            if (!wake_writer.wait_for(lock, std::chrono::duration<double>(timeout), [&] { return writer_done; }))
                ::shutdown(fd, SHUT_RDWR);
        }
        writer.join();
    }

    void close_all() {
        if (reader.joinable()) reader.join();
        if (fd >= 0) ::close(fd);
        fd = -1;
    }

    // ---- the step thread ----

    bool wait(std::string& error) {
        if (dead) {
            std::lock_guard lock(mu);
            error = fmt::format("the OPC UA server went away ({})", failure);
            return false;
        }
        if (!opt.lockstep) return true;
        std::unique_lock lock(mu);
        const auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(opt.lockstep_timeout));
        // In slices, so that a SIGINT during `plant run --lockstep` is seen.
        while (budget <= 0 && !dead && !closing && Clock::now() < until && !engine::InterruptGuard::requested())
            granted.wait_for(lock, std::min<Clock::duration>(std::chrono::milliseconds(100), until - Clock::now()));
        if (budget > 0) return true;
        error.clear();
        if (engine::InterruptGuard::requested()) return false;
        error = dead      ? fmt::format("the OPC UA server went away ({})", failure)
                : closing ? std::string("the OPC UA link closed")
                          : fmt::format("lock-step: no client advanced the plant for {:g} s (call Link.Advance, "
                                        "ns=1;s=Link.Advance, to run N steps)", opt.lockstep_timeout);
        return false;
    }

    void before_step(engine::Engine& e) {
        if (watched != &e) {  // a new engine (plant serve restarted the run): watch its outputs
            for (const Node& n : link.nodes)
                if (n.dir == graph::Dir::Out) e.watch(graph::SlotId(n.slots[0]));
            watched = &e;
        }
        {
            std::lock_guard lock(mu);
            for (size_t i = 0; i < pending.size(); ++i) {
                Pending& p = pending[i];
                Pending& t = taken[i];
                if (p.set) {
                    t.set = true;
                    t.value = p.value;
                    t.text.assign(p.text);
                    p.set = false;
                }
                carry[i] += p.fires;
                p.fires = 0;
                if (p.force) {
                    t.force = true;
                    t.mode = p.mode;
                    t.force_value = p.force_value;
                    t.force_text.assign(p.force_text);
                    p.force = false;
                }
            }
        }
        applied_now.clear();
        // Each event carries the time of the step it feeds, as the page's do: logged or recorded,
        // it replays in that step (an events file, `plant run --events`).
        const double at = double(e.steps() + 1) * e.dt();
        for (size_t i = 0; i < taken.size(); ++i) {
            const Node& n = link.nodes[i];
            Pending& t = taken[i];
            if (t.force) {
                t.force = false;
                engine::Event& ev = force_events[i];
                ev.mode = t.mode;
                ev.value.resize(t.mode == ForceMode::Stuck && n.type != SlotType::String ? 1 : 0);  // within its capacity
                if (!ev.value.empty()) ev.value[0] = t.force_value;
                ev.text.assign(t.force_text);
                ev.time = at;
                engine::apply_event(e, ev);
                applied_now.push_back(&ev);
            }
            engine::Event& ev = events[i];
            if (n.cls == NodeClass::Method) {
                if (carry[i] > 0) {  // one call per step: a second would land in the same step
                    --carry[i];
                    ev.time = at;
                    engine::apply_event(e, ev);
                    applied_now.push_back(&ev);
                }
                continue;
            }
            if (!t.set) continue;
            t.set = false;
            // A write that leaves the input as it is is no input: a PLC may write its outputs every scan.
            const std::span<const double> now = e.value(graph::SlotId(n.slots[0]));
            const bool same = n.type == SlotType::String ? !now.empty() && e.str(int32_t(now[0])) == t.text
                                                         : !now.empty() && now[0] == t.value;
            if (same) continue;
            ev.value.resize(n.type == SlotType::String ? 0 : 1);
            if (!ev.value.empty()) ev.value[0] = t.value;
            ev.text.assign(t.text);
            ev.time = at;
            engine::apply_event(e, ev);
            applied_now.push_back(&ev);
        }
        if (!applied_now.empty()) {
            std::lock_guard lock(mu);
            stats.applied += int64_t(applied_now.size());
        }
    }

    void after_step(const engine::Engine& e) {
        if (e.steps() < last_steps) {  // the run restarted (plant serve): counts from zero, every value again
            std::fill(count.begin(), count.end(), 0);
            need_full = true;
        }
        last_steps = e.steps();
        Writer w(scratch.data(), scratch.size());
        const bool full = need_full;
        if (full && dropped_since > 0) {
            w.put_u8('D');
            w.put_u32(dropped_since);
        }
        w.put_u8('T');
        w.put_f64(double(e.steps()));
        w.put_f64(e.time());
        for (size_t i = 0; i < link.nodes.size(); ++i) {
            const Node& n = link.nodes[i];
            const graph::SlotId s(n.slots[0]);
            const uint8_t forced = uint8_t(e.forced(s));
            if (full || forced != last_forced[i]) {
                w.put_u8('Q');
                w.put_u32(uint32_t(i));
                w.put_u8(forced);
                last_forced[i] = forced;
            }
            if (n.cls == NodeClass::Method) continue;
            if (n.cls == NodeClass::Counter) {
                const bool active = e.active(s);
                count[i] += active ? 1 : 0;
                if (active || full) {
                    w.put_u8(active ? 'E' : 'V');
                    w.put_u32(uint32_t(i));
                    w.put_f64(double(count[i]));
                }
                continue;
            }
            const std::span<const double> v = e.value(s);
            const double x = v.empty() ? 0 : v[0];
            if (n.type == SlotType::String) {
                const std::string_view text = v.empty() ? std::string_view{} : e.str(int32_t(x));
                const std::string_view cut = text.substr(0, kMaxText);
                if (full || cut != last_text[i]) {
                    w.put_u8('X');
                    w.put_u32(uint32_t(i));
                    w.put_text(cut);
                    last_text[i].assign(cut);
                }
                continue;
            }
            if (full || std::memcmp(&x, &last_value[i], sizeof x) != 0) {
                w.put_u8('V');
                w.put_u32(uint32_t(i));
                w.put_f64(x);
                last_value[i] = x;
            }
        }
        std::lock_guard lock(mu);
        steps_now = e.steps();
        if (opt.lockstep && budget > 0) --budget;
        if (fill_used + w.size() <= fill.size()) {
            std::copy(scratch.begin(), scratch.begin() + std::ptrdiff_t(w.size()), fill.begin() + std::ptrdiff_t(fill_used));
            fill_used += w.size();
            need_full = false;
            dropped_since = 0;
            ++stats.steps;
        } else {  // the server is a buffer behind: this step is lost, the next that fits has everything
            need_full = true;
            ++dropped_since;
            ++stats.dropped;
        }
        while (!targets.empty() && targets.front().steps <= steps_now && replies.size() < replies.capacity()) {
            replies.push_back({targets.front().request, status::Good, double(steps_now)});
            targets.erase(targets.begin());  // a few at most: no allocation
        }
        wake_writer.notify_one();
    }
};

Bridge::Bridge(const graph::Graph& g, Link link, BridgeOptions options)
    : impl_(std::make_unique<Impl>(g, std::move(link), options)) {}
Bridge::~Bridge() = default;
void Bridge::attach(int fd) { impl_->attach(fd); }
bool Bridge::handshake(const std::string& config, double timeout, std::string& ready, std::string& error) {
    return impl_->handshake(config, timeout, ready, error);
}
bool Bridge::wait(std::string& error) { return impl_->wait(error); }
void Bridge::before_step(engine::Engine& e) { impl_->before_step(e); }
std::span<const engine::Event* const> Bridge::applied() const { return impl_->applied_now; }
void Bridge::after_step(const engine::Engine& e) { impl_->after_step(e); }
void Bridge::finish(double timeout) { impl_->finish(timeout); }
void Bridge::close() { impl_->close_all(); }
bool Bridge::alive() const { return !impl_->dead; }
const Link& Bridge::link() const { return impl_->link; }

BridgeStats Bridge::stats() const {
    std::lock_guard lock(impl_->mu);
    return impl_->stats;
}

}  // namespace plant::opcua
