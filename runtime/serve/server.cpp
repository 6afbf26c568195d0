#include "serve/server.h"

#include "serve/protocol.h"

#include <utility>  // Boost 1.74's asio headers use std::exchange without it

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
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
#include <thread>

namespace plant::view {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
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

class WsSession;

struct Server::Impl {
    Player& player;
    ServerOptions opt;
    net::io_context ioc{1};
    tcp::acceptor acceptor{ioc};
    std::thread thread;
    mutable std::mutex m;
    std::set<WsSession*> sessions;
    ServerStats stats;
    int next_client = 1;

    Impl(Player& p, ServerOptions o) : player(p), opt(std::move(o)) {}
    void accept();
    void inspected_changed();
    void count(uint64_t ServerStats::*field, uint64_t n = 1) {
        std::lock_guard lock(m);
        stats.*field += n;
    }
};

// One page's WebSocket: reads its messages, sends it the scene, frames, status and the
// event log on its own timer, never more than it can take.
class WsSession : public std::enable_shared_from_this<WsSession> {
public:
    WsSession(tcp::socket&& socket, Server::Impl& server) : ws_(std::move(socket)), server_(server), timer_(ws_.get_executor()) {}

    void run(http::request<http::string_body> req) {
        ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
        ws_.read_message_max(kMaxClientMessage);
        ws_.async_accept(req, beast::bind_front_handler(&WsSession::on_accept, shared_from_this()));
    }
    // The object this page inspects ("" the plant itself); false when none.
    bool inspecting(std::string& path) const {
        path = inspect_;
        return inspecting_;
    }
    void close() {
        if (closed_) return;
        closed_ = true;
        timer_.cancel();
        beast::error_code ec;
        beast::get_lowest_layer(ws_).socket().shutdown(tcp::socket::shutdown_both, ec);
        beast::get_lowest_layer(ws_).socket().close(ec);
    }

private:
    void on_accept(beast::error_code ec) {
        if (ec) return;
        {
            std::lock_guard lock(server_.m);
            id_ = server_.next_client++;
            server_.sessions.insert(this);
            ++server_.stats.clients;
        }
        registered_ = true;
        send(json{{"type", "welcome"}, {"client", id_}, {"version", kProtocolVersion}}.dump(), false);
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
        ws_.async_read(buffer_, beast::bind_front_handler(&WsSession::on_read, shared_from_this()));
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
        // Logged on the server's stderr too: the first few of each page, then a count.
        if (++errors_ <= 5 || errors_ % 1000 == 0)
            std::cerr << "plant serve: page " << id_ << ": " << msg
                      << (errors_ == 5 ? " (further errors of this page: every 1000th is logged)" : "")
                      << (errors_ > 5 ? " (" + std::to_string(errors_) + " errors so far)" : "") << "\n";
        if (queue_.size() >= kMaxQueued / 2) {  // a flooding page: replies are dropped, not queued
            server_.count(&ServerStats::dropped_replies);
            return;
        }
        send(error_message(msg), false);
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
            if (server_.player.live()) return reply_error("seek is for replays; a live run goes on");
            c.kind = Command::Kind::Seek;
            c.value = msg.time;
            break;
        case ClientMessage::Kind::Control:
            if (msg.action == "pause") c.kind = Command::Kind::Pause;
            else if (msg.action == "run") c.kind = Command::Kind::Run;
            else if (msg.action == "step") c.kind = Command::Kind::Step;
            else if (msg.action == "restart") c.kind = Command::Kind::Restart;
            else c.kind = Command::Kind::Speed, c.value = msg.speed;
            break;
        case ClientMessage::Kind::Event: {
            if (!server_.player.live()) return reply_error("a replay is read-only: events go to a live run");
            c.kind = Command::Kind::Event;
            const std::string input = msg.value.empty() ? msg.path : msg.path + " " + msg.value;
            if (!engine::parse_input(server_.player.graph(), server_.player.slots(), input, c.event, error))
                return reply_error(error);
            break;
        }
        }
        if (!server_.player.command(std::move(c))) reply_error("too many commands waiting; try again");
    }

