#include "sema/names.h"

#include "sema/elaborator.h"

namespace plant::sema {

void Names::add(Span use, Span decl, const std::string& slot, bool declaration) {
    if (!use.valid() || !decl.valid()) return;
    // A loop's body, an object's every instance: each use recorded once.
    if (!seen_.emplace(use.file, use.begin, use.end, decl.file, decl.begin, slot, declaration).second) return;
    all_.push_back({use, decl, slot, declaration});
}

void survey_names(const Program& prog, const SourceMap& sources, Names& out, long long max_members) {
    // Dependents first (the root's plant, then what it uses): a type already elaborated
    // inside another, in the same survey, has had its names read.
    std::set<const ast::ObjectDecl*> surveyed;
    for (size_t m = prog.modules.size(); m-- > 0;)
        for (const auto& o : prog.modules[m].ast->objects) {
            if (surveyed.count(&o)) continue;
            Sink dropped;
            Elaborator one(prog, sources, dropped);
            one.max_expanded_ = max_members;
            one.record_names(&out, true, &surveyed);
            one.check_object(o, static_cast<int>(m));
        }
}

}  // namespace plant::sema
