// Completion, read from the buffer as typed (the line being written rarely parses) and the
// last parse of the file: after `a.b.` the members of what the path names (an instance's
// type, a cast's, a source's pooled object's: its ports, instances and components; a
// component: its slots); after `import` the
// modules and the object types they declare; after a number the units; at the start of a
// line in a component's braces its kind's properties; at the start of a member the
// component kinds and the object types.
#include "lsp/lookup.h"
#include "lsp/symbols.h"

#include "graph/kinds.h"
#include "sema/schema.h"
#include "units/units.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace plant::lsp {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The LSP's CompletionItemKind numbers we use.
enum class ItemKind { Field = 5, Variable = 6, Class = 7, Module = 9, Property = 10, Unit = 11, Keyword = 14, Event = 23 };

bool ident(char ch) { return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'; }

struct Seg {
    std::string name;
    bool indexed = false;  // seg[i]
};
// What is written before the dot at `dot`: `(p as Bottle).a.b[i].c` gives the cast's type
// "Bottle" and the segments a, b[i], c.
struct Chain {
    std::string cast_type;
    std::vector<Seg> segs;
};

Chain chain_before(const std::string& t, size_t dot) {
    Chain chain;
    size_t at = dot;
    for (;;) {
        size_t end = at;
        bool indexed = false;
        if (end > 0 && (t[end - 1] == ']' || t[end - 1] == ')')) {  // skip an index, or a cast
            const char close = t[end - 1], open = close == ']' ? '[' : '(';
            const size_t inner_end = end - 1;
            int depth = 0;
            while (end > 0) {
                const char ch = t[--end];
                depth += ch == close ? 1 : ch == open ? -1 : 0;
                if (depth == 0) break;
            }
            if (close == ')') {
                std::istringstream words(t.substr(end + 1, inner_end - end - 1));
                std::string word, last, before_last;
                while (words >> word) before_last = last, last = word;
                if (before_last == "as") chain.cast_type = last;
                return chain;
            }
            indexed = true;
        }
        size_t begin = end;
        while (begin > 0 && ident(t[begin - 1])) --begin;
        if (begin == end) break;
        chain.segs.insert(chain.segs.begin(), Seg{t.substr(begin, end - begin), indexed});
        if (begin == 0 || t[begin - 1] != '.') break;
        at = begin - 1;
    }
    return chain;
}

// The type a source issues: the callee of its `object` property.
const ast::ObjectDecl* issued_type(const Compilation& c, const ast::ComponentDecl& k) {
    if (k.kind.text != "source") return nullptr;
    for (const auto& p : k.properties)
        if (p.name.text == "object" && p.value) return find_type(c, p.value->text);
    return nullptr;
}

void add_type_members(const ast::ObjectDecl& type, json& items) {
    const Members ms = members_of(type);
    for (const ast::PortDecl* p : ms.ports)
        items.push_back({{"label", p->name.text}, {"kind", ItemKind::Field}, {"detail", (p->is_input ? "in " : "out ") + p->type.text}});
    for (const ast::InstanceDecl* x : ms.instances)
        items.push_back({{"label", x->name.text}, {"kind", ItemKind::Variable}, {"detail", x->type.text}});
    for (const ast::ComponentDecl* x : ms.components)
        if (!x->name.text.empty()) items.push_back({{"label", x->name.text}, {"kind", ItemKind::Property}, {"detail", x->kind.text}});
}

void add_slots(const ast::ComponentDecl& k, json& items) {
    if (const sema::KindSpec* spec = sema::find_kind(k.kind.text))
        for (const graph::SlotSpec& s : sema::kind_slots(*spec))
            items.push_back({{"label", std::string(s.name)}, {"kind", ItemKind::Event},
                             {"detail", fmt::format("{} {}", graph::word(s.dir), graph::word(s.type))},
                             {"documentation", std::string(s.doc)}});
    auto named = [&](const std::string& name, const char* what) { items.push_back({{"label", name}, {"kind", ItemKind::Field}, {"detail", what}}); };
    for (const auto& p : k.places) named(p.name.text, "place");
    for (const auto& t : k.transitions) named(t.name.text, "transition");
    for (const auto& a : k.animations) named(a.name.text, "animation");
    for (const auto& v : k.variants) named(v.name.text, "variant");
    for (const auto& g : k.children) named(g.name.text, "child graphics");
}

// The members of what `chain` names, looked up from the object written at `offset` (else
// from the file's other objects), or from a cast's type; through instances' types and a
// source's pooled objects (`store[i].`), and into a component's slots.
json members_after(const Compilation& c, const sema::LoadedModule& m, size_t offset, const Chain& chain) {
    json items = json::array();
    std::vector<const ast::ObjectDecl*> from;  // the object written at `offset` first
    if (!chain.cast_type.empty()) {
        if (const ast::ObjectDecl* t = find_type(c, chain.cast_type)) from.push_back(t);
    } else {
        for (const auto& o : m.ast->objects)
            if (inside(o.span, offset)) from.push_back(&o);
        for (const auto& o : m.ast->objects)
            if (!inside(o.span, offset)) from.push_back(&o);
    }
    for (const ast::ObjectDecl* o : from) {
        const ast::ObjectDecl* in = o;
        const ast::ComponentDecl* component = nullptr;
        for (const Seg& seg : chain.segs) {
            if (component) {  // a child graphics: graphics look { graphics lid ... }
                const ast::ComponentDecl* child = nullptr;
                for (const auto& g : component->children)
                    if (g.name.text == seg.name) child = &g;
                component = child;
            } else if (in) {
                const Members ms = members_of(*in);
                const ast::ObjectDecl* next = nullptr;
                for (const ast::InstanceDecl* i : ms.instances)
                    if (i->name.text == seg.name) next = find_type(c, i->type.text);
                for (const ast::ComponentDecl* k : ms.components)
                    if (k->name.text == seg.name) {
                        if (seg.indexed && issued_type(c, *k)) next = issued_type(c, *k);
                        else component = k;
                    }
                in = next;
            }
            if (!in && !component) break;
        }
        if (component) add_slots(*component, items);
        else if (in && (in != o || !chain.cast_type.empty())) add_type_members(*in, items);
        if (!items.empty()) break;
    }
    return items;
}

// The object types a module file declares (its `object NAME` lines).
std::vector<std::string> declared_types(const fs::path& file) {
    std::ifstream in(file);
    std::vector<std::string> out;
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string first, name;
        if (words >> first && first == "object" && words >> name) {
            name = name.substr(0, name.find_first_of("({ "));
            if (!name.empty()) out.push_back(name);
        }
    }
    return out;
}

