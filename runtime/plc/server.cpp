#include "plc/server.h"

#include "engine/interrupt.h"
#include "engine/events.h"
#include "graph/range.h"
#include "graph/utf8.h"
#include "plc/codec.h"
#include "plc/frames.h"

#include <fmt/format.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <mutex>
#include <thread>
#include <utility>

namespace plant::plc {

using graph::SlotType;
using Clock = std::chrono::steady_clock;

namespace {

// What clients wrote to one entry since the step thread last took it.
struct Pending {
    bool set = false;      // a value to apply
    double value = 0;
    std::string text;      // string entries
    int32_t fires = 0;     // void entries: writes of 1 (each fires the input once)
};

struct PendingFault {
    bool set = false;
    engine::ForceMode mode = engine::ForceMode::None;
    double value = 0;
};

struct Client {
    int fd = -1;
    std::vector<uint8_t> buf;
    Clock::time_point partial_since{};
};

// Whether a written value stays within the range of the physics it moves (graph/range.h: a
// belt's speed within 100 km/s): out of it, it is refused like a value that is not finite.
bool in_range(const engine::Engine& e, const engine::Event& ev, double v) {
    for (graph::SlotId s : ev.slots)
        if (!graph::input_range(e.graph(), s, &v).empty()) return false;
    return true;
}

}  // namespace

struct Server::Impl {
    const graph::Graph& g;
    ServerOptions opt;
    Tables tables;
    const Map& map;
    modbus_t* ctx = nullptr;
    int listen_fd = -1, wake[2] = {-1, -1}, port = 0;
    std::thread net;
    std::atomic<bool> stopping{false};

    // Shared between the threads, under mu.
    std::mutex mu;
    std::condition_variable granted;
    std::vector<Pending> pending;
    std::vector<PendingFault> faults;
    int64_t budget = 0;                 // lock-step: steps granted and not yet run
    std::vector<uint16_t> snapshot;     // the outputs' registers, entry after entry
    uint16_t status[kStatusCount] = {};
    uint64_t generation = 0;
    ServerStats stats;

    // The step thread's own, sized once.
    std::vector<int32_t> offset;        // entry -> its first register in the snapshot (-1: an input)
    std::vector<uint16_t> out;
    std::vector<uint64_t> active_count;
    std::vector<Pending> taken;
    std::vector<PendingFault> taken_faults;
    std::vector<int32_t> carry;         // void fires still to apply, one per step
    std::vector<engine::Event> events, force_events;
    std::vector<const engine::Event*> applied_now;  // what the last before_step applied
    std::vector<uint8_t> applied_once;
    std::vector<double> last_value;
    std::vector<std::string> last_text;
    bool watched = false;

    // The network thread's own.
    std::vector<Client> clients;
    std::vector<Change> changes;
    uint64_t seen_generation = ~uint64_t(0);

    Impl(const graph::Graph& graph, Map m, ServerOptions o) : g(graph), opt(std::move(o)), tables(m), map(tables.map()) {
        const size_t n = map.entries.size();
        pending.resize(n);
        faults.resize(n);
        taken.resize(n);
        taken_faults.resize(n);
        carry.assign(n, 0);
        active_count.assign(n, 0);
        applied_once.assign(n, 0);
        last_value.assign(n, 0);
        last_text.resize(n);
        offset.assign(n, -1);
        int32_t regs = 0;
        for (size_t i = 0; i < n; ++i) {
            const Entry& e = map.entries[i];
            if (e.encoding == Encoding::String)  // strings never outgrow their registers: no allocation per step
                for (std::string* s : {&pending[i].text, &taken[i].text, &last_text[i]}) s->reserve(2 * e.length + 1);
            engine::Event ev;
            ev.path = e.path;
            ev.slots = e.slots;
            ev.value.assign(1, 0);
            ev.text.reserve(2 * e.length + 1);
            events.push_back(ev);
            ev.force = true;
            force_events.push_back(ev);
            if (!written_by_plc(e.table)) {
                offset[i] = regs;
                regs += width(e);
            }
        }
        out.assign(regs, 0);
        snapshot.assign(regs, 0);
        status[kStatusLockstep - kStatusSteps] = opt.lockstep ? 1 : 0;  // before the first step too
        applied_now.reserve(2 * n);
        clients.reserve(opt.max_clients);
        changes.reserve(256);
    }

    ~Impl() { shutdown(); }

