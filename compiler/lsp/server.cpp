#include "lsp/lsp.h"
#include "lsp/protocol.h"
#include "lsp/symbols.h"

#include "compiler.h"
#include "fmt/formatter.h"
#include "units/units.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <istream>
#include <map>
#include <memory>
#include <optional>
#include <algorithm>
#include <cctype>
#include <variant>
#include <ostream>
#include <set>
#include <string>
#include <tuple>
#include <vector>

namespace plant::lsp {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// JSON-RPC error codes (the LSP specification's).
constexpr int kParseError = -32700;
constexpr int kInvalidRequest = -32600;
constexpr int kMethodNotFound = -32601;
constexpr int kInvalidParams = -32602;
constexpr int kServerNotInitialized = -32002;
constexpr int kRequestFailed = -32803;

std::string canonical(const std::string& path) {
    std::error_code ec;
    fs::path c = fs::weakly_canonical(path, ec);
    return ec ? path : c.string();
}

json zero_range() {
    json p = {{"line", 0}, {"character", 0}};
    return {{"start", p}, {"end", p}};
}

class Server {
public:
    Server(std::ostream& out, std::string stdlib) : out_(out), stdlib_(std::move(stdlib)) {}

    // Returns false when the client said `exit`.
    bool handle(const std::string& body) {
        json msg = json::parse(body, nullptr, false);
        if (msg.is_discarded()) {
            send_error(nullptr, kParseError, "the message is not valid JSON");
            return true;
        }
        if (!msg.is_object() || !msg.contains("method") || !msg["method"].is_string()) {
            // A response from the client (we send no requests) needs nothing; anything else is invalid.
            if (msg.is_object() && msg.contains("id") && !msg.contains("result") && !msg.contains("error"))
                send_error(msg["id"], kInvalidRequest, "a request needs a string 'method'");
            else if (!msg.is_object())
                send_error(nullptr, kInvalidRequest, "a JSON-RPC message is an object");
            return true;
        }
        const std::string method = msg["method"];
        const bool is_request = msg.contains("id");
        const json id = is_request ? msg["id"] : json();
        const json params = msg.contains("params") ? msg["params"] : json::object();
        if (method == "exit") return false;
        if (!initialized_ && method != "initialize") {
            if (is_request) send_error(id, kServerNotInitialized, "the server is not initialized");
            return true;
        }
        try {
            dispatch(method, is_request, id, params);
        } catch (const json::exception& e) {
            if (is_request) send_error(id, kInvalidParams, std::string("bad parameters: ") + e.what());
        }
        return true;
    }

