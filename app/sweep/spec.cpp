// The sweep spec: YAML read by yaml-cpp, every node's mark kept for located errors.
#include "sweep.h"
#include "graph/utf8.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace plant::sweep {

namespace {

Loc at(const YAML::Node& n) {
    const YAML::Mark m = n.Mark();
    if (m.line < 0) return {};
    return {m.line + 1, m.column + 1};
}

std::string trim(std::string s) {
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.pop_back();
    size_t i = 0;
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
    return s.substr(i);
}

// Numbers printed so that a range's values read as written (0.1 + 2 * 0.1 -> 0.3).
std::string number(double v) {
    std::ostringstream s;
    s.precision(10);
    s << (std::abs(v) < 1e-12 ? 0.0 : v);
    return s.str();
}

class Reader {
public:
    Reader(Spec& s, std::vector<SpecError>& e) : spec_(s), errors_(e) {}

    void error(const YAML::Node& n, std::string msg) { errors_.push_back({at(n), std::move(msg)}); }

    bool scalar(const YAML::Node& n, const std::string& what, std::string& out) {
        if (!n.IsScalar()) {
            error(n, what + " must be a single value");
            return false;
        }
        out = trim(n.Scalar());
        if (out.empty()) {
            error(n, what + " is empty");
            return false;
        }
        return true;
    }

    bool positive_int(const YAML::Node& n, const std::string& what, int& out) {
        std::string s;
        if (!scalar(n, what, s)) return false;
        char* end = nullptr;
        const long v = std::strtol(s.c_str(), &end, 10);
        if (*end || v < 1 || v > 1000000) {
            error(n, what + " must be a whole number from 1 to 1000000, not '" + s + "'");
            return false;
        }
        out = int(v);
        return true;
    }

    bool quantity(const YAML::Node& n, const std::string& what, double& v, std::string& unit) {
        std::string s;
        if (!scalar(n, what, s)) return false;
        if (!split_quantity(s, v, unit)) {
            error(n, what + ": '" + s + "' is not a number with an optional unit");
            return false;
        }
        return true;
    }