    // Everything due for this page, then again after 1/fps s.
    void pump() {
        if (closed_) return;
        Player& p = server_.player;
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
        for (std::string& line : p.log_since(log_next_, next))
            if (queue_.size() < kMaxQueued) send(std::move(line), false);
        log_next_ = next;
        const auto now = std::chrono::steady_clock::now();
        if (now - last_status_ >= kStatusPeriod && queue_.size() < kMaxQueued / 2) {
            if (auto st = p.status()) {
                last_status_ = now;
                std::string s = st->status;
                auto it = st->inspect.find(inspect_);
                if (inspecting_ && it != st->inspect.end() && !s.empty() && s.back() == '}') {
                    s.pop_back();
                    s += ",\"inspect\":" + it->second + "}";
                }
                send(std::move(s), false);
            }
        }
        // A frame only when the page has taken everything before it: frames are dropped,
        // never queued up behind a slow page.
        if (!writing_ && queue_.empty()) {
            if (auto f = p.frame(); f && f->seq != last_seq_) {
                std::string bytes;
                encode_frame(f->frame, f->body_seq, f->gfx_seq, last_seq_, f->paused, bytes);
                last_seq_ = f->seq;
                server_.count(&ServerStats::frames);
                send(std::move(bytes), true);
            }
        }
        timer_.expires_after(std::chrono::milliseconds(1000 / fps_));
        timer_.async_wait([self = shared_from_this()](beast::error_code ec) {
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
            return;
        }
        writing_ = true;
        ws_.binary(queue_.front().binary);
        ws_.async_write(net::buffer(queue_.front().data),
                        beast::bind_front_handler(&WsSession::on_write, shared_from_this()));
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
    websocket::stream<beast::tcp_stream> ws_;
    Server::Impl& server_;
    net::steady_timer timer_;
    beast::flat_buffer buffer_;
    std::deque<Out> queue_;
    bool writing_ = false, closed_ = false, registered_ = false;
    int id_ = 0, fps_ = 30;
    uint64_t errors_ = 0;
    uint64_t scene_version_ = 0, last_seq_ = 0, history_version_ = ~uint64_t(0);
    size_t log_next_ = 0;
    std::chrono::steady_clock::time_point last_status_{};
    std::string inspect_;
    bool inspecting_ = false;
};

// One HTTP connection: files, the events file, or the upgrade to a WebSocket.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
public:
    HttpSession(tcp::socket&& socket, Server::Impl& server) : stream_(std::move(socket)), server_(server) {}
    void run() { do_read(); }

private:
    void do_read() {
        parser_.emplace();
        parser_->body_limit(64 * 1024);
        parser_->header_limit(16 * 1024);
        stream_.expires_after(std::chrono::seconds(30));
        http::async_read(stream_, buffer_, *parser_, beast::bind_front_handler(&HttpSession::on_read, shared_from_this()));
    }
    void on_read(beast::error_code ec, size_t) {
        if (ec == http::error::end_of_stream) {
            stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
            return;
        }
        if (ec) return;
        http::request<http::string_body> req = parser_->release();
        if (websocket::is_upgrade(req)) {
            if (req.target() != "/ws") return respond(req, http::status::not_found, "no WebSocket here; use /ws\n");
            stream_.expires_never();
            std::make_shared<WsSession>(stream_.release_socket(), server_)->run(std::move(req));
            return;
        }
        handle(req);
    }

    void handle(const http::request<http::string_body>& req) {
        if (req.method() != http::verb::get && req.method() != http::verb::head)
            return respond(req, http::status::method_not_allowed, "only GET and HEAD\n");
        const std::string rel = safe_relative(std::string_view(req.target().data(), req.target().size()));
        if (rel.empty()) {
            server_.count(&ServerStats::refused_http);
            return respond(req, http::status::bad_request, "refused: a path with '..', a hidden name or an escape\n");
        }
        if (rel == "events") return respond(req, http::status::ok, server_.player.events_file(), "text/plain; charset=utf-8");
        std::string body, file;
        if (rel.rfind("models/", 0) == 0) {
            const std::string name = rel.substr(7);
            file = model_name(name) ? find_model(server_.opt.models, name).file : find_model_resource(server_.opt.models, name);
        }
        else if (!server_.opt.viewer_dir.empty()) file = (fs::path(server_.opt.viewer_dir) / rel).string();
        if (file.empty() || !read_file(file, body)) return respond(req, http::status::not_found, "not found\n");
        respond(req, http::status::ok, std::move(body), content_type(file));
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
        http::async_write(stream_, *res, [self = shared_from_this(), res](beast::error_code ec, size_t) {
            if (ec) return;
            if (!res->keep_alive()) {
                self->stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
                return;
            }
            self->do_read();
        });
    }

    beast::tcp_stream stream_;
    Server::Impl& server_;
    beast::flat_buffer buffer_;
    std::optional<http::request_parser<http::string_body>> parser_;
    std::shared_ptr<void> res_;
};

void Server::Impl::accept() {
    acceptor.async_accept(net::make_strand(ioc), [this](beast::error_code ec, tcp::socket socket) {
        if (!acceptor.is_open()) return;
        if (!ec) std::make_shared<HttpSession>(std::move(socket), *this)->run();
        accept();
    });
}

void Server::Impl::inspected_changed() {
    std::set<std::string> paths;
    {
        std::lock_guard lock(m);
        std::string path;
        for (WsSession* s : sessions)
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
        for (WsSession* s : impl_->sessions) s->close();
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