    bool shut_down() const { return shutdown_; }

private:
    void dispatch(const std::string& method, bool is_request, const json& id, const json& params) {
        if (method == "initialize") {
            initialized_ = true;
            json sync = {{"openClose", true}, {"change", 2}, {"save", {{"includeText", false}}}};
            send_result(id, {{"capabilities", {{"textDocumentSync", sync},
                                                {"definitionProvider", true},
                                                {"documentSymbolProvider", true},
                                                {"referencesProvider", true},
                                                {"hoverProvider", true},
                                                {"documentFormattingProvider", true},
                                                {"completionProvider", {{"triggerCharacters", {"."}}}}}},
                             {"serverInfo", {{"name", "plant lsp"}}}});
        } else if (method == "initialized") {
        } else if (method == "shutdown") {
            shutdown_ = true;
            send_result(id, nullptr);
        } else if (method == "textDocument/didOpen") {
            const json& doc = params.at("textDocument");
            open(doc.at("uri").get<std::string>(), doc.at("text").get<std::string>());
        } else if (method == "textDocument/didChange") {
            change(params.at("textDocument").at("uri").get<std::string>(), params.at("contentChanges"));
        } else if (method == "textDocument/didSave") {
            const std::string uri = params.at("textDocument").at("uri");
            if (auto it = docs_.find(uri); it != docs_.end() && params.contains("text"))
                it->second.text = params["text"].get<std::string>();
            recheck();
        } else if (method == "textDocument/didClose") {
            docs_.erase(params.at("textDocument").at("uri").get<std::string>());
            recheck();
        } else if (method == "textDocument/formatting") {
            if (const Document* doc = document(id, params)) format_document(id, *doc);
        } else if (method == "textDocument/definition" || method == "textDocument/hover" ||
                   method == "textDocument/completion" || method == "textDocument/documentSymbol" ||
                   method == "textDocument/references") {
            const Document* found = document(id, params);
            if (!found) return;
            const Document& doc = *found;
            if (method == "textDocument/documentSymbol") {
                const sema::LoadedModule* m = module_of(doc);
                send_result(id, m ? document_symbols(*doc.parsed, *m) : json::array());
                return;
            }
            const json& p = params.at("position");
            const size_t offset = offset_of(doc.text, p.at("line"), p.at("character"));
            if (method == "textDocument/references")
                send_result(id, references(doc, offset, params.at("context").at("includeDeclaration").get<bool>()));
            else if (method == "textDocument/definition") send_result(id, definition(doc, offset));
            else if (method == "textDocument/hover") send_result(id, hover(doc, offset));
            else send_result(id, completion(doc, offset));
        } else if (is_request) {
            send_error(id, kMethodNotFound, "unknown method '" + method + "'");
        }
        // Unknown notifications ($/cancelRequest, workspace/didChangeConfiguration, ...) are ignored.
    }

    struct Document {
        std::string path;  // canonical
        std::string text;
        // The last compilation of this document whose own file parsed: what hover,
        // definition and completion look at while the buffer has a syntax error.
        std::shared_ptr<Compilation> parsed;
    };

    // The open document a request names; null after answering with an error.
    const Document* document(const json& id, const json& params) {
        const std::string uri = params.at("textDocument").at("uri");
        auto it = docs_.find(uri);
        if (it != docs_.end()) return &it->second;
        send_error(id, kInvalidParams, "unknown document '" + uri + "' (not opened)");
        return nullptr;
    }

    // `plant fmt` on the buffer: one edit replacing the whole text (none when it is
    // formatted). The client's tab size and spaces option do not apply: the layout is fixed.
    void format_document(const json& id, const Document& doc) {
        SourceMap sources;
        Sink sink;
        const auto out = formatter::format_text(doc.path, doc.text, sources, sink);
        if (!out) {
            send_error(id, kRequestFailed, "not formatted: the document has syntax errors (see its diagnostics)");
            return;
        }
        json edits = json::array();
        if (*out != doc.text) {
            const int32_t raw = sources.add(doc.path, doc.text);
            json range = {{"start", {{"line", 0}, {"character", 0}}},
                          {"end", position_of(sources, raw, static_cast<uint32_t>(doc.text.size()))}};
            edits.push_back({{"range", range}, {"newText", *out}});
        }
        send_result(id, edits);
    }

    void open(const std::string& uri, std::string text) {
        docs_[uri] = Document{canonical(uri_to_path(uri)), std::move(text), nullptr};
        recheck();
    }

    void change(const std::string& uri, const json& changes) {
        auto it = docs_.find(uri);
        if (it == docs_.end()) return;  // a notification: no answer possible
        std::string& text = it->second.text;
        for (const json& c : changes) {
            if (!c.contains("range")) {
                text = c.at("text").get<std::string>();
                continue;
            }
            const json& r = c["range"];
            size_t b = offset_of(text, r.at("start").at("line"), r.at("start").at("character"));
            size_t e = offset_of(text, r.at("end").at("line"), r.at("end").at("character"));
            if (e < b) std::swap(b, e);
            text.replace(b, e - b, c.at("text").get<std::string>());
        }
        recheck();
    }