// After `import`: the stdlib's modules (their types as detail), and each type, which
// inserts the module that declares it.
json imports(const std::string& stdlib_dir) {
    json items = json::array();
    std::error_code ec;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(stdlib_dir, ec))
        if (e.path().extension() == ".plant") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
        const std::string module = "std." + f.stem().string();
        const std::vector<std::string> types = declared_types(f);
        std::string detail;
        for (const auto& t : types) detail += (detail.empty() ? "" : ", ") + t;
        items.push_back({{"label", module}, {"kind", ItemKind::Module}, {"detail", detail}});
        for (const auto& t : types)
            items.push_back({{"label", t}, {"kind", ItemKind::Class}, {"detail", module}, {"insertText", module}});
    }
    return items;
}

// The first word of the line that opens the innermost `{` still open at `at`, or "".
std::string opener(const std::string& t, size_t at) {
    int depth = 0;
    for (size_t i = at; i-- > 0;) {
        if (t[i] == '}') ++depth;
        else if (t[i] == '{' && depth-- == 0) {
            const size_t line = t.rfind('\n', i);
            std::istringstream words(t.substr(line == std::string::npos ? 0 : line + 1, i - (line == std::string::npos ? 0 : line + 1)));
            std::string first;
            words >> first;
            if (first == "}") words >> first;  // } else {
            return first.substr(0, first.find_first_of(":({"));
        }
    }
    return "";
}

json properties(const sema::KindSpec& spec) {
    json items = json::array();
    for (const auto& p : spec.props) {
        std::string detail = p.dim.none() ? "" : units::dim_name(p.dim) + " (" + units::si_unit(p.dim) + ")";
        if (p.required) detail += detail.empty() ? "required" : ", required";
        items.push_back({{"label", std::string(p.name)}, {"kind", ItemKind::Property}, {"detail", detail},
                         {"documentation", std::string(p.doc)}});
    }
    return items;
}

}  // namespace

json completion(const Compilation* c, const sema::LoadedModule* m, const std::string& t, size_t offset,
                const std::string& stdlib_dir) {
    json items = json::array();
    size_t start = std::min(offset, t.size());
    while (start > 0 && ident(t[start - 1])) --start;
    const size_t line_begin = start == 0 ? 0 : t.rfind('\n', start - 1) + 1;  // npos + 1 == 0
    const std::string before = t.substr(line_begin, start - line_begin);
    const size_t first = before.find_first_not_of(" \t");
    const bool is_import = first != std::string::npos && before.compare(first, 6, "import") == 0;
    if (is_import) return imports(stdlib_dir);
    if (start > 0 && t[start - 1] == '.')
        return c && m ? members_after(*c, *m, offset, chain_before(t, start - 1)) : items;
    size_t k = before.size();
    while (k > 0 && before[k - 1] == ' ') --k;
    if (k > 0 && std::isdigit(static_cast<unsigned char>(before[k - 1]))) {
        for (const auto& u : units::unit_atoms()) items.push_back({{"label", u}, {"kind", ItemKind::Unit}});
        return items;
    }
    const std::string open = opener(t, start);
    if (first == std::string::npos) {  // the start of a line
        if (const sema::KindSpec* spec = sema::find_kind(open)) return properties(*spec);
        if (open == "object" || open == "plant" || open == "for" || open == "if" || open == "else")
            for (const auto& word : sema::kind_words())
                items.push_back({{"label", word}, {"kind", ItemKind::Keyword}, {"detail", "component"},
                                 {"documentation", std::string(sema::find_kind(word)->doc)}});
    }
    if (c)
        for (const auto& mod : c->program.modules)
            for (const auto& o : mod.ast->objects)
                if (!o.is_plant) items.push_back({{"label", o.name.text}, {"kind", ItemKind::Class}, {"detail", signature(*c, o)}});
    return items;
}

}  // namespace plant::lsp
