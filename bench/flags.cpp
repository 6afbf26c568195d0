#include "flags.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>

namespace plant::bench {

namespace {

// A finite number from the whole of `text`.
bool finite_number(const std::string& text, double& v) {
    if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) return false;
    char* end = nullptr;
    errno = 0;
    v = std::strtod(text.c_str(), &end);
    return !*end && errno == 0 && std::isfinite(v);
}

std::string from_to(long lo, long hi) { return "from " + std::to_string(lo) + " to " + std::to_string(hi); }

}  // namespace

std::vector<std::string> comma_items(const std::string& text) {
    std::vector<std::string> items;
    for (size_t at = 0; at <= text.size();) {
        const size_t comma = std::min(text.find(',', at), text.size());
        items.push_back(text.substr(at, comma - at));
        at = comma + 1;
    }
    return items;
}

Flags::Flags(const std::string& program, const std::string& usage, const std::string& about)
    : cli_(program, usage, about) {
    cli_.errors_as(program, program + " --help");
    cli_.usage_as(program);
    cli_.positionals(extra_);
}

void Flags::add(const std::string& name, const std::string& shown, const std::string& help, Check check) {
    Value& v = values_.emplace_back();
    v.check = std::move(check);
    v.option = cli_.value(name, v.text, help, shown, shown);
}

void Flags::whole(const std::string& name, int& v, long lo, long hi, const std::string& help) {
    add(name, "N", help, [&v, name, lo, hi](const std::string& t) -> std::string {
        long n = 0;
        if (!app::whole_number(t, lo, hi, n)) return name + ": '" + t + "' is not a whole number " + from_to(lo, hi);
        v = int(n);
        return {};
    });
}

void Flags::wholes(const std::string& name, std::vector<int>& v, long lo, long hi, const std::string& help) {
    add(name, "N,N,...", help, [&v, name, lo, hi](const std::string& t) -> std::string {
        std::vector<int> got;
        for (const std::string& item : comma_items(t)) {
            long n = 0;
            if (!app::whole_number(item, lo, hi, n))
                return name + ": '" + item + "' in '" + t + "' is not a whole number " + from_to(lo, hi);
            got.push_back(int(n));
        }
        v = std::move(got);
        return {};
    });
}

void Flags::number(const std::string& name, double& v, bool zero_too, const std::string& shown,
                   const std::string& help) {
    add(name, shown, help, [&v, name, zero_too](const std::string& t) -> std::string {
        double x = 0;
        if (!finite_number(t, x) || x < 0 || (x == 0 && !zero_too))
            return name + ": '" + t + "' is not a number " + (zero_too ? "of 0 or more" : "above 0");
        v = x;
        return {};
    });
}

void Flags::positive(const std::string& name, double& v, const std::string& shown, const std::string& help) {
    number(name, v, false, shown, help);
}

void Flags::not_negative(const std::string& name, double& v, const std::string& shown, const std::string& help) {
    number(name, v, true, shown, help);
}

void Flags::text(const std::string& name, std::string& v, const std::string& shown, const std::string& help) {
    add(name, shown, help, [&v, name, shown](const std::string& t) -> std::string {
        if (t.empty()) return name + " needs " + shown;
        v = t;
        return {};
    });
}

void Flags::choice(const std::string& name, std::string& v, const std::vector<std::string>& choices,
                   const std::string& help) {
    std::string shown;
    for (const std::string& c : choices) shown += (shown.empty() ? "" : "|") + c;
    add(name, shown, help, [&v, name, choices, shown](const std::string& t) -> std::string {
        for (const std::string& c : choices)
            if (t == c) {
                v = t;
                return {};
            }
        return name + ": '" + t + "' is not one of " + shown;
    });
}

void Flags::flag(const std::string& name, bool& v, bool to, const std::string& help) {
    bool& seen = switches_.emplace_back(false);
    cli_.flag(name, seen, help)->each([&v, to](const std::string&) { v = to; });
}

void Flags::pairs(int& runs, double& warmup, double& window, bool& rows) {
    auto seconds = [](double s) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", s);
        return std::string(buf);
    };
    whole("--runs", runs, 1, 1000, "pairs, each without the client and with it (default " + std::to_string(runs) + ")");
    not_negative("--warmup", warmup, "S", "simulated seconds before the window (default " + seconds(warmup) + ")");
    positive("--window", window, "S", "simulated seconds measured (default " + seconds(window) + ")");
    flag("--rows", rows, true, "only the rows of bench/run.sh's table");
}

int Flags::parse(int argc, char** argv) {
    const int code = cli_.parse(std::vector<std::string>(argv + 1, argv + argc), std::cout, std::cerr);
    if (code >= 0) return code;
    for (Value& v : values_) {
        if (v.option->count() == 0) continue;
        if (const std::string e = v.check(v.text); !e.empty()) return error(e);
    }
    if (words_) *words_ = extra_;
    else if (!extra_.empty()) return error("unexpected word '" + extra_.front() + "'");
    return -1;
}

int Flags::error(const std::string& message) const { return cli_.usage_error(std::cerr, message); }

}  // namespace plant::bench
