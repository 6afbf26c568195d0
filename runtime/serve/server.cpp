#include "serve/server.h"

#include "faults/drill.h"
#include "faults/operable.h"
#include "graph/plugin.h"
#include "serve/protocol.h"
#include "serve/report.h"
#include "serve/roles.h"

#include <utility>  // Boost 1.74's asio headers use std::exchange without it

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <type_traits>
#include <unordered_set>
#include <thread>

namespace plant::view {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
namespace ssl = net::ssl;
using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

constexpr size_t kMaxQueued = 64;       // messages waiting for one page
constexpr size_t kMaxFile = 64u << 20;  // bytes of one served file
constexpr auto kStatusPeriod = std::chrono::milliseconds(200);

std::string error_message(std::string_view msg) {
    return json{{"type", "error"}, {"message", msg}}.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string_view content_type(const std::string& path) {
    const std::string ext = fs::path(path).extension().string();
    if (ext == ".html") return "text/html; charset=utf-8";
    if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
    if (ext == ".css") return "text/css; charset=utf-8";
    if (ext == ".json" || ext == ".map") return "application/json";
    if (ext == ".png") return "image/png";
    if (ext == ".svg") return "image/svg+xml";
    if (ext == ".glb") return "model/gltf-binary";
    if (ext == ".gltf") return "model/gltf+json";
    if (ext == ".wasm") return "application/wasm";
    if (ext == ".txt" || ext == ".md") return "text/plain; charset=utf-8";
    return "application/octet-stream";
}

// The request target as a relative path below the served folder; empty when refused
// (a '..' or hidden segment, a backslash, an escape, a control character).
std::string safe_relative(std::string_view target) {
    if (auto q = target.find_first_of("?#"); q != std::string_view::npos) target = target.substr(0, q);
    if (target.empty() || target.front() != '/') return {};
    std::string out;
    size_t i = 1;
    while (i <= target.size()) {
        size_t j = target.find('/', i);
        if (j == std::string_view::npos) j = target.size();
        std::string_view seg = target.substr(i, j - i);
        if (!seg.empty()) {
            if (seg == ".." || seg.front() == '.') return {};
            for (char c : seg)
                if (c == '\\' || c == '%' || static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return {};
            if (!out.empty()) out += '/';
            out += seg;
        }
        i = j + 1;
    }
    return out.empty() ? "index.html" : out;
}

bool read_file(const fs::path& p, std::string& out) {
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) return false;
    const auto size = fs::file_size(p, ec);
    if (ec || size > kMaxFile) return false;
    std::ifstream in(p, std::ios::binary);
    out.assign(size_t(size), '\0');
    in.read(out.data(), std::streamsize(size));
    return bool(in);
}

}  // namespace

// What the Impl knows of a page: its WebSocket session, whatever its stream.
class WsPage {
public:
    virtual ~WsPage() = default;
    // The object this page inspects ("" the plant itself); false when none.
    virtual bool inspecting(std::string& path) const = 0;
    virtual void close() = 0;
};

using PlainStream = beast::tcp_stream;
using TlsStream = beast::ssl_stream<beast::tcp_stream>;

struct Server::Impl {
    Player& player;
    ServerOptions opt;
    net::io_context ioc{1};
    tcp::acceptor acceptor{ioc};
    std::optional<ssl::context> tls;
    std::thread thread;
    mutable std::mutex m;
    std::set<WsPage*> sessions;
    ServerStats stats;
    int next_client = 1;
    bool loopback = true;
    TokenGate gate;                      // the I/O thread's own
    std::set<graph::SlotId> operable;  // the slots a trainee may fire or set
    std::string operable_json;           // those inputs, for the welcome: [{path, label, type}]
    // The session report on demand (/report): made on a thread of its own, one at a time,
    // so the pages' I/O never waits for the replay.
    std::mutex report_m;
    std::thread report_thread;
    bool report_busy = false;

