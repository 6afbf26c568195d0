#include "text.h"

#include "kinds.h"
#include "validate.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <fstream>
#include <istream>
#include <iterator>
#include <map>
#include <ostream>
#include <type_traits>
#include <vector>

namespace plant::graph {
namespace {

constexpr std::string_view kMagic = "plant-graph";
const std::string kVersion = std::to_string(kFormatVersion);

// ---- writing ----

class Writer {
public:
    Writer(const Graph& g, std::string& out) : g_(g), o_(out) {}

    template <class T>
    void field(std::string_view key, const T& v) {
        o_ += ' ';
        o_ += key;
        o_ += '=';
        put(v);
    }

    void put(int32_t v) { fmt::format_to(out(), "{}", v); }
    template <class R, IdRole Role>
    void put(TypedId<R, Role> id) { put(id.v); }
    void put(Detail d) { put(d.v); }
    void put(double v) { fmt::format_to(out(), "{}", v); }  // shortest round-trip form
    void put(bool v) { o_ += v ? "true" : "false"; }
    template <class E>
        requires std::is_enum_v<E>
    void put(E e) { o_ += word(e); }
    template <size_t N>
    void put(const std::array<double, N>& v) {
        o_ += '(';
        numbers(v);
        o_ += ')';
    }
    void put(const Pose& p) {
        o_ += '(';
        numbers(p.p);
        o_ += '|';
        numbers(p.q);
        o_ += ')';
    }
    void put(Name n) {
        if (n.id == -1) o_ += '-';
        else if (n.id < 0 || n.id >= count_of(g_.names))
            fmt::format_to(out(), "#{}", n.id);  // a broken id: visible, and rejected by the loader
        else put(g_.names[n.id]);
    }
    // Src{} is "-"; anything else is written in full so that nothing is lost.
    void put(Src s) {
        if (s == Src{}) o_ += '-';
        else fmt::format_to(out(), "{}:{}:{}", s.file, s.line, s.col);
    }
    // Escapes keep every record on one line.
    void put(std::string_view s) {
        o_ += '"';
        for (char c : s) {
            switch (c) {
            case '"': o_ += "\\\""; break;
            case '\\': o_ += "\\\\"; break;
            case '\n': o_ += "\\n"; break;
            case '\r': o_ += "\\r"; break;
            case '\t': o_ += "\\t"; break;
            default:
                if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
                    fmt::format_to(out(), "\\x{:02x}", static_cast<unsigned char>(c));
                else
                    o_ += c;
            }
        }
        o_ += '"';
    }

    template <class Rows, class F>
    void table(std::string_view member, std::string_view elem, const Rows& rows, F&& fields) {
        if (rows.empty() && optional_table(member)) return;
        fmt::format_to(out(), "count {} {}\n", member, rows.size());
        int32_t i = 0;
        for (const auto& r : rows) {
            fmt::format_to(out(), "{} {}", elem, i++);
            fields(r);
            o_ += '\n';
        }
    }

private:
    std::back_insert_iterator<std::string> out() { return std::back_inserter(o_); }
    template <size_t N>
    void numbers(const std::array<double, N>& v) {
        for (size_t i = 0; i < N; ++i) {
            if (i) o_ += ' ';
            put(v[i]);
        }
    }

