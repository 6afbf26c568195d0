// Who a page is in a `plant serve` session (docs/viewer.md, "Roles"): the instructor, who
// holds the session's secret token and does everything, or a trainee, who watches and
// operates what a trainee may (the inputs the plant file lists as `operable`, the hand).
// The server decides each page's role when it connects; what is here is the part without
// networking: the token, comparing it, and throttling an address that keeps guessing.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>

namespace plant::view {

enum class Role : uint8_t { Instructor, Trainee };
std::string_view word(Role r);

// 128 random bits from the operating system (getrandom), as 32 lowercase hex digits; "" and
// `error` set when the system gives none.
std::string make_token(std::string& error);
// Whether `given` is `secret`, in a time that does not depend on where they differ
// (OpenSSL's CRYPTO_memcmp); an empty secret matches nothing.
bool same_token(std::string_view given, std::string_view secret);
// The value of `key` in a request target's query (`/ws?token=ab&role=trainee`), undecoded;
// `present` false when the key is not there.
std::string query_value(std::string_view target, std::string_view key, bool& present);

// Wrong tokens per client address: after kMaxFailures within kWindow the address is locked
// out (every token refused unread) for `lockout`, doubling with each lockout in a row up to
// 32 times; a right token clears its record. Bounded: at most kMaxAddresses are remembered
// (the stalest go first).
class TokenGate {
public:
    using Clock = std::chrono::steady_clock;
    static constexpr int kMaxFailures = 5;
    static constexpr auto kWindow = std::chrono::minutes(10);
    static constexpr size_t kMaxAddresses = 4096;

    explicit TokenGate(Clock::duration lockout = std::chrono::seconds(30)) : lockout_(lockout) {}
    // False while `addr` is locked out; then `wait` is how long it still is.
    bool may_try(const std::string& addr, Clock::time_point now, Clock::duration& wait) const;
    // A wrong token from `addr`; true when this one locked it out.
    bool failed(const std::string& addr, Clock::time_point now);
    void succeeded(const std::string& addr) { gates_.erase(addr); }
    // Wrong tokens from `addr` so far (those refused unread included).
    uint64_t failures(const std::string& addr) const;
    void refused_unread(const std::string& addr);

private:
    struct Gate {
        int failures = 0;    // since the last lockout
        int lockouts = 0;    // in a row
        uint64_t total = 0;  // every wrong or unread token
        Clock::time_point last{}, until{};
    };
    Clock::duration lockout_;
    std::map<std::string, Gate> gates_;
};

}  // namespace plant::view