    void shutdown() {
        if (net.joinable()) {
            stopping = true;
            granted.notify_all();
            const char c = 0;
            if (write(wake[1], &c, 1) < 0) {}  // the loop also wakes on its own every 100 ms
            net.join();
        }
        for (Client& c : clients) close(c.fd);
        clients.clear();
        for (int* fd : {&listen_fd, &wake[0], &wake[1]})
            if (*fd >= 0) {
                close(*fd);
                *fd = -1;
            }
        if (ctx) {
            modbus_set_socket(ctx, -1);
            modbus_free(ctx);
            ctx = nullptr;
        }
    }

    bool start(std::string& error) {
        in_addr probe{};
        if (inet_pton(AF_INET, opt.host.c_str(), &probe) != 1) {
            error = fmt::format("modbus host '{}' is not an IPv4 address (e.g. 127.0.0.1)", opt.host);
            return false;
        }
        if (opt.port < 0 || opt.port > 65535) {
            error = fmt::format("modbus port {} is not a port number (0 to 65535; 0 picks a free one)", opt.port);
            return false;
        }
        ctx = modbus_new_tcp(opt.host.c_str(), opt.port);
        if (!ctx) {
            error = fmt::format("modbus: {}", modbus_strerror(errno));
            return false;
        }
        listen_fd = modbus_tcp_listen(ctx, 64);
        if (listen_fd < 0) {
            error = fmt::format("modbus: cannot listen on {}:{}: {}", opt.host, opt.port, modbus_strerror(errno));
            return false;
        }
        sockaddr_in addr{};
        socklen_t len = sizeof addr;
        getsockname(listen_fd, reinterpret_cast<sockaddr*>(&addr), &len);
        port = ntohs(addr.sin_port);
        if (pipe2(wake, O_CLOEXEC | O_NONBLOCK) != 0) {
            error = fmt::format("modbus: pipe: {}", std::strerror(errno));
            return false;
        }
        net = std::thread([this] { loop(); });
        return true;
    }

    // ---- the network thread ----

    enum class Serve : uint8_t { Ok, Left, Drop };

    void remove(size_t i, Serve why) {
        close(clients[i].fd);
        clients[i] = std::move(clients.back());
        clients.pop_back();
        std::lock_guard lock(mu);
        stats.clients = int64_t(clients.size());
        ++(why == Serve::Left ? stats.left : stats.dropped);
    }

    void accept_client() {
        const int fd = accept4(listen_fd, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd < 0) return;
        std::lock_guard lock(mu);
        if (std::cmp_greater_equal(clients.size(), opt.max_clients) || fd >= FD_SETSIZE) {
            close(fd);
            ++stats.refused;
            return;
        }
        const int one = 1;
        setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        clients.push_back({fd, {}, {}});
        clients.back().buf.reserve(2 * MODBUS_TCP_MAX_ADU_LENGTH);
        ++stats.accepted;
        stats.clients = int64_t(clients.size());
    }

    // The latest published outputs and the lock-step grant into the served tables.
    void refresh() {
        modbus_mapping_t& m = tables.mapping();
        std::lock_guard lock(mu);
        m.tab_registers[kAdvance] = uint16_t(std::min<int64_t>(budget, 65535));
        if (generation == seen_generation) return;
        seen_generation = generation;
        for (size_t i = 0; i < map.entries.size(); ++i) {
            if (offset[i] < 0) continue;
            const Entry& e = map.entries[i];
            const uint16_t* r = &snapshot[offset[i]];
            if (e.table == Table::DiscreteInput) m.tab_input_bits[e.address] = uint8_t(r[0] != 0);
            else std::copy(r, r + width(e), m.tab_input_registers + e.address);
        }
        std::copy(status, status + kStatusCount, m.tab_input_registers + kStatusSteps);
    }

    // A request's changes into the pending writes (the caller holds mu).
    void take_changes() {
        if (changes.empty()) return;
        const modbus_mapping_t& m = tables.mapping();
        for (const Change& c : changes) {
            if (c.kind == Change::Advance) {
                budget += c.steps;
                continue;
            }
            const Entry& e = map.entries[c.entry];
            if (c.kind == Change::Fault) {
                const uint16_t* r = m.tab_registers + kFaultBase + kFaultStride * c.entry;
                PendingFault& f = faults[c.entry];
                f.set = true;
                f.mode = engine::ForceMode(r[0]);
                f.value = double(get_float(r + 1));
                continue;
            }
            uint16_t bit;
            const uint16_t* r = m.tab_registers + e.address;
            if (e.table == Table::Coil) {
                bit = m.tab_bits[e.address];
                r = &bit;
            }
            Pending& p = pending[c.entry];
            if (e.type == SlotType::Void) {
                if (decode(e, r) != 0) ++p.fires;
            } else {
                p.set = true;
                if (e.type == SlotType::String) decode_text(e, r, p.text);
                else p.value = decode(e, r);
            }
        }
        granted.notify_all();
        changes.clear();
    }