    // Compiles every open document (the buffers over the disk) and publishes the
    // diagnostics of every file involved; a file that had diagnostics and has none now
    // gets an empty list.
    void recheck() {
        sema::Overlay overlay;
        for (const auto& [uri, doc] : docs_) overlay[doc.path] = doc.text;
        std::map<std::string, json> by_uri;  // uri -> diagnostics
        std::map<std::string, std::set<std::string>> seen;
        for (auto& [uri, doc] : docs_) {
            by_uri.try_emplace(uri, json::array());
            auto shared = std::make_shared<Compilation>();
            Compilation& c = *shared;
            CompileOptions options;
            options.stdlib_dir = stdlib_;
            options.require_plant = false;  // as `plant check`
            options.overlay = &overlay;
            compile_file(doc.path, options, c);
            std::map<int32_t, std::string> file_uri;
            for (const auto& m : c.program.modules) file_uri[m.ast.file] = path_to_uri(m.key);
            for (const auto& [file, u] : file_uri) by_uri.try_emplace(u, json::array());
            bool syntax_ok = !c.program.modules.empty();
            for (const Diagnostic& d : c.sink.all())
                if (d.id == DiagId::Syntax) syntax_ok = false;
            if (syntax_ok || !doc.parsed) doc.parsed = shared;
            for (const Diagnostic& d : c.sink.sorted()) {
                std::string target = uri;
                json range = zero_range();
                if (auto f = file_uri.find(d.span.file); f != file_uri.end()) {
                    target = f->second;
                    range = range_of(c.sources, d.span);
                }
                json item = {{"range", range},
                             {"severity", d.severity == Severity::Error ? 1 : d.severity == Severity::Warning ? 2 : 3},
                             {"code", std::string(info(d.id).code)},
                             {"source", "plant"},
                             {"message", d.message}};
                json related = json::array();
                for (const Note& n : d.notes) {
                    const Span& s = file_uri.count(n.span.file) ? n.span : d.span;
                    if (!file_uri.count(s.file)) continue;
                    related.push_back({{"location", {{"uri", file_uri[s.file]}, {"range", range_of(c.sources, s)}}},
                                       {"message", n.message}});
                }
                if (!related.empty()) item["relatedInformation"] = related;
                // The same error in an imported file shows once, whichever open file reached it.
                if (!seen[target].insert(item.dump()).second) continue;
                by_uri[target].push_back(std::move(item));
            }
        }
        for (const std::string& uri : published_)
            by_uri.try_emplace(uri, json::array());
        published_.clear();
        for (auto& [uri, list] : by_uri) {
            if (!list.empty()) published_.insert(uri);
            send_notification("textDocument/publishDiagnostics", {{"uri", uri}, {"diagnostics", list}});
        }
    }

    // --- Features on the last parsed AST ------------------------------------------------

    static bool inside(const Span& s, size_t offset) { return s.valid() && s.begin <= offset && offset <= s.end; }

    static const sema::LoadedModule* module_of(const Document& doc) {
        if (!doc.parsed) return nullptr;
        for (const auto& m : doc.parsed->program.modules)
            if (m.key == doc.path) return &m;
        return nullptr;
    }

    static json location(const Compilation& c, const Span& s) {
        for (const auto& m : c.program.modules)
            if (m.ast.file == s.file) return {{"uri", path_to_uri(m.key)}, {"range", range_of(c.sources, s)}};
        return nullptr;
    }

    static const ast::ObjectDecl* find_type(const Compilation& c, const std::string& name) {
        for (const auto& m : c.program.modules)
            for (const auto& o : m.ast.objects)
                if (o.name.text == name) return &o;
        return nullptr;
    }