    const Graph& g_;
    std::string& o_;
};

// ---- reading ----

// The element word of a table ("comps" -> "comp"), for messages.
std::string_view element_word(std::string_view member) {
#define PLANT_ELEMENT_WORD(member_, Record, elem, FIELDS) \
    if (member == #member_) return #elem;
    PLANT_GRAPH_TABLES(PLANT_ELEMENT_WORD)
#undef PLANT_ELEMENT_WORD
    return member;
}

// What a value was expected to be, for messages.
constexpr std::string_view what(int32_t) { return "integer"; }
template <class R, IdRole Role>
constexpr std::string_view what(TypedId<R, Role>) { return "integer"; }
constexpr std::string_view what(Detail) { return "integer"; }
constexpr std::string_view what(double) { return "number"; }
constexpr std::string_view what(bool) { return "bool"; }
template <class E>
    requires std::is_enum_v<E>
constexpr std::string_view what(E) { return "word"; }
template <size_t N>
constexpr std::string_view what(const std::array<double, N>&) { return N == 3 ? "vec3" : "quat"; }
constexpr std::string_view what(const Pose&) { return "pose"; }
constexpr std::string_view what(Name) { return "name"; }
constexpr std::string_view what(Src) { return "src"; }
inline std::string_view what(const std::string&) { return "string"; }

// A short piece of text at `s` for messages: a parenthesised value or a word.
std::string_view snippet(std::string_view s) {
    size_t end = s.starts_with('(') ? s.find(')') : s.find(' ');
    if (end != std::string_view::npos && s.starts_with('(')) ++end;
    return s.substr(0, std::min<size_t>(end, 40));
}

// The header's version when it is not this program's: what it is, and what to do.
std::string version_error(std::string_view rest) {
    int v = 0;
    const auto [end, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), v);
    if (ec != std::errc{} || end != rest.data() + rest.size() || v <= 0)
        return fmt::format("'{}' is not a format version (this program reads plant-graph {})", snippet(rest),
                           kFormatVersion);
    if (v < kFormatVersion)
        return fmt::format("written by an older compiler, in format {} (this program reads format {}): compile "
                           "its plant file again, `plant build FILE.plant -o FILE.graph`",
                           v, kFormatVersion);
    return fmt::format("written by a newer compiler, in format {} (this program reads format {}): run it with "
                       "that compiler's plant, or compile its plant file again with this one",
                       v, kFormatVersion);
}

// Parses the grammar described in text.h; every step either advances or fails
// with the first error, so any input ends after one pass over it.
class Reader {
public:
    Reader(std::istream& in, Graph& g) : in_(in), g_(g) {}
    const std::string& error() const { return error_; }
    // The line each record was read from, per table member name; the settings line as "".
    int line_of(std::string_view member, int32_t row) const {
        auto it = lines_.find(std::string(member));
        if (it == lines_.end() || row < 0 || row >= count_of(it->second)) return settings_line_;
        return it->second[row];
    }