    Impl(Player& p, ServerOptions o) : player(p), opt(std::move(o)), gate(opt.lockout) {
        json list = json::array();
        if (player.live())
            for (const faults::Operable& in : faults::operable_inputs(player.graph())) {
                if (in.slots.empty()) continue;  // a graph written by hand
                operable.insert(in.slots.begin(), in.slots.end());
                std::string path = engine::path_of(player.slots(), in.slots);
                if (path.empty()) path = player.graph().slot_path(in.slots[0]);
                list.push_back({{"path", path},
                                {"label", in.label.empty() ? path : in.label},
                                {"type", graph::word(player.graph().slots[graph::SlotId(in.slots[0])].type)}});
            }
        // An operator panel's buttons, emergency stops and selectors are an operator's by
        // nature: their inputs are operable without a list (the page draws the panel itself).
        const graph::Graph& g = player.graph();
        for (graph::CompId c : graph::ids_of(g.comps)) {
            if (!player.live()) break;
            const graph::KindDesc* k = graph::plugin_of(g, c);
            if (!k || (k->word != "button" && k->word != "estop" && k->word != "selector")) continue;
            const graph::Comp& cp = g.comps[c];
            for (graph::SlotId sl : graph::children(cp.slot_adr, cp.slot_num))
                if (g.slots[sl].dir == graph::Dir::In) {
                    operable.insert(sl);
                    const std::string path = g.slot_path(sl);
                    list.push_back({{"path", path}, {"label", path}, {"type", graph::word(g.slots[sl].type)}, {"panel", true}});
                }
        }
        operable_json = list.dump(-1, ' ', false, json::error_handler_t::replace);
    }
    void accept();
    void inspected_changed();
    void count(uint64_t ServerStats::*field, uint64_t n = 1) {
        std::lock_guard lock(m);
        stats.*field += n;
    }
    // The role of a request from `addr` (host:port; `host` without the port) for `target`
    // (its ?token= and ?role=); false and `refusal` set for a wrong token, or a locked-out
    // address, which is logged.
    bool authorize(const std::string& host, const std::string& addr, std::string_view target, Role& role,
                   std::string& refusal);
};

bool Server::Impl::authorize(const std::string& host, const std::string& addr, std::string_view target, Role& role,
                             std::string& refusal) {
    bool has_token = false, has_role = false;
    const std::string token = query_value(target, "token", has_token);
    const bool trainee = query_value(target, "role", has_role) == "trainee" && has_role;
    role = trainee || (!opt.open && !has_token && !loopback) ? Role::Trainee : Role::Instructor;
    if (!has_token || opt.open) return true;  // --open asks for no token, so none is wrong
    const auto now = TokenGate::Clock::now();
    TokenGate::Clock::duration wait{};
    if (!gate.may_try(host, now, wait)) {
        gate.refused_unread(host);
        count(&ServerStats::bad_tokens);
        const auto secs = std::chrono::duration_cast<std::chrono::seconds>(wait).count() + 1;
        refusal = fmt::format("too many wrong tokens from {}: refused for {} s more", host, secs);
        const uint64_t n = gate.failures(host);
        if (n % 100 == 0) std::cerr << "plant serve: " << addr << ": " << refusal << " (" << n << " wrong tokens)\n";
        return false;
    }
    if (same_token(token, opt.token)) {
        gate.succeeded(host);
        return true;
    }
    const bool locked = gate.failed(host, now);
    count(&ServerStats::bad_tokens);
    refusal = "wrong token: this is not the session's instructor URL";
    std::cerr << "plant serve: " << addr << ": refused: wrong token"
              << (locked ? fmt::format(" ({} in a row: the address is locked out for a while)", TokenGate::kMaxFailures)
                         : std::string())
              << "\n";
    return false;
}

// One page's WebSocket: reads its messages, sends it the scene, frames, status and the
// event log on its own timer, never more than it can take. A trainee's page is sent no
// force (the status's, the inspector's, the event log's) and may send only what a trainee
// may; a page refused at the door (a wrong token) is told why and closed.
template <class Stream>
class WsSession : public WsPage, public std::enable_shared_from_this<WsSession<Stream>> {
public:
    WsSession(Stream&& stream, Server::Impl& server, Role role, std::string addr, std::string refusal)
        : ws_(std::move(stream)), server_(server), timer_(ws_.get_executor()), role_(role), addr_(std::move(addr)),
          refusal_(std::move(refusal)) {}