    // A list, {from, to, step} or {random, from, to, seed}.
    void values(const YAML::Node& n, Param& p) {
        if (n.IsSequence()) {
            if (n.size() == 0) error(n, "parameter '" + p.name + "' has an empty list of values");
            for (const auto& v : n) {
                std::string s;
                if (scalar(v, "a value of '" + p.name + "'", s)) p.values.push_back({s, at(v)});
            }
            return;
        }
        if (n.IsScalar()) {
            std::string s;
            if (scalar(n, "the value of '" + p.name + "'", s)) p.values.push_back({s, at(n)});
            return;
        }
        if (!n.IsMap()) {
            error(n, "parameter '" + p.name + "': give a list, {from, to, step} or {random, from, to, seed}");
            return;
        }
        for (const auto& kv : n) {
            const std::string k = kv.first.Scalar();
            if (k != "from" && k != "to" && k != "step" && k != "random" && k != "seed")
                error(kv.first, "unknown key '" + k + "' in a range (from, to, step, random, seed)");
        }
        if (!n["from"] || !n["to"]) {
            error(n, "parameter '" + p.name + "': a range needs from and to");
            return;
        }
        double from = 0, to = 0;
        std::string fu, tu;
        if (!quantity(n["from"], "from", from, fu) || !quantity(n["to"], "to", to, tu)) return;
        if (fu != tu) {
            error(n["to"], "'to' is in '" + tu + "' but 'from' in '" + fu + "': write both in one unit");
            return;
        }
        const std::string unit = fu.empty() ? "" : " " + fu;
        if (n["random"]) {
            int count = 0;
            if (!positive_int(n["random"], "random (the number of samples)", count)) return;
            if (n["step"]) error(n["step"], "a random range has no step");
            if (!n["seed"]) {
                error(n, "parameter '" + p.name + "': random samples need a seed (any whole number)");
                return;
            }
            std::string seed_text;
            if (!scalar(n["seed"], "seed", seed_text)) return;
            char* end = nullptr;
            uint64_t state = std::strtoull(seed_text.c_str(), &end, 10);
            if (*end) {
                error(n["seed"], "seed must be a whole number, not '" + seed_text + "'");
                return;
            }
            if (!(to > from)) {
                error(n, "parameter '" + p.name + "': empty range (from " + number(from) + " to " + number(to) + ")");
                return;
            }
            // splitmix64: the same samples on every machine and library.
            for (int i = 0; i < count; ++i) {
                state += 0x9e3779b97f4a7c15ULL;
                uint64_t z = state;
                z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
                z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
                z ^= z >> 31;
                const double u = double(z >> 11) * 0x1.0p-53;
                char buf[64];
                std::snprintf(buf, sizeof buf, "%.6g", from + u * (to - from));
                p.values.push_back({buf + unit, at(n)});
            }
            return;
        }
        if (n["seed"]) error(n["seed"], "a seed belongs to random samples");
        if (!n["step"]) {
            error(n, "parameter '" + p.name + "': a range needs a step (or random: N for samples)");
            return;
        }
        double step = 0;
        std::string su;
        if (!quantity(n["step"], "step", step, su)) return;
        if (su != fu) {
            error(n["step"], "'step' is in '" + su + "' but 'from' in '" + fu + "': write all three in one unit");
            return;
        }
        if (!(step > 0) || to < from) {
            error(n, "parameter '" + p.name + "': empty range (from " + number(from) + " to " + number(to) +
                         " by " + number(step) + ")");
            return;
        }
        const double count = std::floor((to - from) / step + 1e-9) + 1;
        if (count > 100000) {
            error(n, "parameter '" + p.name + "': more than 100000 values");
            return;
        }
        for (int i = 0; i < int(count); ++i) p.values.push_back({number(from + i * step) + unit, at(n)});
    }