    struct Members {
        std::vector<const ast::InstanceDecl*> instances;
        std::vector<const ast::PortDecl*> ports;
        std::vector<const ast::ComponentDecl*> components;
    };
    static void collect(const std::vector<ast::Member>& members, Members& out) {
        for (const auto& m : members) {
            if (auto* i = std::get_if<ast::InstanceDecl>(&m)) out.instances.push_back(i);
            else if (auto* p = std::get_if<ast::PortDecl>(&m)) out.ports.push_back(p);
            else if (auto* k = std::get_if<ast::ComponentDecl>(&m)) out.components.push_back(k);
            else if (auto* f = std::get_if<std::unique_ptr<ast::ForDecl>>(&m)) collect((*f)->body, out);
            else if (auto* c = std::get_if<std::unique_ptr<ast::IfDecl>>(&m)) {
                collect((*c)->then_body, out);
                collect((*c)->else_body, out);
            }
        }
    }
    static Members members_of(const ast::ObjectDecl& o) {
        Members out;
        collect(o.members, out);
        return out;
    }

    static std::string slice(const Compilation& c, const Span& s) {
        if (!s.valid()) return "";
        const std::string& t = c.sources.text(s.file);
        return t.substr(s.begin, std::min<size_t>(s.end, t.size()) - std::min<size_t>(s.begin, t.size()));
    }

    // The `///` lines right above a declaration, without the slashes.
    static std::string doc_comment(const Compilation& c, const Span& s) {
        const std::string& t = c.sources.text(s.file);
        size_t line_begin = t.rfind('\n', s.begin == 0 ? 0 : s.begin - 1);
        std::vector<std::string> lines;
        while (line_begin != std::string::npos && line_begin > 0) {
            size_t prev = t.rfind('\n', line_begin - 1);
            size_t from = prev == std::string::npos ? 0 : prev + 1;
            std::string line = t.substr(from, line_begin - from);
            size_t first = line.find_first_not_of(" \t");
            if (first == std::string::npos || line.compare(first, 3, "///") != 0) break;
            std::string body = line.substr(first + 3);
            if (!body.empty() && body[0] == ' ') body.erase(0, 1);
            lines.insert(lines.begin(), body);
            if (prev == std::string::npos) break;
            line_begin = prev;
        }
        std::string out;
        for (const auto& l : lines) out += l + "\n";
        return out;
    }

    static std::string signature(const Compilation& c, const ast::ObjectDecl& o) {
        std::string sig = (o.is_plant ? "plant " : "object ") + o.name.text;
        if (!o.params.empty()) {
            sig += "(";
            for (size_t i = 0; i < o.params.size(); ++i) {
                const auto& p = o.params[i];
                sig += (i ? ", " : "") + p.name.text + ": " + p.type.text;
                if (p.default_value) sig += " = " + slice(c, p.default_value->span);
            }
            sig += ")";
        }
        return sig;
    }

    static json markdown(const std::string& code, const std::string& text) {
        return {{"contents", {{"kind", "markdown"}, {"value", "```plant\n" + code + "\n```" + (text.empty() ? "" : "\n\n" + text)}}}};
    }

    json definition(const Document& doc, size_t offset) {
        const sema::LoadedModule* m = module_of(doc);
        if (!m) return nullptr;
        const Compilation& c = *doc.parsed;
        for (const auto& imp : m->ast.imports) {
            if (!inside(imp.span, offset)) continue;
            std::string rel = imp.module;
            for (auto& ch : rel)
                if (ch == '.') ch = '/';
            rel += ".plant";
            fs::path file = imp.module.rfind("std.", 0) == 0 ? fs::path(stdlib_) / rel.substr(4)
                                                             : fs::path(doc.path).parent_path() / rel;
            return {{"uri", path_to_uri(canonical(file.string()))}, {"range", zero_range()}};
        }
        for (const auto& o : m->ast.objects) {
            for (const ast::InstanceDecl* i : members_of(o).instances) {
                if (!inside(i->type.span, offset) && !inside(i->name.span, offset)) continue;
                if (const ast::ObjectDecl* t = find_type(c, i->type.text)) return location(c, t->name.span);
            }
        }
        return nullptr;
    }