    void run(http::request<http::string_body> req) {
        ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
        ws_.read_message_max(kMaxClientMessage);
        ws_.async_accept(req, beast::bind_front_handler(&WsSession::on_accept, this->shared_from_this()));
    }
    bool inspecting(std::string& path) const override {
        path = inspect_;
        return inspecting_;
    }
    void close() override {
        if (closed_) return;
        closed_ = true;
        timer_.cancel();
        beast::error_code ec;
        beast::get_lowest_layer(ws_).socket().shutdown(tcp::socket::shutdown_both, ec);
        beast::get_lowest_layer(ws_).socket().close(ec);
    }

private:
    bool trainee() const { return role_ == Role::Trainee; }

    void on_accept(beast::error_code ec) {
        if (ec) return;
        if (!refusal_.empty()) {  // told why, then closed once that is written
            close_after_write_ = true;
            send(error_message(refusal_), false);
            return;
        }
        {
            std::lock_guard lock(server_.m);
            id_ = server_.next_client++;
            server_.sessions.insert(this);
            ++server_.stats.clients;
        }
        registered_ = true;
        send(fmt::format(R"({{"type":"welcome","client":{},"version":{},"role":"{}","operable":{}}})", id_,
                         kProtocolVersion, word(role_), server_.operable_json),
             false);
        pump();
        do_read();
    }
    void unregister() {
        if (!registered_) return;
        registered_ = false;
        {
            std::lock_guard lock(server_.m);
            server_.sessions.erase(this);
            --server_.stats.clients;
        }
        if (inspecting_) server_.inspected_changed();
    }
    void do_read() {
        ws_.async_read(buffer_, beast::bind_front_handler(&WsSession::on_read, this->shared_from_this()));
    }
    void on_read(beast::error_code ec, size_t) {
        if (ec) {
            closed_ = true;
            timer_.cancel();
            unregister();
            return;
        }
        server_.count(&ServerStats::messages);
        const std::string text = beast::buffers_to_string(buffer_.data());
        buffer_.consume(buffer_.size());
        if (!ws_.got_text()) reply_error("messages are JSON text, not binary");
        else handle(text);
        do_read();
    }

    void reply_error(std::string_view msg) {
        server_.count(&ServerStats::errors);
        // Logged on the server's stderr too, with the page's role and address: the first few
        // of each page, then a count.
        if (++errors_ <= 5 || errors_ % 1000 == 0)
            std::cerr << "plant serve: page " << id_ << " (" << word(role_) << " at " << addr_ << "): " << msg
                      << (errors_ == 5 ? " (further errors of this page: every 1000th is logged)" : "")
                      << (errors_ > 5 ? " (" + std::to_string(errors_) + " errors so far)" : "") << "\n";
        if (queue_.size() >= kMaxQueued / 2) {  // a flooding page: replies are dropped, not queued
            server_.count(&ServerStats::dropped_replies);
            return;
        }
        send(error_message(msg), false);
    }
    void refuse(std::string_view msg) {
        server_.count(&ServerStats::trainee_refused);
        reply_error(fmt::format("refused: {}", msg));
    }

    // What a trainee may do with an input event: the hand's acts, and events on inputs the
    // plant lists as operable, every slot of them (a port: all it forwards to).
    bool trainee_may(const engine::Event& ev, std::string& why) const {
        if (ev.force) {
            why = fmt::format("a trainee may not force or release slots ('{}')", ev.path);
            return false;
        }
        if (ev.hand != engine::HandAct::None) return true;
        for (graph::SlotId s : ev.slots)
            if (!server_.operable.count(s)) {
                why = fmt::format("'{}' is not an input a trainee may operate (the plant's `operable` lists them)",
                                  ev.path);
                return false;
            }
        return !ev.slots.empty();
    }