    // Reads what arrived and answers every complete frame.
    Serve serve(Client& c) {
        uint8_t chunk[4096];
        const ssize_t got = recv(c.fd, chunk, sizeof chunk, 0);
        if (got == 0) return Serve::Left;
        if (got < 0) return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR ? Serve::Ok : Serve::Left;
        c.buf.insert(c.buf.end(), chunk, chunk + got);
        size_t at = 0;
        bool ok = true;
        while (ok) {
            const int len = frame_length(c.buf.data() + at, c.buf.size() - at);
            if (len < 0) ok = false;  // not Modbus TCP: nothing after it can be framed
            if (len <= 0) break;
            refresh();
            modbus_set_socket(ctx, c.fd);
            // Answered and taken under the lock before_step takes: a client that has its
            // answer finds its write applied at the next step (it was answered before it
            // was taken, and a step in between missed it).
            std::lock_guard lock(mu);
            const int64_t before = tables.exceptions();
            ok = tables.handle(ctx, c.buf.data() + at, len, changes);
            take_changes();
            ++stats.requests;
            stats.exceptions += tables.exceptions() - before;
            at += len;
        }
        c.buf.erase(c.buf.begin(), c.buf.begin() + std::ptrdiff_t(std::min(at, c.buf.size())));
        c.partial_since = c.buf.empty() ? Clock::time_point{} : c.partial_since == Clock::time_point{} ? Clock::now() : c.partial_since;
        return ok ? Serve::Ok : Serve::Drop;
    }

    void loop() {
        while (!stopping) {
            fd_set rd;
            FD_ZERO(&rd);
            FD_SET(listen_fd, &rd);
            FD_SET(wake[0], &rd);
            int top = std::max(listen_fd, wake[0]);
            for (const Client& c : clients) {
                FD_SET(c.fd, &rd);
                top = std::max(top, c.fd);
            }
            timeval tv{0, 100000};
            const int n = select(top + 1, &rd, nullptr, nullptr, &tv);
            if (stopping) break;
            if (n < 0) continue;  // EINTR
            for (size_t i = clients.size(); i-- > 0;)
                if (FD_ISSET(clients[i].fd, &rd))
                    if (const Serve how = serve(clients[i]); how != Serve::Ok) remove(i, how);
            const auto now = Clock::now();
            for (size_t i = clients.size(); i-- > 0;)  // a frame left half sent: the client is gone or stuck
                if (clients[i].partial_since != Clock::time_point{} &&
                    std::chrono::duration<double>(now - clients[i].partial_since).count() > opt.partial_timeout)
                    remove(i, Serve::Drop);
            if (FD_ISSET(listen_fd, &rd)) accept_client();
        }
    }

    // ---- the step thread ----

    void watch(engine::Engine& e) {
        for (size_t i = 0; i < map.entries.size(); ++i)
            if (offset[i] >= 0) e.watch(graph::SlotId(map.entries[i].slots[0]));
        watched = true;
    }