    void read(const YAML::Node& root) {
        if (!root.IsMap()) {
            error(root, "a sweep spec is a map (plant:, vary:, for:, ...)");
            return;
        }
        static const std::set<std::string> keys = {"plant", "for", "vary", "replicates", "outputs", "timeout", "plot"};
        for (const auto& kv : root)
            if (!keys.count(kv.first.Scalar()))
                error(kv.first, "unknown key '" + kv.first.Scalar() +
                                    "' (plant, for, vary, replicates, outputs, timeout, plot)");
        if (!root["plant"]) error(root, "the spec names no plant (plant: FILE)");
        else if (std::string f; scalar(root["plant"], "plant", f)) {
            namespace fs = std::filesystem;
            const fs::path p = fs::path(spec_.path).parent_path() / f;
            spec_.plant = p.lexically_normal().string();
            spec_.plant_loc = at(root["plant"]);
            if (!fs::is_regular_file(p)) error(root["plant"], "no plant file '" + spec_.plant + "'");
        }
        if (root["for"]) {
            double s = 0;
            if (scalar(root["for"], "for", spec_.run_for) && !parse_seconds(spec_.run_for, s))
                error(root["for"], "for: '" + spec_.run_for + "' is not a time (s, ms, min, h)");
            spec_.for_loc = at(root["for"]);
        }
        if (root["timeout"]) {
            std::string t;
            if (scalar(root["timeout"], "timeout", t) && (!parse_seconds(t, spec_.timeout) || spec_.timeout <= 0))
                error(root["timeout"], "timeout: '" + t + "' is not a positive time (s, ms, min, h)");
        }
        if (const YAML::Node vary = root["vary"]) {
            if (!vary.IsMap() || vary.size() == 0) error(vary, "vary: a map from parameter names to values");
            else
                for (const auto& kv : vary) {
                    Param p;
                    p.name = kv.first.Scalar();
                    p.loc = at(kv.first);
                    values(kv.second, p);
                    spec_.params.push_back(std::move(p));
                }
        }
        if (const YAML::Node r = root["replicates"]) {
            if (r.IsMap()) {
                for (const auto& kv : r)
                    if (kv.first.Scalar() != "count" && kv.first.Scalar() != "perturb" && kv.first.Scalar() != "by")
                        error(kv.first, "unknown key '" + kv.first.Scalar() + "' in replicates (count, perturb, by)");
                if (!r["count"]) error(r, "replicates: needs a count");
                else positive_int(r["count"], "replicates' count", spec_.replicates);
                if (r["perturb"] && scalar(r["perturb"], "perturb", spec_.perturb)) spec_.perturb_loc = at(r["perturb"]);
                if (r["by"] && scalar(r["by"], "by", spec_.perturb_by)) spec_.perturb_by_loc = at(r["by"]);
                if (r["perturb"].IsDefined() != r["by"].IsDefined())
                    error(r, "replicates: perturb (a parameter) and by (the step) go together");
            } else {
                positive_int(r, "replicates", spec_.replicates);
            }
        }
        if (const YAML::Node outs = root["outputs"]) {
            if (!outs.IsSequence() || outs.size() == 0) error(outs, "outputs: a list (issued, commissioned, ...)");
            else
                for (const auto& o : outs) {
                    Output out;
                    out.loc = at(o);
                    if (o.IsMap() && o.size() == 1) {
                        const std::string k = o.begin()->first.Scalar();
                        if (k != "total" && k != "rate") {
                            error(o.begin()->first, "an output is a counter, {total: RECORD} or {rate: RECORD}, not '" + k + "'");
                            continue;
                        }
                        out.kind = k == "total" ? Output::Total : Output::Rate;
                        if (!scalar(o.begin()->second, k, out.name)) continue;
                    } else if (o.IsScalar()) {
                        static const std::set<std::string> counters = {"issued", "commissioned", "on_line",
                                                                       "lost",   "stalled",      "rtf"};
                        out.name = trim(o.Scalar());
                        if (!counters.count(out.name)) {
                            error(o, "unknown output '" + out.name +
                                         "' (issued, commissioned, on_line, lost, stalled, rtf, {total: RECORD}, "
                                         "{rate: RECORD})");
                            continue;
                        }
                    } else {
                        error(o, "an output is a counter, {total: RECORD} or {rate: RECORD}");
                        continue;
                    }
                    spec_.outputs.push_back(out);
                }
        } else {
            for (const char* c : {"issued", "commissioned", "lost", "stalled", "rtf"})
                spec_.outputs.push_back({Output::Counter, c, {}});
        }
        if (root["plot"] && scalar(root["plot"], "plot", spec_.plot)) {
            spec_.plot_loc = at(root["plot"]);
            bool found = false;
            for (const Output& o : spec_.outputs) found = found || o.column() == spec_.plot;
            if (!found) error(root["plot"], "plot: '" + spec_.plot + "' is not one of the outputs");
        }
        std::set<std::string> seen;
        for (const Param& p : spec_.params)
            if (!seen.insert(p.name).second) errors_.push_back({p.loc, "parameter '" + p.name + "' varied twice"});
    }

private:
    Spec& spec_;
    std::vector<SpecError>& errors_;
};

}  // namespace

std::string Output::column() const {
    if (kind == Counter) return name;
    return (kind == Total ? "total:" : "rate:") + name;
}

bool split_quantity(const std::string& text, double& number, std::string& unit) {
    const char* s = text.c_str();
    char* end = nullptr;
    number = std::strtod(s, &end);
    if (end == s || !std::isfinite(number)) return false;
    unit = trim(std::string(end));
    return true;
}