    void handle(const std::string& text) {
        ClientMessage msg;
        std::string error;
        if (!decode_client_message(text, msg, error)) return reply_error(error);
        Command c;
        c.client = id_;
        switch (msg.kind) {
        case ClientMessage::Kind::Hello: fps_ = msg.fps; return;
        case ClientMessage::Kind::Inspect:
            if (!server_.player.live() && !msg.stop_inspect) return reply_error("a replay has no live slots to inspect");
            inspect_ = msg.path;
            inspecting_ = !msg.stop_inspect;
            server_.inspected_changed();
            return;
        case ClientMessage::Kind::Seek:
            if (trainee()) return refuse("the instructor runs the session: a trainee may not seek");
            if (server_.player.live()) return reply_error("seek is for replays; a live run goes on");
            c.kind = Command::Kind::Seek;
            c.value = msg.time;
            break;
        case ClientMessage::Kind::Control:
            if (trainee()) return refuse("the instructor runs the session: a trainee may not pause, run, step, "
                                         "restart or change the speed");
            if (msg.action == "pause") c.kind = Command::Kind::Pause;
            else if (msg.action == "run") c.kind = Command::Kind::Run;
            else if (msg.action == "step") c.kind = Command::Kind::Step;
            else if (msg.action == "restart") c.kind = Command::Kind::Restart;
            else c.kind = Command::Kind::Speed, c.value = msg.speed;
            break;
        case ClientMessage::Kind::Drill:
            if (trainee()) return refuse("drills are the instructor's");
            if (!server_.player.live()) return reply_error("a replay is read-only: drills go to a live run");
            c.kind = Command::Kind::Drill;
            c.role = word(role_);
            if (!faults::parse_drill(server_.player.graph(), server_.player.slots(), msg.path, c.drill, error))
                return reply_error("drill: " + error);
            break;
        case ClientMessage::Kind::DrillCancel:
            if (trainee()) return refuse("drills are the instructor's");
            if (!server_.player.live()) return reply_error("a replay is read-only: drills go to a live run");
            c.kind = Command::Kind::DrillCancel;
            c.role = word(role_);
            c.value = msg.drill;
            break;
        case ClientMessage::Kind::Event: {
            if (!server_.player.live()) return reply_error("a replay is read-only: events go to a live run");
            c.kind = Command::Kind::Event;
            c.role = word(role_);
            const std::string input = msg.value.empty() ? msg.path : msg.path + " " + msg.value;
            if (!engine::parse_input(server_.player.graph(), server_.player.slots(), input, c.event, error))
                return reply_error(error);
            if (std::string why; trainee() && !trainee_may(c.event, why)) return refuse(why);
            break;
        }
        }
        if (!server_.player.command(std::move(c))) reply_error("too many commands waiting; try again");
    }

    // Everything due for this page, then again after 1/fps s.
    void pump() {
        if (closed_) return;
        Player& p = server_.player;
        // Whether the page has taken everything sent before this pump: a frame goes only then
        // (below), after what this pump sends first (a page asking for 5 frames a second or
        // fewer has a status due at every pump).
        const bool caught_up = !writing_ && queue_.empty();
        if (const uint64_t v = p.scene_version(); v != scene_version_) {
            if (auto scene = p.scene()) {
                scene_version_ = v;
                last_seq_ = 0;
                send(*scene, false);
                history_version_ = ~uint64_t(0);  // the series of the new run follow it
            }
        }
        // The run's series from t = 0: after the scene, and whole again when they start anew
        // (a restart, a seek in a replay).
        if (const uint64_t h = p.history_version(); h != history_version_ && scene_version_ != 0) {
            history_version_ = h;
            send(p.history_json(), false);
        }
        size_t next = 0;
        for (std::string& line : p.log_since(log_next_, next, !trainee()))
            if (queue_.size() < kMaxQueued) send(std::move(line), false);
        log_next_ = next;
        const auto now = std::chrono::steady_clock::now();
        if (now - last_status_ >= kStatusPeriod && queue_.size() < kMaxQueued / 2) {
            if (auto st = p.status()) {
                last_status_ = now;
                const StatusPub::View& view = trainee() ? st->trainee : st->instructor;
                std::string s = view.status;
                auto it = view.inspect.find(inspect_);
                if (inspecting_ && it != view.inspect.end() && !s.empty() && s.back() == '}') {
                    s.pop_back();
                    s += ",\"inspect\":" + it->second + "}";
                }
                send(std::move(s), false);
            }
        }
        // A frame only when the page has taken everything before this pump: frames are
        // dropped, never queued up behind a slow page.
        if (caught_up) {
            if (auto f = p.frame(); f && f->seq != last_seq_) {
                std::string bytes;
                encode_frame(f->frame, f->body_seq, f->gfx_seq, last_seq_, f->paused, bytes);
                last_seq_ = f->seq;
                server_.count(&ServerStats::frames);
                send(std::move(bytes), true);
            }
        }
        timer_.expires_after(std::chrono::milliseconds(1000 / fps_));
        timer_.async_wait([self = this->shared_from_this()](beast::error_code ec) {
            if (!ec) self->pump();
        });
    }