    // The uses of the name at `offset` in every open document's import closure (so a type
    // of an open stdlib file is also found in an open plant that imports it).
    json references(const Document& doc, size_t offset, bool include_declaration) const {
        json locations = json::array();
        const sema::LoadedModule* m = module_of(doc);
        if (!m) return locations;
        const std::optional<Target> target = target_at(*doc.parsed, *m, offset);
        if (!target) return locations;
        add_references(*doc.parsed, *target, include_declaration, locations);
        for (const auto& [uri, other] : docs_)
            if (other.parsed && &other != &doc) add_references(*other.parsed, *target, include_declaration, locations);
        return locations;
    }

    json hover(const Document& doc, size_t offset) {
        const sema::LoadedModule* m = module_of(doc);
        if (!m) return nullptr;
        const Compilation& c = *doc.parsed;
        for (const auto& o : m->ast.objects) {
            const Members mine = members_of(o);
            for (const ast::InstanceDecl* i : mine.instances) {
                const ast::ObjectDecl* t = find_type(c, i->type.text);
                if (!t) continue;
                if (inside(i->type.span, offset) || inside(i->name.span, offset))
                    return markdown(signature(c, *t), doc_comment(c, t->span));
                for (const ast::Arg& a : i->args) {
                    if (!a.name || !inside(a.name->span, offset)) continue;
                    for (const ast::Param& p : t->params) {
                        if (p.name.text != a.name->text) continue;
                        std::string text = "parameter of " + t->name.text;
                        if (auto dim = units::dim_of_type(p.type.text)) text += "; unit: " + units::si_unit(*dim);
                        if (p.default_value) text += "; default: " + slice(c, p.default_value->span);
                        return markdown(p.name.text + ": " + p.type.text, text);
                    }
                }
            }
            for (const ast::PortDecl* p : mine.ports)
                if (inside(p->name.span, offset))
                    return markdown((p->is_input ? "in " : "out ") + p->name.text + ": " + p->type.text,
                                    p->is_input ? "input port" : "output port");
            for (const ast::Param& p : o.params) {
                if (!inside(p.name.span, offset)) continue;
                std::string text = "parameter of " + o.name.text;
                if (auto dim = units::dim_of_type(p.type.text)) text += "; unit: " + units::si_unit(*dim);
                if (p.default_value) text += "; default: " + slice(c, p.default_value->span);
                return markdown(p.name.text + ": " + p.type.text, text);
            }
            if (inside(o.name.span, offset)) return markdown(signature(c, o), doc_comment(c, o.span));
        }
        return nullptr;
    }

