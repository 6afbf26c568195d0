// Runs as child processes: `plant run PLANT --set ... --for T --quiet --summary=json`,
// stdout and stderr to files in the work folder, read back into a Result when the child ends.
#include "sweep.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <sstream>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace plant::sweep {

using json = nlohmann::json;

namespace {

double now() {
    using namespace std::chrono;
    return duration<double>(steady_clock::now().time_since_epoch()).count();
}

std::string slurp(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

std::string trim_line(std::string s) {
    while (!s.empty() && (s.back() == ' ' || s.back() == '\n' || s.back() == '\r')) s.pop_back();
    size_t i = 0;
    while (i < s.size() && s[i] == ' ') ++i;
    return s.substr(i);
}

// The last line of stderr that says something (a run's error), without the caret lines.
std::string last_error(const std::string& err) {
    std::istringstream in(err);
    std::string best, line;
    while (std::getline(in, line)) {
        line = trim_line(line);
        if (line.find("error") != std::string::npos) return line;
        if (!line.empty() && line[0] != '|' && line[0] != '^') best = line;
    }
    return best;
}

// The sweep's pid in the name: a run left behind by a killed sweep never writes into the
// files of the same run started again by --resume.
std::string out_path(const std::string& dir, int index, const char* ext) {
    return fmt::format("{}/run-{}-{}.{}", dir, index, ::getpid(), ext);
}

}  // namespace

bool parse_summary(const std::string& text, Summary& s) {
    // `plant run --summary=json` (docs/runtime.md, "The summary as JSON"); a value that is
    // not a number (null: a NaN) reads as NaN.
    const json j = json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("simulated_time_s")) return false;
    auto number = [](const json& v) { return v.is_number() ? v.get<double>() : std::nan(""); };
    s.counters["rtf"] = number(j.value("real_time_factor", json()));
    const json objects = j.value("objects", json::object());
    for (const auto& [key, name] : {std::pair{"issued", "issued"}, {"taken", "commissioned"}, {"on_line", "on_line"},
                                    {"lost", "lost"}, {"stalled", "stalled"}})
        if (objects.contains(key) && !objects[key].is_null()) s.counters[name] = number(objects[key]);
    for (const json& r : j.value("records", json::array())) {
        const std::string column = r.value("column", "");
        if (r.contains("events")) {
            s.totals[column] = number(r["events"]);
            s.rates[column] = number(r.value("per_minute", json()));
        } else {
            s.totals[column] = number(r.value("value", json()));
        }
    }
    s.nan = j.value("warnings", json::object()).value("nan_state", 0) > 0;
    return true;
}

Pool::~Pool() {
    for (const Child& c : children_) {
        ::kill(c.pid, SIGKILL);
        ::waitpid(c.pid, nullptr, 0);
    }
}

