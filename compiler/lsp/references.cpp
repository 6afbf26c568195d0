// Find references, definition and the name under the cursor, read from the names sema
// resolved (sema/names.h): the language server resolves no name itself. A use and its
// declaration are matched by their Target: the declaration's module and offset, and the
// slot's dotted name for a slot of a component.
#include "lsp/protocol.h"
#include "lsp/symbols.h"

#include <map>
#include <set>
#include <utility>

namespace plant::lsp {
namespace {

using nlohmann::json;

// The module key of each source file of `c`.
std::map<int32_t, std::string> module_keys(const Compilation& c) {
    std::map<int32_t, std::string> keys;
    for (const auto& m : c.program.modules) keys[m.ast->file] = m.key;
    return keys;
}

// What `n` stands for; nullopt when its declaration lies outside the modules.
std::optional<Target> target_of(const std::map<int32_t, std::string>& keys, const sema::NameUse& n) {
    auto it = keys.find(n.decl.file);
    if (it == keys.end()) return std::nullopt;
    return Target{it->second, n.decl.begin, n.slot};
}

}  // namespace

std::optional<Target> target_at(const Compilation& c, const sema::LoadedModule& m, size_t offset) {
    const sema::NameUse* best = nullptr;
    for (const sema::NameUse& n : c.names.all())
        if (n.use.file == m.ast->file && n.use.begin <= offset && offset <= n.use.end &&
            (!best || n.use.end - n.use.begin < best->use.end - best->use.begin))
            best = &n;
    if (!best) return std::nullopt;
    return target_of(module_keys(c), *best);
}

void add_references(const Compilation& c, const Target& t, bool include_declaration, json& locations) {
    const auto keys = module_keys(c);
    std::set<std::string> have;
    for (const json& l : locations) have.insert(l.dump());
    for (const sema::NameUse& n : c.names.all()) {
        auto file = keys.find(n.use.file);
        if ((n.declaration && !include_declaration) || file == keys.end() || target_of(keys, n) != t) continue;
        json l = {{"uri", path_to_uri(file->second)}, {"range", range_of(c.sources, n.use)}};
        if (have.insert(l.dump()).second) locations.push_back(std::move(l));
    }
}

json declaration_of(const Compilation& c, const Target& t) {
    const auto keys = module_keys(c);
    // A place, transition, variant or child graphics is declared by name; a built-in slot
    // (`look.tick`) by its component.
    for (const Target& want : {t, Target{t.file, t.at, ""}})
        for (const sema::NameUse& n : c.names.all())
            if (n.declaration && keys.count(n.use.file) && target_of(keys, n) == want)
                return {{"uri", path_to_uri(keys.at(n.use.file))}, {"range", range_of(c.sources, n.use)}};
    return nullptr;
}

}  // namespace plant::lsp
