#include "lsp/lsp.h"
#include "lsp/lookup.h"
#include "lsp/protocol.h"
#include "lsp/repair.h"
#include "lsp/symbols.h"

#include "compiler.h"
#include "graph/utf8.h"
#include "fmt/formatter.h"
#include "units/units.h"

#include <fmt/format.h>
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
        // LSP messages are UTF-8: a document in another encoding is named as such.
        if (const size_t bad = graph::invalid_utf8(body); bad != std::string::npos) {
            send_error(nullptr, kParseError,
                       fmt::format("the message is not valid UTF-8: byte 0x{:02X} at offset {} (LSP messages and the documents in "
                                   "them are UTF-8; save the file as UTF-8)",
                                   unsigned(static_cast<unsigned char>(body[bad])), bad));
            return true;
        }
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
            else if (method == "textDocument/hover") {
                const sema::LoadedModule* m = module_of(doc);
                send_result(id, m ? hover(*doc.parsed, *m, offset) : json());
            } else {
                send_result(id, completion(doc.parsed.get(), module_of(doc), doc.text, offset, stdlib_));
            }
        } else if (is_request) {
            send_error(id, kMethodNotFound, "unknown method '" + method + "'");
        }
        // Unknown notifications ($/cancelRequest, workspace/didChangeConfiguration, ...) are ignored.
    }

    struct Document {
        std::string path;  // canonical
        std::string text;
        // What hover, definition, completion, the outline and references read: the last
        // compilation of this document's text; with a syntax error, of the text with the
        // broken lines blanked (lsp/repair.h), so the rest of the file answers at the
        // buffer's positions; else the last version that parsed.
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
            // The modules whose text did not change since this document's last check are
            // not parsed again (most of the time: all but the edited file).
            if (doc.parsed) options.reuse = {&doc.parsed->program, &doc.parsed->sources};
            compile_file(doc.path, options, c);
            std::map<int32_t, std::string> file_uri;
            for (const auto& m : c.program.modules) file_uri[m.ast->file] = path_to_uri(m.key);
            for (const auto& [file, u] : file_uri) by_uri.try_emplace(u, json::array());
            std::shared_ptr<Compilation> read =
                !syntax_error_in(c, doc.path) ? shared : parse_repaired(doc.path, doc.text, stdlib_, overlay, c);
            if (!read && !doc.parsed) read = shared;
            if (read) {  // the names in it, as sema resolves them (lsp/symbols.h reads them)
                sema::survey_names(read->program, read->sources, read->names, sema::kMaxMembers);
                doc.parsed = read;
            }
            for (const Diagnostic& d : c.sink.sorted()) {
                std::string target = uri;
                json range = zero_range();
                if (auto f = file_uri.find(d.span.file); f != file_uri.end()) {
                    target = f->second;
                    range = range_of(c.sources, d.span);
                }
                // A note without a place of its own ("did you mean 'tick'?") is part of the
                // message: clients that show no related information (Neovim 0.7) show it too.
                std::string message = d.message;
                json related = json::array();
                for (const Note& n : d.notes) {
                    const bool own_place = n.span.valid() && !(n.span.file == d.span.file && n.span.begin == d.span.begin &&
                                                                n.span.end == d.span.end);
                    if (!own_place || !file_uri.count(n.span.file)) {
                        message += "; " + n.message;
                        continue;
                    }
                    related.push_back({{"location", {{"uri", file_uri[n.span.file]}, {"range", range_of(c.sources, n.span)}}},
                                       {"message", n.message}});
                }
                json item = {{"range", range},
                             {"severity", d.severity == Severity::Error ? 1 : d.severity == Severity::Warning ? 2 : 3},
                             {"code", std::string(info(d.id).code)},
                             {"source", "plant"},
                             {"message", message}};
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

    // --- Features on the last parse ------------------------------------------------

    static const sema::LoadedModule* module_of(const Document& doc) {
        if (!doc.parsed) return nullptr;
        for (const auto& m : doc.parsed->program.modules)
            if (m.key == doc.path) return &m;
        return nullptr;
    }

    json definition(const Document& doc, size_t offset) {
        const sema::LoadedModule* m = module_of(doc);
        if (!m) return nullptr;
        const Compilation& c = *doc.parsed;
        for (const auto& imp : m->ast->imports) {
            if (!inside(imp.span, offset)) continue;
            std::string rel = imp.module;
            for (auto& ch : rel)
                if (ch == '.') ch = '/';
            rel += ".plant";
            fs::path file = imp.module.rfind("std.", 0) == 0 ? fs::path(stdlib_) / rel.substr(4)
                                                             : fs::path(doc.path).parent_path() / rel;
            return {{"uri", path_to_uri(canonical(file.string()))}, {"range", zero_range()}};
        }
        // An instance's name: its type.
        for (const auto& o : m->ast->objects)
            for (const ast::InstanceDecl* i : members_of(o).instances)
                if (inside(i->name.span, offset)) offset = i->type.span.begin;
        // A type's, a path's segment, a named argument, a parameter's, `let`'s or loop variable's use.
        if (const std::optional<Target> t = target_at(c, *m, offset)) return declaration_of(c, *t);
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