bool parse_seconds(const std::string& text, double& seconds) {
    double v = 0;
    std::string u;
    if (!split_quantity(text, v, u)) return false;
    if (u == "s") seconds = v;
    else if (u == "ms") seconds = v / 1000;
    else if (u == "min") seconds = v * 60;
    else if (u == "h") seconds = v * 3600;
    else return false;
    return seconds > 0;
}

bool load_spec(const std::string& path, Spec& out, std::vector<SpecError>& errors) {
    out = Spec{};
    out.path = path;
    std::ifstream f(path, std::ios::binary);
    if (!f) {
        errors.push_back({{}, "cannot read the spec"});
        return false;
    }
    std::stringstream text;
    text << f.rdbuf();
    // A spec is YAML, UTF-8 text: a bad byte is named where it is, before YAML reads on.
    const std::string all = text.str();
    if (const size_t bad = graph::invalid_utf8(all); bad != std::string::npos) {
        const size_t line_start = all.rfind('\n', bad == 0 ? 0 : bad - 1);
        const int line = 1 + int(std::count(all.begin(), all.begin() + std::ptrdiff_t(bad), '\n'));
        const size_t col = bad - (line_start == std::string::npos || bad == 0 ? 0 : line_start + 1);
        errors.push_back({{line, int(col) + 1},
                          fmt::format("not valid UTF-8: byte 0x{:02X} here (a spec is UTF-8 text)",
                                      static_cast<unsigned char>(all[bad]))});
        return false;
    }
    try {
        const YAML::Node root = YAML::Load(all);
        Reader(out, errors).read(root);
    } catch (const YAML::Exception& e) {
        errors.push_back({{e.mark.line + 1, e.mark.column + 1}, e.msg});
    }
    return errors.empty();
}

std::string render_errors(const std::string& path, const std::vector<SpecError>& errors) {
    std::vector<std::string> lines;
    {
        std::ifstream f(path, std::ios::binary);
        for (std::string l; std::getline(f, l);) lines.push_back(l);
    }
    std::string out;
    for (const SpecError& e : errors) {
        if (e.loc.line <= 0) {
            out += path + ": error: " + e.message + "\n";
            continue;
        }
        out += path + ":" + std::to_string(e.loc.line) + ":" + std::to_string(e.loc.col) + ": error: " + e.message + "\n";
        if (size_t(e.loc.line) <= lines.size()) {
            const std::string num = std::to_string(e.loc.line);
            out += " " + num + " | " + lines[size_t(e.loc.line) - 1] + "\n";
            out.append(1 + num.size(), ' ');
            out += " | ";
            out.append(size_t(std::max(0, e.loc.col - 1)), ' ');
            out += "^\n";
        }
    }
    return out;
}

std::vector<Run> expand(const Spec& spec) {
    std::vector<Run> runs;
    size_t combos = 1;
    for (const Param& p : spec.params) combos *= p.values.size();
    for (size_t c = 0; c < combos; ++c) {
        // The first parameter varies slowest.
        std::vector<size_t> pick(spec.params.size());
        size_t rest = c;
        for (size_t k = spec.params.size(); k-- > 0;) {
            pick[k] = rest % spec.params[k].values.size();
            rest /= spec.params[k].values.size();
        }
        for (int r = 0; r < spec.replicates; ++r) {
            Run run;
            run.index = int(runs.size());
            run.replicate = r;
            for (size_t k = 0; k < spec.params.size(); ++k) {
                const std::string& v = spec.params[k].values[pick[k]].text;
                run.values.push_back(v);
                std::string set = v;
                if (r > 0 && spec.params[k].name == spec.perturb) {
                    set = "(" + v + ") + " + std::to_string(r) + " * (" + spec.perturb_by + ")";
                }
                run.sets.push_back(spec.params[k].name + "=" + set);
            }
            runs.push_back(std::move(run));
        }
    }
    return runs;
}

bool is_final(const std::string& status) { return status != "lost" && !status.empty(); }

}  // namespace plant::sweep
