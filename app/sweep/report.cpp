// The sweep's files: results.csv (a row per run), summary.md (a row per combination of
// values, means over replicates) and plot.gp/plot.dat/plot.svg (one output over one or two
// varied parameters).
#include "sweep.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <ostream>
#include <sstream>

namespace plant::sweep {

namespace {

// Fields never hold a comma, quote or newline, so a row splits on commas.
std::string field(std::string s) {
    for (char& c : s) {
        if (c == ',') c = ';';
        else if (c == '"') c = '\'';
        else if (c == '\n' || c == '\r') c = ' ';
    }
    return s;
}

std::vector<std::string> split(const std::string& row) {
    std::vector<std::string> out;
    std::string cur;
    for (char c : row) {
        if (c == ',') {
            out.push_back(cur);
            cur.clear();
        } else {
            cur += c;
        }
    }
    out.push_back(cur);
    return out;
}

bool write_file(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp, std::ios::binary);
        f << text;
        if (!f.flush()) return false;
    }
    return std::rename(tmp.c_str(), path.c_str()) == 0;
}

}  // namespace

std::string csv_header(const Spec& spec) {
    std::string h = "run,replicate";
    // Appended piece by piece: "," + string trips GCC 12's false -Wrestrict at -O3.
    for (const Param& p : spec.params) {
        h += ',';
        h += field(p.name);
    }
    for (const Output& o : spec.outputs) {
        h += ',';
        h += field(o.column());
    }
    return h + ",status,message,wall_s";
}

std::string csv_row(const Spec& spec, const Run& run, const Result& r) {
    std::string row = fmt::format("{},{}", run.index, run.replicate);
    for (const std::string& v : run.values) {
        row += ',';
        row += field(v);
    }
    for (size_t k = 0; k < spec.outputs.size(); ++k) {
        row += ',';
        row += field(k < r.outputs.size() ? r.outputs[k] : "");
    }
    return row + "," + r.status + "," + field(r.message) + fmt::format(",{:.3f}", r.wall);
}

std::string status_of(const Spec& spec, const std::string& row) {
    const auto cells = split(row);
    const size_t status_col = 2 + spec.params.size() + spec.outputs.size();
    return cells.size() == status_col + 3 ? cells[status_col] : "";
}

bool read_csv(const std::string& path, const Spec& spec, std::map<int, std::string>& rows,
              std::map<int, std::string>& status, std::string& error) {
    std::ifstream f(path, std::ios::binary);
    if (!f) return true;  // nothing yet
    std::string line;
    if (!std::getline(f, line)) return true;
    if (line != csv_header(spec)) {
        error = path + ": its header is not this spec's (" + csv_header(spec) + "): another spec wrote it";
        return false;
    }
    const size_t status_col = 2 + spec.params.size() + spec.outputs.size();
    while (std::getline(f, line)) {
        const auto cells = split(line);
        if (cells.size() != status_col + 3) continue;  // a row cut short by a crash of the sweep itself
        char* end = nullptr;
        const long i = std::strtol(cells[0].c_str(), &end, 10);
        if (*end || cells[0].empty()) continue;
        rows[int(i)] = line;
        status[int(i)] = cells[status_col];
    }
    return true;
}

bool append_row(const std::string& csv_path, const std::string& row) {
    std::FILE* f = std::fopen(csv_path.c_str(), "ab");
    if (!f) return false;
    const bool ok = std::fputs((row + "\n").c_str(), f) >= 0 && std::fflush(f) == 0;
    return std::fclose(f) == 0 && ok;
}

namespace {

// The column plotted: the spec's `plot`, else the first output that is not rtf.
size_t plot_column(const Spec& spec) {
    const size_t no = spec.outputs.size();
    size_t k = 0;
    if (!spec.plot.empty()) {
        while (k < no && spec.outputs[k].column() != spec.plot) ++k;
    } else {
        while (k < no && spec.outputs[k].name == "rtf") ++k;
        if (k == no) k = 0;
    }
    return k;
}

}  // namespace

std::optional<std::string> flat_plot_warning(const Spec& spec, const std::map<int, std::string>& rows) {
    const size_t np = spec.params.size(), no = spec.outputs.size(), status_col = 2 + np + no;
    const size_t k = plot_column(spec);
    if (k >= no) return std::nullopt;
    std::string value;
    int runs = 0;
    for (const auto& [i, row] : rows) {
        const auto c = split(row);
        if (c.size() != status_col + 3 || c[status_col] != "ok" || c[2 + np + k].empty()) continue;
        if (runs > 0 && c[2 + np + k] != value) return std::nullopt;
        value = c[2 + np + k];
        ++runs;
    }
    if (runs < 2) return std::nullopt;
    std::string why = "a plot of it is flat and shows nothing about the parameters";
    if (std::strtod(value.c_str(), nullptr) == 0)
        why += "; is the simulated time per run (" + spec.run_for + ", --for) long enough for anything to happen?";
    return spec.outputs[k].column() + " is " + value + " in every run that ended ok (" + std::to_string(runs) +
           " runs): " + why;
}