    void send(std::string data, bool binary) {
        queue_.push_back({std::move(data), binary});
        if (!writing_) do_write();
    }
    void do_write() {
        if (queue_.empty() || closed_) {
            writing_ = false;
            if (close_after_write_ && !closed_) {
                closed_ = true;
                ws_.async_close(websocket::close_code::policy_error,
                                [self = this->shared_from_this()](beast::error_code) {});
            }
            return;
        }
        writing_ = true;
        ws_.binary(queue_.front().binary);
        ws_.async_write(net::buffer(queue_.front().data),
                        beast::bind_front_handler(&WsSession::on_write, this->shared_from_this()));
    }
    void on_write(beast::error_code ec, size_t) {
        if (ec) {
            writing_ = false;
            close();
            unregister();
            return;
        }
        queue_.pop_front();
        do_write();
    }

    struct Out {
        std::string data;
        bool binary;
    };
    websocket::stream<Stream> ws_;
    Server::Impl& server_;
    net::steady_timer timer_;
    Role role_;
    std::string addr_, refusal_;
    beast::flat_buffer buffer_;
    std::deque<Out> queue_;
    bool writing_ = false, closed_ = false, registered_ = false, close_after_write_ = false;
    int id_ = 0, fps_ = 30;
    uint64_t errors_ = 0;
    uint64_t scene_version_ = 0, last_seq_ = 0, history_version_ = ~uint64_t(0);
    size_t log_next_ = 0;
    std::chrono::steady_clock::time_point last_status_{};
    std::string inspect_;
    bool inspecting_ = false;
};

// One HTTP connection: files, the events file, or the upgrade to a WebSocket; over TLS
// after its handshake when the stream is one.
template <class Stream>
class HttpSession : public std::enable_shared_from_this<HttpSession<Stream>> {
    static constexpr bool kTls = !std::is_same_v<Stream, PlainStream>;

public:
    template <class... Tls>
    HttpSession(tcp::socket&& socket, Server::Impl& server, Tls&... tls)
        : stream_(std::move(socket), tls...), server_(server) {
        beast::error_code ec;
        const tcp::endpoint ep = beast::get_lowest_layer(stream_).socket().remote_endpoint(ec);
        host_ = ec ? "?" : ep.address().to_string();
        addr_ = ec ? "?" : (ep.address().is_v6() ? "[" + host_ + "]" : host_) + ":" + std::to_string(ep.port());
    }
    void run() {
        if constexpr (kTls) {
            beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(30));
            stream_.async_handshake(ssl::stream_base::server, [self = this->shared_from_this()](beast::error_code ec) {
                if (!ec) self->do_read();
            });
        } else {
            do_read();
        }
    }

private:
    void do_read() {
        parser_.emplace();
        parser_->body_limit(64 * 1024);
        parser_->header_limit(16 * 1024);
        beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(30));
        http::async_read(stream_, buffer_, *parser_,
                         beast::bind_front_handler(&HttpSession::on_read, this->shared_from_this()));
    }
    void shutdown() {
        beast::error_code ec;
        if constexpr (kTls)
            stream_.async_shutdown([self = this->shared_from_this()](beast::error_code) {});
        else
            stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
    }
    void on_read(beast::error_code ec, size_t) {
        if (ec == http::error::end_of_stream) return shutdown();
        if (ec) return;
        http::request<http::string_body> req = parser_->release();
        const std::string_view target(req.target().data(), req.target().size());
        if (websocket::is_upgrade(req)) {
            if (target.substr(0, target.find('?')) != "/ws")
                return respond(req, http::status::not_found, "no WebSocket here; use /ws\n");
            Role role = Role::Trainee;
            std::string refusal;
            server_.authorize(host_, addr_, target, role, refusal);
            beast::get_lowest_layer(stream_).expires_never();
            std::make_shared<WsSession<Stream>>(std::move(stream_), server_, role, addr_, std::move(refusal))
                ->run(std::move(req));
            return;
        }
        handle(req);
    }

    void handle(const http::request<http::string_body>& req) {
        if (req.method() != http::verb::get && req.method() != http::verb::head)
            return respond(req, http::status::method_not_allowed, "only GET and HEAD\n");
        const std::string_view target(req.target().data(), req.target().size());
        const std::string rel = safe_relative(target);
        if (rel.empty()) {
            server_.count(&ServerStats::refused_http);
            return respond(req, http::status::bad_request, "refused: a path with '..', a hidden name or an escape\n");
        }
        if (rel == "events") {  // the session's events file holds the instructor's forces
            Role role = Role::Trainee;
            std::string refusal;
            if (!server_.authorize(host_, addr_, target, role, refusal))
                return respond(req, http::status::forbidden, refusal + "\n");
            if (role != Role::Instructor)
                return respond(req, http::status::forbidden,
                               "the session's events file is the instructor's (its URL carries ?token=)\n");
            return respond(req, http::status::ok, server_.player.events_file(), "text/plain; charset=utf-8");
        }
        if (rel == "report" || rel == "report.md") return report(req, target, rel == "report.md");
        std::string body, file;
        if (rel.rfind("models/", 0) == 0) {
            const std::string name = rel.substr(7);
            file = model_name(name) ? find_model(server_.opt.models, name).file : find_model_resource(server_.opt.models, name);
        }
        else if (!server_.opt.viewer_dir.empty()) file = (fs::path(server_.opt.viewer_dir) / rel).string();
        if (file.empty() || !read_file(file, body)) return respond(req, http::status::not_found, "not found\n");
        respond(req, http::status::ok, std::move(body), content_type(file));
    }

    // The session report so far (serve/report.h): the session's events replayed headless, so
    // its counters are the replay's; HTML with the plot (gnuplot) or Markdown. The
    // instructor's only: a trainee is refused and logged.
    void report(const http::request<http::string_body>& req, std::string_view target, bool markdown) {
        Role role = Role::Trainee;
        std::string refusal;
        if (!server_.authorize(host_, addr_, target, role, refusal))
            return respond(req, http::status::forbidden, refusal + "\n");
        if (role != Role::Instructor) {
            server_.count(&ServerStats::trainee_refused);
            std::cerr << "plant serve: " << addr_ << " (trainee): refused: the session report is the instructor's\n";
            return respond(req, http::status::forbidden,
                           "the session report is the instructor's (its URL carries ?token=)\n");
        }
        if (!server_.player.live()) return respond(req, http::status::not_found, "a replay has no session report\n");
        std::lock_guard lock(server_.report_m);
        if (server_.report_busy)
            return respond(req, http::status::service_unavailable, "a report is being made; try again in a moment\n");
        if (server_.report_thread.joinable()) server_.report_thread.join();
        server_.report_busy = true;
        server_.report_thread = std::thread([self = this->shared_from_this(), req, markdown,
                                             text = server_.player.events_file()] {
            Server::Impl& srv = self->server_;
            const graph::Graph& g = srv.player.graph();
            Session session;
            std::string error, body;
            http::status status = http::status::ok;
            if (!replay_session_text(g, srv.opt.plant_file, "session.events", text, 0, session, error)) {
                status = http::status::internal_server_error;
                body = "the session does not replay: " + error + "\n";
            } else if (markdown) {
                body = report_markdown(session, "");
            } else {
                body = report_page(session, text, error);
                if (body.empty()) status = http::status::internal_server_error, body = error + "\n";
            }
            srv.count(&ServerStats::reports);
            {
                std::lock_guard lock(srv.report_m);
                srv.report_busy = false;
            }
            net::post(self->stream_.get_executor(), [self, req, status, body = std::move(body), markdown]() mutable {
                self->respond(req, status, std::move(body),
                              markdown ? "text/markdown; charset=utf-8" : "text/html; charset=utf-8");
            });
        });
    }

    void respond(const http::request<http::string_body>& req, http::status status, std::string body,
                 std::string_view type = "text/plain; charset=utf-8") {
        auto res = std::make_shared<http::response<http::string_body>>(status, req.version());
        res->set(http::field::server, "plant serve");
        res->set(http::field::content_type, beast::string_view(type.data(), type.size()));
        res->set(http::field::cache_control, "no-store");
        res->keep_alive(req.keep_alive());
        if (req.method() == http::verb::head) res->content_length(body.size());
        else res->body() = std::move(body);
        if (req.method() != http::verb::head) res->prepare_payload();
        res_ = res;
        http::async_write(stream_, *res, [self = this->shared_from_this(), res](beast::error_code ec, size_t) {
            if (ec) return;
            if (!res->keep_alive()) return self->shutdown();
            self->do_read();
        });
    }

    Stream stream_;
    Server::Impl& server_;
    std::string host_, addr_;  // the client's address; with its port
    beast::flat_buffer buffer_;
    std::optional<http::request_parser<http::string_body>> parser_;
    std::shared_ptr<void> res_;
};