bool Pool::start(const Run& run, std::string& error) {
    std::vector<std::string> args = {exec_.plant_exe, "run", spec_.plant};
    for (const std::string& s : run.sets) {
        args.push_back("--set");
        args.push_back(s);
    }
    args.insert(args.end(), {"--for", exec_.run_for, "--quiet", "--threads", "1", "--summary=json"});
    const std::string out = out_path(exec_.work_dir, run.index, "out");
    const std::string err = out_path(exec_.work_dir, run.index, "err");
    const pid_t parent = ::getpid();
    const pid_t pid = ::fork();
    if (pid < 0) {
        error = std::string("fork: ") + std::strerror(errno);
        return false;
    }
    if (pid == 0) {
        // A run dies with the sweep (even a SIGKILLed one), and a Ctrl-C at the terminal
        // reaches the sweep only (its own process group): the sweep stops its runs itself.
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (::getppid() != parent) ::_exit(126);
        ::setpgid(0, 0);
        const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int i = ::open("/dev/null", O_RDONLY);
        if (o < 0 || e < 0 || i < 0) ::_exit(126);
        ::dup2(i, 0);
        ::dup2(o, 1);
        ::dup2(e, 2);
        std::vector<char*> argv;
        for (std::string& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        ::execv(argv[0], argv.data());
        ::_exit(127);
    }
    children_.push_back({int(pid), run.index, now(), false});
    return true;
}

bool Pool::poll(Result& r) {
    for (;;) {
        int status = 0;
        const pid_t pid = ::waitpid(-1, &status, WNOHANG);
        if (pid <= 0) break;
        for (size_t i = 0; i < children_.size(); ++i) {
            if (children_[i].pid != pid) continue;
            const Child c = children_[i];
            children_.erase(children_.begin() + long(i));
            r = finish(c, status);
            return true;
        }
    }
    const double t = now();
    for (Child& c : children_)
        if (!c.timed_out && t - c.started > exec_.timeout) {
            c.timed_out = true;
            ::kill(c.pid, SIGKILL);
        }
    return false;
}

std::vector<Result> Pool::stop_all(const std::string& why) {
    std::vector<Result> out;
    for (const Child& c : children_) {
        ::kill(c.pid, SIGKILL);
        ::waitpid(c.pid, nullptr, 0);
        Result r;
        r.index = c.index;
        r.status = "lost";
        r.message = why;
        r.wall = now() - c.started;
        r.outputs.assign(spec_.outputs.size(), "");
        std::remove(out_path(exec_.work_dir, c.index, "out").c_str());
        std::remove(out_path(exec_.work_dir, c.index, "err").c_str());
        out.push_back(std::move(r));
    }
    children_.clear();
    return out;
}

Result Pool::finish(const Child& c, int status) {
    Result r;
    r.index = c.index;
    r.wall = now() - c.started;
    const std::string out_file = out_path(exec_.work_dir, c.index, "out");
    const std::string err_file = out_path(exec_.work_dir, c.index, "err");
    const std::string out = slurp(out_file), err = slurp(err_file);
    std::remove(out_file.c_str());
    std::remove(err_file.c_str());
    r.outputs.assign(spec_.outputs.size(), "");
    if (c.timed_out) {
        r.status = "timeout";
        r.message = fmt::format("no result after {:g} s of wall time", exec_.timeout);
        return r;
    }
    if (WIFSIGNALED(status)) {
        const int sig = WTERMSIG(status);
        // SIGKILL from outside (the OOM killer, an operator, a batch system): run it again on --resume.
        r.status = sig == SIGKILL || sig == SIGTERM ? "lost" : "crashed";
        r.message = fmt::format("killed by signal {} ({})", sig, strsignal(sig));
        return r;
    }
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (code == 127 || code == 126) {
        // exec failed (the binary replaced or gone mid-sweep): the run never started; run it again.
        r.status = "lost";
        r.message = code == 127 ? "cannot run " + exec_.plant_exe : "cannot write " + out_file;
        return r;
    }
    if (code == 128 + SIGINT || code == 128 + SIGTERM) {
        // `plant run` stopped by a signal from outside, not by its plant: run it again.
        r.status = "lost";
        r.message = fmt::format("interrupted by {} (exit code {})", code == 128 + SIGINT ? "SIGINT" : "SIGTERM", code);
        return r;
    }
    if (code != 0) {
        r.status = code == 1 && err.find("error[E") != std::string::npos ? "compile_error" : "failed";
        r.message = last_error(err);
        if (r.message.empty()) r.message = fmt::format("exit code {}", code);
        return r;
    }
    Summary s;
    if (!parse_summary(out, s)) {
        r.status = "failed";
        r.message = "no summary on stdout";
        return r;
    }
    r.status = s.nan ? "nan" : "ok";
    if (s.nan) r.message = "an object's state became NaN";
    for (size_t k = 0; k < spec_.outputs.size(); ++k) {
        const Output& o = spec_.outputs[k];
        const auto& m = o.kind == Output::Counter ? s.counters : o.kind == Output::Total ? s.totals : s.rates;
        const auto it = m.find(o.name);
        if (it == m.end()) continue;
        if (!std::isfinite(it->second)) {
            r.status = "nan";
            r.message = o.column() + " is not a number";
        }
        r.outputs[k] = fmt::format("{:g}", it->second);
    }
    return r;
}

}  // namespace plant::sweep