bool finish_outputs(const Spec& spec, const std::string& dir, const std::map<int, std::string>& rows,
                    std::ostream& err) {
    // results.csv, sorted by run index.
    std::string csv = csv_header(spec) + "\n";
    for (const auto& [i, row] : rows) csv += row + "\n";
    if (!write_file(dir + "/results.csv", csv)) {
        err << "plant sweep: error: cannot write " << dir << "/results.csv\n";
        return false;
    }

    // Means over the replicates of each combination (ok runs only).
    const size_t np = spec.params.size(), no = spec.outputs.size(), status_col = 2 + np + no;
    struct Group {
        std::vector<std::string> values;
        std::vector<double> sum;
        std::vector<int> n;
        int runs = 0, ok = 0;
    };
    std::vector<Group> groups;
    std::map<std::vector<std::string>, size_t> by_values;
    for (const auto& [i, row] : rows) {
        const auto c = split(row);
        if (c.size() != status_col + 3) continue;
        std::vector<std::string> key(c.begin() + 2, c.begin() + 2 + long(np));
        auto [it, fresh] = by_values.try_emplace(key, groups.size());
        if (fresh) groups.push_back({key, std::vector<double>(no, 0), std::vector<int>(no, 0), 0, 0});
        Group& g = groups[it->second];
        ++g.runs;
        if (c[status_col] != "ok") continue;
        ++g.ok;
        for (size_t k = 0; k < no; ++k) {
            const std::string& v = c[2 + np + k];
            if (v.empty()) continue;
            g.sum[k] += std::strtod(v.c_str(), nullptr);
            ++g.n[k];
        }
    }
    auto mean = [](const Group& g, size_t k) { return g.n[k] ? g.sum[k] / g.n[k] : 0.0; };
    std::ostringstream md;
    md << "# Sweep of " << spec.plant << "\n\n"
       << "From `" << spec.path << "`: " << rows.size() << " runs of " << spec.run_for << " each, "
       << spec.replicates << " replicate" << (spec.replicates == 1 ? "" : "s")
       << " per combination. Outputs are means over the replicates that ran to the end (ok).\n\n|";
    for (const Param& p : spec.params) md << " " << p.name << " |";
    for (const Output& o : spec.outputs) md << " " << o.column() << " |";
    md << " ok/runs |\n|";
    for (size_t k = 0; k < np + no + 1; ++k) md << (k < np ? "---|" : "--:|");
    md << "\n";
    for (const Group& g : groups) {
        md << "|";
        for (const auto& v : g.values) md << " " << v << " |";
        for (size_t k = 0; k < no; ++k) md << " " << (g.n[k] ? fmt::format("{:.4g}", mean(g, k)) : "-") << " |";
        md << " " << g.ok << "/" << g.runs << " |\n";
    }
    const std::optional<std::string> flat = flat_plot_warning(spec, rows);
    if (flat) {
        md << "\n**Warning:** " << *flat << "\n";
        err << "plant sweep: warning: " << *flat << "\n";
    }
    if (!write_file(dir + "/summary.md", md.str())) {
        err << "plant sweep: error: cannot write " << dir << "/summary.md\n";
        return false;
    }

    // The plot: the chosen output over the first parameter, a line per value of the second.
    if (np < 1 || np > 2 || no == 0) return true;
    const size_t k = plot_column(spec);
    std::vector<std::string> series;
    for (const Group& g : groups)
        if (np == 2 && std::find(series.begin(), series.end(), g.values[1]) == series.end()) series.push_back(g.values[1]);
    if (np == 1) series.push_back("");
    std::ostringstream dat;
    for (const std::string& s : series) {
        dat << "# " << (np == 2 ? spec.params[1].name + " = " + s : spec.params[0].name) << "\n";
        for (const Group& g : groups) {
            if (np == 2 && g.values[1] != s) continue;
            double x = 0;
            std::string unit;
            if (!g.n[k] || !split_quantity(g.values[0], x, unit)) continue;
            dat << fmt::format("{:g} {:g}\n", x, mean(g, k));
        }
        dat << "\n\n";
    }
    std::string xunit;
    double x0 = 0;
    if (!groups.empty()) split_quantity(groups[0].values[0], x0, xunit);
    std::ostringstream gp;
    gp << "# plot of " << spec.outputs[k].column() << " from " << spec.path << "; gnuplot plot.gp\n"
       << "set terminal svg size 800,500 dynamic background rgb 'white'\n"
       << "set output 'plot.svg'\n"
       << "set title \"" << spec.plant << ": " << spec.outputs[k].column() << " (mean of " << spec.replicates
       << ", " << spec.run_for << " each)\" noenhanced\n"
       << "set xlabel \"" << spec.params[0].name << (xunit.empty() ? "" : " (" + xunit + ")") << "\" noenhanced\n"
       << "set ylabel \"" << spec.outputs[k].column() << "\" noenhanced\n"
       << "set key outside right noenhanced\nset grid\n"
       << "plot ";
    for (size_t s = 0; s < series.size(); ++s)
        gp << (s ? ", " : "") << "'plot.dat' index " << s << " with linespoints title \""
           << (np == 2 ? spec.params[1].name + " = " + series[s] : spec.outputs[k].column()) << "\"";
    gp << "\n";
    if (!write_file(dir + "/plot.dat", dat.str()) || !write_file(dir + "/plot.gp", gp.str())) {
        err << "plant sweep: error: cannot write the plot files in " << dir << "\n";
        return false;
    }
    const std::string cmd = "cd '" + dir + "' && gnuplot plot.gp 2>/dev/null";
    if (std::system("command -v gnuplot >/dev/null 2>&1") == 0 && std::system(cmd.c_str()) != 0)
        err << "plant sweep: warning: gnuplot failed on " << dir << "/plot.gp\n";
    return true;
}

}  // namespace plant::sweep