void Server::Impl::accept() {
    acceptor.async_accept(net::make_strand(ioc), [this](beast::error_code ec, tcp::socket socket) {
        if (!acceptor.is_open()) return;
        if (!ec && tls) std::make_shared<HttpSession<TlsStream>>(std::move(socket), *this, *tls)->run();
        else if (!ec) std::make_shared<HttpSession<PlainStream>>(std::move(socket), *this)->run();
        accept();
    });
}

void Server::Impl::inspected_changed() {
    std::set<std::string> paths;
    {
        std::lock_guard lock(m);
        std::string path;
        for (WsPage* s : sessions)
            if (s->inspecting(path)) paths.insert(path);
    }
    player.set_inspected(paths);
}

Server::Server(Player& player, ServerOptions opt) : impl_(std::make_unique<Impl>(player, std::move(opt))) {}

Server::~Server() { stop(); }

bool Server::start(std::string& error) {
    beast::error_code ec;
    const auto addr = net::ip::make_address(impl_->opt.host, ec);
    if (ec) {
        error = "--host '" + impl_->opt.host + "' is not an IP address";
        return false;
    }
    impl_->loopback = addr.is_loopback();
    if (!impl_->opt.tls_cert.empty() || !impl_->opt.tls_key.empty()) {
        auto& ctx = impl_->tls.emplace(ssl::context::tls_server);
        ctx.set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 | ssl::context::no_sslv3 |
                        ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1);
        ctx.use_certificate_chain_file(impl_->opt.tls_cert, ec);
        if (ec) {
            error = "--tls-cert: cannot use '" + impl_->opt.tls_cert + "': " + ec.message();
            return false;
        }
        ctx.use_private_key_file(impl_->opt.tls_key, ssl::context::pem, ec);
        if (ec) {
            error = "--tls-key: cannot use '" + impl_->opt.tls_key + "': " + ec.message();
            return false;
        }
    }
    tcp::endpoint ep(addr, impl_->opt.port);
    auto& a = impl_->acceptor;
    a.open(ep.protocol(), ec);
    if (!ec) a.set_option(net::socket_base::reuse_address(true), ec);
    if (!ec) a.bind(ep, ec);
    if (!ec) a.listen(net::socket_base::max_listen_connections, ec);
    if (ec) {
        error = "cannot listen on " + impl_->opt.host + ":" + std::to_string(impl_->opt.port) + ": " + ec.message();
        return false;
    }
    impl_->accept();
    impl_->thread = std::thread([this] { impl_->ioc.run(); });
    return true;
}

