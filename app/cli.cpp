#include "app/cli.h"

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <ostream>
#include <sstream>

namespace plant::app {

namespace {

constexpr size_t kColumn = 28;  // where a flag's help starts

// "-o, --output OUT": a flag's names and its value as the help shows them.
std::string flag_names(const CLI::Option& o) {
    std::string s;
    for (const auto& n : o.get_snames()) s += (s.empty() ? "-" : ", -") + n;
    for (const auto& n : o.get_lnames()) s += (s.empty() ? "--" : ", --") + n;
    const std::string shown = o.get_type_name();
    if (!shown.empty()) s += (o.get_expected_max() == 0 ? "[=" + shown + "]" : " " + shown);
    return s;
}

}  // namespace

Cli::Cli(std::string command, std::string usage, std::string about, std::string footer)
    : command_(std::move(command)),
      usage_(std::move(usage)),
      about_(std::move(about)),
      footer_(std::move(footer)),
      prefix_("plant " + command_),
      help_of_("plant " + command_ + " --help"),
      name_("plant " + command_),
      app_("plant " + command_) {
    app_.set_help_flag("-h,--help", "this help");
    app_.allow_extras();  // unknown flags are reported in our words (parse)
}

void Cli::errors_as(std::string prefix, std::string help_of) {
    prefix_ = std::move(prefix);
    help_of_ = std::move(help_of);
}

CLI::Option* Cli::value(const std::string& names, std::string& v, const std::string& help, const std::string& shown,
                        const std::string& needs) {
    CLI::Option* o = app_.add_option(names, v, help)->type_name(shown);
    needs_[o->get_name()] = needs;
    return o;
}

CLI::Option* Cli::values(const std::string& names, std::vector<std::string>& v, const std::string& help,
                         const std::string& shown, const std::string& needs) {
    CLI::Option* o = app_.add_option(names, v, help)->type_name(shown)->allow_extra_args(false);
    needs_[o->get_name()] = needs;
    return o;
}

CLI::Option* Cli::flag(const std::string& names, bool& v, const std::string& help) {
    return app_.add_flag(names, v, help)->type_name("");
}

CLI::Option* Cli::flag_value(const std::string& names, std::string& v, const std::string& plain, const std::string& help,
                             const std::string& shown) {
    // CLI11's "--name{default}": the default without '=', the value after it.
    std::string spec;
    for (size_t at = 0; at <= names.size();) {
        const size_t comma = std::min(names.find(',', at), names.size());
        spec += (spec.empty() ? "" : ",") + names.substr(at, comma - at) + "{" + plain + "}";
        at = comma + 1;
    }
    return app_.add_flag(spec, v, help)->type_name(shown);
}

void Cli::positionals(std::vector<std::string>& v) { app_.add_option("words", v)->type_name(""); }

int Cli::usage_error(std::ostream& err, const std::string& message) const {
    err << prefix_ << ": error: " << message << "\n";
    if (!help_of_.empty()) err << "(see `" << help_of_ << "`)\n";
    return 2;
}

std::string Cli::help() const {
    std::ostringstream out;
    out << "usage: " << name_ << (usage_.empty() ? "" : " ") << usage_ << "\n";
    if (!about_.empty()) out << "\n" << about_ << "\n";
    std::string flags;
    for (const CLI::Option* o : app_.get_options()) {
        if (o->get_positional()) continue;
        std::string line = "  " + flag_names(*o);
        line += line.size() + 2 <= kColumn ? std::string(kColumn - line.size(), ' ') : "\n" + std::string(kColumn, ' ');
        const std::string& d = o->get_description();
        for (size_t at = 0; at < d.size();) {  // a description's lines, each at the column
            const size_t nl = std::min(d.find('\n', at), d.size());
            line += (at ? "\n" + std::string(kColumn, ' ') : "") + d.substr(at, nl - at);
            at = nl + 1;
        }
        flags += line + "\n";
    }
    if (!flags.empty()) out << "\n" << flags;
    if (!footer_.empty()) out << "\n" << footer_;
    return out.str();
}

int Cli::parse(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
    try {
        app_.parse(std::vector<std::string>(args.rbegin(), args.rend()));  // CLI11 takes them reversed
    } catch (const CLI::CallForHelp&) {
        out << help();
        return 0;
    } catch (const CLI::ArgumentMismatch& e) {
        // "--for: 1 required 10s missing": said as the flag's own need.
        const std::string what = e.what();
        const auto it = needs_.find(what.substr(0, what.find(':')));
        return usage_error(err, it != needs_.end() ? it->first + " needs " + it->second : what);
    } catch (const CLI::ParseError& e) {
        return usage_error(err, e.what());
    }
    for (const std::string& a : app_.remaining())
        if (a.size() > 1 && a[0] == '-') return usage_error(err, "unknown " + unknown_ + " '" + a + "'");
    return -1;
}

bool whole_number(const std::string& text, long lo, long hi, long& v) {
    // Digits, after a '-' at most: strtol alone would take a leading space or '+' too.
    const size_t first = !text.empty() && text[0] == '-' ? 1 : 0;
    if (first >= text.size() || !std::isdigit(static_cast<unsigned char>(text[first]))) return false;
    char* end = nullptr;
    errno = 0;
    v = std::strtol(text.c_str(), &end, 10);
    return !text.empty() && !*end && errno == 0 && v >= lo && v <= hi;
}

}  // namespace plant::app