    json completion(const Document& doc, size_t offset) {
        json items = json::array();
        const std::string& t = doc.text;
        auto ident = [](char ch) { return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'; };
        size_t start = std::min(offset, t.size());
        while (start > 0 && ident(t[start - 1])) --start;
        const size_t line_begin = start == 0 ? 0 : t.rfind('\n', start - 1) + 1;  // npos + 1 == 0
        const std::string before = t.substr(line_begin, start - line_begin);
        const sema::LoadedModule* m = module_of(doc);
        if (start > 0 && t[start - 1] == '.') {
            size_t name_end = start - 1, name_begin = name_end;
            while (name_begin > 0 && ident(t[name_begin - 1])) --name_begin;
            const std::string name = t.substr(name_begin, name_end - name_begin);
            if (before.find("import") != std::string::npos || !m) return items;
            const Compilation& c = *doc.parsed;
            for (const auto& o : m->ast.objects) {
                for (const ast::InstanceDecl* i : members_of(o).instances) {
                    if (i->name.text != name) continue;
                    const ast::ObjectDecl* type = find_type(c, i->type.text);
                    if (!type) continue;
                    const Members ms = members_of(*type);
                    for (const ast::PortDecl* p : ms.ports)
                        items.push_back({{"label", p->name.text}, {"kind", 5},
                                         {"detail", (p->is_input ? "in " : "out ") + p->type.text}});
                    for (const ast::InstanceDecl* x : ms.instances)
                        items.push_back({{"label", x->name.text}, {"kind", 6}, {"detail", x->type.text}});
                    for (const ast::ComponentDecl* x : ms.components)
                        if (!x->name.text.empty())
                            items.push_back({{"label", x->name.text}, {"kind", 10}, {"detail", x->kind.text}});
                    return items;
                }
            }
            return items;
        }
        const size_t first = before.find_first_not_of(" \t");
        if (first != std::string::npos && before.compare(first, 6, "import") == 0) {
            std::error_code ec;
            std::vector<std::string> names;
            for (const auto& e : fs::directory_iterator(stdlib_, ec))
                if (e.path().extension() == ".plant") names.push_back("std." + e.path().stem().string());
            std::sort(names.begin(), names.end());
            for (const auto& n : names) items.push_back({{"label", n}, {"kind", 9}});
            return items;
        }
        size_t k = before.size();
        while (k > 0 && before[k - 1] == ' ') --k;
        if (k > 0 && std::isdigit(static_cast<unsigned char>(before[k - 1]))) {
            for (const auto& u : units::unit_atoms()) items.push_back({{"label", u}, {"kind", 11}});
            return items;
        }
        if (doc.parsed)
            for (const auto& mod : doc.parsed->program.modules)
                for (const auto& o : mod.ast.objects)
                    if (!o.is_plant) items.push_back({{"label", o.name.text}, {"kind", 7}, {"detail", signature(*doc.parsed, o)}});
        return items;
    }

    void send(const json& msg) {
        const std::string body = msg.dump();
        out_ << "Content-Length: " << body.size() << "\r\n\r\n" << body;
        out_.flush();
    }
    void send_result(const json& id, const json& result) {
        send({{"jsonrpc", "2.0"}, {"id", id}, {"result", result}});
    }
    void send_error(const json& id, int code, const std::string& message) {
        send({{"jsonrpc", "2.0"}, {"id", id}, {"error", {{"code", code}, {"message", message}}}});
    }
    void send_notification(const std::string& method, const json& params) {
        send({{"jsonrpc", "2.0"}, {"method", method}, {"params", params}});
    }

    std::ostream& out_;
    std::string stdlib_;
    bool initialized_ = false;
    bool shutdown_ = false;
    std::map<std::string, Document> docs_;  // by URI
    std::set<std::string> published_;       // URIs whose last list was not empty
};

// Reads one framed message body; false at the end of the input.
bool read_message(std::istream& in, std::string& body, bool& framing_ok) {
    framing_ok = true;
    long long length = -1;
    std::string line;
    bool any = false;
    while (std::getline(in, line)) {
        any = true;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty()) break;
        const std::string key = "content-length:";
        std::string lower = line.substr(0, key.size());
        for (auto& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
        if (lower == key) {
            try {
                length = std::stoll(line.substr(key.size()));
            } catch (...) {
                length = -1;
            }
        }
    }
    if (!any || !in) return false;
    if (length < 0 || length > (1LL << 28)) {
        framing_ok = false;
        return true;
    }
    body.assign(static_cast<size_t>(length), '\0');
    in.read(body.data(), length);
    return static_cast<long long>(in.gcount()) == length;
}

}  // namespace

int serve(std::istream& in, std::ostream& out, const std::string& stdlib_dir) {
    Server server(out, stdlib_dir);
    std::string body;
    bool framing_ok = true;
    while (read_message(in, body, framing_ok)) {
        if (!framing_ok) continue;  // a header block without a usable Content-Length: no message to answer
        if (!server.handle(body)) return server.shut_down() ? 0 : 1;
    }
    return server.shut_down() ? 0 : 1;
}

}  // namespace plant::lsp