uint16_t Server::port() const {
    beast::error_code ec;
    return impl_->acceptor.local_endpoint(ec).port();
}

void Server::stop() {
    if (!impl_ || !impl_->thread.joinable()) return;
    net::post(impl_->ioc, [this] {
        beast::error_code ec;
        impl_->acceptor.close(ec);
        std::lock_guard lock(impl_->m);
        for (WsPage* s : impl_->sessions) s->close();
    });
    // Pages close; give their handlers a moment, then stop the loop.
    for (int i = 0; i < 50; ++i) {
        {
            std::lock_guard lock(impl_->m);
            if (impl_->sessions.empty()) break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    impl_->ioc.stop();
    impl_->thread.join();
    std::thread report;  // joined outside the lock, which the thread takes as it ends
    {
        std::lock_guard lock(impl_->report_m);
        report = std::move(impl_->report_thread);
    }
    if (report.joinable()) report.join();
}

bool loopback_host(const std::string& host) {
    beast::error_code ec;
    const auto addr = net::ip::make_address(host, ec);
    return !ec && addr.is_loopback();
}

ServerStats Server::stats() const {
    std::lock_guard lock(impl_->m);
    return impl_->stats;
}

void Server::wait_for_signal() {
    net::io_context sig_ctx;
    net::signal_set signals(sig_ctx, SIGINT, SIGTERM);
    signals.async_wait([](beast::error_code, int) {});
    sig_ctx.run();
}

}  // namespace plant::view