    void before_step(engine::Engine& e) {
        if (!watched) watch(e);
        {
            std::lock_guard lock(mu);
            for (size_t i = 0; i < pending.size(); ++i) {
                Pending& p = pending[i];
                if (p.set) {
                    taken[i].set = true;
                    taken[i].value = p.value;
                    taken[i].text = p.text;
                    p.set = false;
                }
                carry[i] += p.fires;
                p.fires = 0;
                if (faults[i].set) {
                    taken_faults[i] = faults[i];
                    faults[i].set = false;
                }
            }
        }
        int64_t rejected = 0;
        applied_now.clear();
        // Each event carries the time of the step it feeds, as the page's do: logged or recorded,
        // it replays in that step (an events file, `plant run --events`).
        const double at = double(e.steps() + 1) * e.dt();
        for (size_t i = 0; i < taken.size(); ++i) {
            const Entry& en = map.entries[i];
            if (taken_faults[i].set) {
                taken_faults[i].set = false;
                engine::Event& ev = force_events[i];
                ev.mode = taken_faults[i].mode;
                const double v = taken_faults[i].value;
                if (ev.mode == engine::ForceMode::Stuck && (!std::isfinite(v) || !in_range(e, ev, v))) {
                    ++rejected;
                } else {
                    ev.value.resize(ev.mode == engine::ForceMode::Stuck ? 1 : 0);  // within its capacity
                    if (!ev.value.empty())
                        ev.value[0] = en.type == SlotType::Int ? std::round(v) : en.type == SlotType::Real ? v : v != 0 ? 1 : 0;
                    ev.time = at;
                    engine::apply_event(e, ev);
                    applied_now.push_back(&ev);
                }
            }
            engine::Event& ev = events[i];
            if (en.type == SlotType::Void) {
                if (carry[i] > 0) {  // one fire per step: a second would land in the same step
                    --carry[i];
                    ev.value.clear();
                    ev.time = at;
                    engine::apply_event(e, ev);
                    applied_now.push_back(&ev);
                }
                continue;
            }
            if (!taken[i].set) continue;
            taken[i].set = false;
            const double v = en.type == SlotType::Bool ? (taken[i].value != 0 ? 1 : 0)
                              : en.type == SlotType::Int ? std::round(taken[i].value) : taken[i].value;
            // Not finite, out of the physics' range, or a string that is not UTF-8 (it would
            // reach traces and the viewer as is): rejected, counted.
            if (!std::isfinite(v) || !in_range(e, ev, v) ||
                (en.type == SlotType::String && graph::invalid_utf8(taken[i].text) != std::string::npos)) {
                ++rejected;
                continue;
            }
            const bool same = applied_once[i] && (en.type == SlotType::String ? last_text[i] == taken[i].text : last_value[i] == v);
            if (same) continue;  // a PLC writes its outputs every scan: only a change is an input
            applied_once[i] = 1;
            last_value[i] = v;
            last_text[i] = taken[i].text;
            ev.value.assign(1, v);
            ev.text = taken[i].text;
            ev.time = at;
            engine::apply_event(e, ev);
            applied_now.push_back(&ev);
        }
        if (!applied_now.empty() || rejected) {
            std::lock_guard lock(mu);
            stats.applied += int64_t(applied_now.size());
            stats.rejected += rejected;
        }
    }

    void after_step(const engine::Engine& e) {
        for (size_t i = 0; i < map.entries.size(); ++i) {
            if (offset[i] < 0) continue;
            const Entry& en = map.entries[i];
            const graph::SlotId s(en.slots[0]);
            const bool active = e.active(s);
            active_count[i] += active ? 1 : 0;
            const std::span<const double> v = en.type == SlotType::Void ? std::span<const double>{} : e.value(s);
            const std::string_view text = en.type == SlotType::String && !v.empty() ? e.str(int32_t(v[0])) : std::string_view{};
            encode(en, v, text, active, active_count[i], &out[offset[i]]);
        }
        uint16_t st[kStatusCount];
        put_u32(uint32_t(e.steps()), st);
        put_u32(uint32_t(std::llround(e.time() * 1000)), st + 2);
        st[kStatusLockstep - kStatusSteps] = opt.lockstep ? 1 : 0;
        std::lock_guard lock(mu);
        std::copy(out.begin(), out.end(), snapshot.begin());
        std::copy(st, st + kStatusCount, status);
        ++generation;
        if (opt.lockstep && budget > 0) --budget;
    }

    bool wait_for_step(std::string& error) {
        std::unique_lock lock(mu);
        const auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                               std::chrono::duration<double>(opt.lockstep_timeout));
        // In slices, so that a SIGINT during `plant run --lockstep` is seen.
        while (budget <= 0 && !stopping && Clock::now() < until && !engine::InterruptGuard::requested())
            granted.wait_for(lock, std::min<Clock::duration>(std::chrono::milliseconds(100), until - Clock::now()));
        if (budget > 0) return true;
        error.clear();
        if (engine::InterruptGuard::requested()) return false;
        error = stopping ? "the Modbus server stopped"
                         : fmt::format("lock-step: no client advanced the plant for {:g} s (write N to holding register {} "
                                       "on {}:{} to run N steps)", opt.lockstep_timeout, kAdvance, opt.host, port);
        return false;
    }
};

Server::Server(const graph::Graph& g, Map map, ServerOptions options)
    : impl_(std::make_unique<Impl>(g, std::move(map), std::move(options))) {}
Server::~Server() = default;
bool Server::start(std::string& error) { return impl_->start(error); }
int Server::port() const { return impl_->port; }
void Server::stop() { impl_->shutdown(); }
void Server::before_step(engine::Engine& e) { impl_->before_step(e); }
std::span<const engine::Event* const> Server::applied() const { return impl_->applied_now; }
void Server::after_step(const engine::Engine& e) { impl_->after_step(e); }
bool Server::wait_for_step(std::string& error) { return impl_->wait_for_step(error); }
const Map& Server::map() const { return impl_->map; }

ServerStats Server::stats() const {
    std::lock_guard lock(impl_->mu);
    return impl_->stats;
}

}  // namespace plant::plc
