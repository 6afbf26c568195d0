#include "serve/roles.h"

#include <openssl/crypto.h>
#include <sys/random.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace plant::view {

std::string_view word(Role r) { return r == Role::Instructor ? "instructor" : "trainee"; }

std::string make_token(std::string& error) {
    unsigned char bytes[16];
    size_t got = 0;
    while (got < sizeof bytes) {
        const ssize_t n = getrandom(bytes + got, sizeof bytes - got, 0);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            error = std::string("the system gives no random bytes for the session's token: ") + std::strerror(errno);
            return {};
        }
        got += size_t(n);
    }
    static constexpr char kHex[] = "0123456789abcdef";
    std::string out;
    for (unsigned char b : bytes) {
        out += kHex[b >> 4];
        out += kHex[b & 15];
    }
    return out;
}

bool same_token(std::string_view given, std::string_view secret) {
    // The length is no secret (every token has 32 digits); the content is compared whole.
    if (secret.empty() || given.size() != secret.size()) return false;
    return CRYPTO_memcmp(given.data(), secret.data(), secret.size()) == 0;
}

std::string query_value(std::string_view target, std::string_view key, bool& present) {
    present = false;
    const size_t q = target.find('?');
    if (q == std::string_view::npos) return {};
    std::string_view query = target.substr(q + 1);
    if (const size_t h = query.find('#'); h != std::string_view::npos) query = query.substr(0, h);
    while (!query.empty()) {
        const size_t amp = query.find('&');
        const std::string_view pair = query.substr(0, amp);
        const size_t eq = pair.find('=');
        if (pair.substr(0, eq) == key) {
            present = true;
            return eq == std::string_view::npos ? std::string() : std::string(pair.substr(eq + 1));
        }
        if (amp == std::string_view::npos) break;
        query = query.substr(amp + 1);
    }
    return {};
}

bool TokenGate::may_try(const std::string& addr, Clock::time_point now, Clock::duration& wait) const {
    auto it = gates_.find(addr);
    if (it == gates_.end() || now >= it->second.until) return true;
    wait = it->second.until - now;
    return false;
}

bool TokenGate::failed(const std::string& addr, Clock::time_point now) {
    if (!gates_.count(addr) && gates_.size() >= kMaxAddresses) {
        auto stalest = std::min_element(gates_.begin(), gates_.end(),
                                        [](const auto& a, const auto& b) { return a.second.last < b.second.last; });
        gates_.erase(stalest);
    }
    Gate& g = gates_[addr];
    if (g.last != Clock::time_point{} && now - g.last > kWindow) g.failures = g.lockouts = 0;  // a fresh start
    g.last = now;
    ++g.total;
    if (++g.failures < kMaxFailures) return false;
    g.failures = 0;
    g.until = now + lockout_ * (int64_t(1) << std::min(g.lockouts, 5));
    ++g.lockouts;
    return true;
}

void TokenGate::refused_unread(const std::string& addr) {
    if (auto it = gates_.find(addr); it != gates_.end()) ++it->second.total;
}

uint64_t TokenGate::failures(const std::string& addr) const {
    auto it = gates_.find(addr);
    return it == gates_.end() ? 0 : it->second.total;
}

}  // namespace plant::view