    bool read() {
        Graph& g = g_;
        if (!line(kMagic)) return false;
        if (!lit(" ") || rest_ != kVersion) return fail(version_error(rest_));
        if (!line("plant") || !arg("plant", g.plant) || !end_of_line()) return false;
        if (!line("settings")) return false;
        settings_line_ = line_no_;
        if (!field("rate", g.settings.rate) || !field("gravity", g.settings.gravity))
            return false;
        // Optional, written only when off (the default is on).
        if (rest_.starts_with(" steady_transport=") && !field("steady_transport", g.settings.steady_transport))
            return false;
        if (!end_of_line()) return false;
        if (!table("files", "file", g.files, [&](std::string& f) { return arg("file", f); }))
            return false;
#define PLANT_READ_FIELD(T_, f_) &&field(#f_, r.f_)
#define PLANT_READ_TABLE(member, Record, elem, FIELDS) \
    if (!table(#member, #elem, g.member, [&](Record& r) { return true FIELDS(PLANT_READ_FIELD); })) \
        return false;
        PLANT_GRAPH_TABLES(PLANT_READ_TABLE)
#undef PLANT_READ_TABLE
#undef PLANT_READ_FIELD
        if (!line("end") || !end_of_line()) return false;
        if (advance()) return fail("unexpected content after 'end'");
        return true;
    }

private:
    bool fail(std::string_view msg) {
        if (error_.empty()) error_ = fmt::format("line {}: {}", line_no_, msg);
        return false;
    }

    // Moves to the next line that is not blank or a comment; false at the end.
    bool advance() {
        while (std::getline(in_, line_)) {
            ++line_no_;
            if (!line_.empty() && line_.back() == '\r') line_.pop_back();
            if (line_.empty() || line_[0] == '#') continue;
            rest_ = line_;
            return true;
        }
        ++line_no_;  // report the end as the line after the last one
        rest_ = {};
        return false;
    }
    bool next_line() {
        if (held_) {
            held_ = false;
            return true;
        }
        return advance() || fail("unexpected end of file");
    }

    // The next line, which must start with `keyword` as a whole word.
    bool line(std::string_view keyword) {
        if (!next_line()) return false;
        std::string_view at = rest_;
        if (lit(keyword) && at_delim()) return true;
        return fail(fmt::format("expected '{}', got '{}'", keyword, snippet(at)));
    }

    bool lit(std::string_view s) {
        if (!rest_.starts_with(s)) return false;
        rest_.remove_prefix(s.size());
        return true;
    }
    bool at_delim() const { return rest_.empty() || rest_[0] == ' '; }

    bool end_of_line() {
        if (rest_.empty()) return true;
        return fail(fmt::format("unexpected '{}' at the end of the line", snippet(rest_.substr(1))));
    }

    // " key=value"
    template <class T>
    bool field(std::string_view key, T& v) {
        if (rest_.empty()) return fail(fmt::format("missing field '{}'", key));
        std::string_view at = rest_;
        if (lit(" ") && lit(key) && lit("=")) return value(key, v);
        if (at.starts_with(' ')) at.remove_prefix(1);
        return fail(fmt::format("expected field '{}', got '{}'", key, at.substr(0, at.find_first_of("= "))));
    }
    // " value"
    template <class T>
    bool arg(std::string_view key, T& v) {
        if (!lit(" ")) return fail(fmt::format("missing {}", what(v)));
        return value(key, v);
    }
    // A value must end the line or be followed by a space.
    template <class T>
    bool value(std::string_view key, T& v) {
        std::string_view at = rest_;
        if (get(v) && at_delim()) return true;
        return fail(fmt::format("bad {} '{}' for '{}'", what(v), snippet(at), key));
    }

    template <class N>
    bool number(N& v) {
        const char* b = rest_.data();
        auto [p, ec] = std::from_chars(b, b + rest_.size(), v);
        if (ec != std::errc{}) return false;
        rest_.remove_prefix(p - b);
        return true;
    }
    template <size_t N>
    bool numbers(std::array<double, N>& v) {
        for (size_t i = 0; i < N; ++i)
            if ((i && !lit(" ")) || !number(v[i])) return false;
        return true;
    }

    bool get(int32_t& v) { return number(v); }
    template <class R, IdRole Role>
    bool get(TypedId<R, Role>& id) { return number(id.v); }
    bool get(Detail& d) { return number(d.v); }
    bool get(double& v) { return number(v); }
    bool get(bool& v) {
        if (lit("true")) v = true;
        else if (lit("false")) v = false;
        else return false;
        return true;
    }
    template <class E>
        requires std::is_enum_v<E>
    bool get(E& e) {
        size_t n = std::min(rest_.find(' '), rest_.size());
        if (!parse_word(rest_.substr(0, n), e)) return false;
        rest_.remove_prefix(n);
        return true;
    }
    template <size_t N>
    bool get(std::array<double, N>& v) { return lit("(") && numbers(v) && lit(")"); }
    bool get(Pose& p) { return lit("(") && numbers(p.p) && lit("|") && numbers(p.q) && lit(")"); }
    bool get(Name& n) {
        if (lit("-")) {
            n = Name{};
            return true;
        }
        std::string s;
        if (!get(s)) return false;
        n = g_.intern(s);
        return true;
    }
    bool get(Src& s) {
        if (rest_.starts_with('-') && (rest_.size() == 1 || rest_[1] == ' ')) {
            rest_.remove_prefix(1);
            s = Src{};
            return true;
        }
        return number(s.file) && lit(":") && number(s.line) && lit(":") && number(s.col);
    }
    bool get(std::string& s) {
        if (!lit("\"")) return false;
        while (!rest_.empty()) {
            char c = rest_[0];
            rest_.remove_prefix(1);
            if (c == '"') return true;
            if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return false;  // must be escaped
            if (c != '\\') {
                s += c;
                continue;
            }
            if (rest_.empty()) return false;
            char e = rest_[0];
            rest_.remove_prefix(1);
            switch (e) {
            case 'n': s += '\n'; break;
            case 'r': s += '\r'; break;
            case 't': s += '\t'; break;
            case '"':
            case '\\': s += e; break;
            case 'x': {
                unsigned byte = 0;
                if (rest_.size() < 2) return false;
                auto [p, ec] = std::from_chars(rest_.data(), rest_.data() + 2, byte, 16);
                if (ec != std::errc{} || p != rest_.data() + 2) return false;
                s += static_cast<char>(byte);
                rest_.remove_prefix(2);
                break;
            }
            default: return false;
            }
        }
        return false;  // unterminated
    }

    // "count <member> N" and then N lines "<elem> <id> ...", ids 0..N-1 in order.
    template <class Rows, class F>
    bool table(std::string_view member, std::string_view elem, Rows& rows, F&& fields) {
        if (!next_line()) return false;
        std::string_view at = rest_;
        int32_t n = -1;
        if (optional_table(member) && !at.starts_with(fmt::format("count {} ", member))) {
            held_ = true;  // absent: empty, and this line is the next table's (or 'end')
            return true;
        }
        if (!(lit("count ") && lit(member) && lit(" ") && number(n) && rest_.empty() && n >= 0))
            return fail(fmt::format("expected 'count {} N', got '{}'", member, at.substr(0, 40)));
        std::vector<int>& lines = lines_[std::string(member)];
        for (int32_t i = 0; i < n; ++i) {
            if (!next_line()) return false;
            at = rest_;
            int32_t id = -1;
            if (!(lit(elem) && lit(" ") && number(id) && at_delim()))
                return fail(fmt::format("expected '{} {}', got '{}'", elem, i, at.substr(0, 40)));
            if (id != i) return fail(fmt::format("expected {} id {}, got {}", elem, i, id));
            typename Rows::value_type r{};
            if (!fields(r) || !end_of_line()) return false;
            rows.push_back(std::move(r));
            lines.push_back(line_no_);
        }
        return true;
    }

    std::istream& in_;
    Graph& g_;
    std::string line_;
    std::string_view rest_;  // the unread part of line_
    int line_no_ = 0;
    bool held_ = false;  // the current line is to be read again (an absent optional table)
    std::string error_;
    std::map<std::string, std::vector<int>> lines_;
    int settings_line_ = 0;
};

}  // namespace

std::string to_text(const Graph& g) {
    std::string o;
    Writer w(g, o);
    o += fmt::format("{} {}\nplant ", kMagic, kVersion);
    w.put(g.plant);
    o += "\nsettings";
    w.field("rate", g.settings.rate);
    w.field("gravity", g.settings.gravity);
    if (!g.settings.steady_transport) w.field("steady_transport", false);
    o += '\n';
    w.table("files", "file", g.files, [&](const std::string& f) {
        o += ' ';
        w.put(std::string_view(f));
    });
#define PLANT_WRITE_FIELD(T_, f_) w.field(#f_, r.f_);
#define PLANT_WRITE_TABLE(member, Record, elem, FIELDS) \
    w.table(#member, #elem, g.member, [&](const Record& r) { FIELDS(PLANT_WRITE_FIELD) });
    PLANT_GRAPH_TABLES(PLANT_WRITE_TABLE)
#undef PLANT_WRITE_TABLE
#undef PLANT_WRITE_FIELD
    o += "end\n";
    return o;
}

void write_text(const Graph& g, std::ostream& out) { out << to_text(g); }

namespace {

constexpr uint64_t fnv1a(std::string_view s, uint64_t h) {
    for (const char c : s) {
        h ^= static_cast<unsigned char>(c);
        h *= 1099511628211ull;
    }
    return h;
}

// The tables as the X-macros list them: "member word {Type field;...}" each, in order.
#define PLANT_SCHEMA_FIELD(T_, f_) #T_ " " #f_ ";"
#define PLANT_SCHEMA_TABLE(member, Record, elem, FIELDS) #member " " #elem " {" FIELDS(PLANT_SCHEMA_FIELD) "}\n"
constexpr std::string_view kSchema = "settings rate gravity [steady_transport]\nfiles file\n" PLANT_GRAPH_TABLES(PLANT_SCHEMA_TABLE);
#undef PLANT_SCHEMA_TABLE
#undef PLANT_SCHEMA_FIELD

// The schema as the fingerprint reads it: a field's type as the text form knows it. An
// OptId<R> is written as R's id is (it only may be -1, which the loader decides), and
// Detail and Adr<Value> as the int32_t they were before they were typed: the text is the
// same, so the fingerprint and the version stay.
std::string schema_as_written() {
    std::string s(kSchema);
    auto replace_all = [&s](std::string_view from, std::string_view to) {
        for (size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
            s.replace(at, from.size(), to);
    };
    replace_all("Detail ", "int32_t ");
    replace_all("Adr<Value> ", "int32_t ");
    for (size_t at = s.find("OptId<"); at != std::string::npos; at = s.find("OptId<", at)) {
        const size_t close = s.find('>', at);
        const std::string record = s.substr(at + 6, close - at - 6);
        s.replace(at, close + 1 - at, record + "Id");
    }
    return s;
}

template <class E>
uint64_t hash_words(uint64_t h, E last) {
    for (int i = 0; i <= int(last); ++i) h = fnv1a(std::string(word(E(i))) + ",", h);
    return fnv1a(";", h);
}

}  // namespace

uint64_t format_fingerprint() {
    uint64_t h = fnv1a(schema_as_written(), 14695981039346656037ull);
    h = hash_words(h, SlotType::Ref);
    h = hash_words(h, Dir::Out);
    h = hash_words(h, CompKind::Plugin);
    h = hash_words(h, BodyMode::Kinematic);
    h = hash_words(h, ShapeKind::Hull);
    h = hash_words(h, JointKind::Slider);
    h = hash_words(h, Cond::Either);
    h = hash_words(h, LogicOp::Or);
    for (int k = 0; k <= int(CompKind::Plugin); ++k)
        for (const SlotSpec& s : fixed_slots(CompKind(k)))
            h = fnv1a(fmt::format("{}:{} {} {};", word(CompKind(k)), s.name, word(s.type), word(s.dir)), h);
    return h;
}

bool read_text(std::istream& in, Graph& g, std::string& error, Check check) {
    Graph loaded;
    Reader reader(in, loaded);
    if (!reader.read()) {
        error = reader.error();
        return false;
    }
    GraphProblem p;
    if (check == Check::Full && !validate(loaded, p)) {
        const int line = reader.line_of(p.table, p.row);
        error = p.table.empty() ? fmt::format("line {}: {}", line, p.message)
                                : fmt::format("line {}: {} {}: {}", line, element_word(p.table), p.row, p.message);
        return false;
    }
    g = std::move(loaded);
    error.clear();
    return true;
}

bool load_text_file(const std::string& path, Graph& g, std::string& error, Check check) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        error = path + ": cannot open";
        return false;
    }
    if (read_text(in, g, error, check)) return true;
    error = path + ": " + error;
    return false;
}

}  // namespace plant::graph
