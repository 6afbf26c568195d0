// Checks a spec against its plant before any run: the plant compiles, every varied name is
// one of its parameters, every value compiles as that parameter (type and unit, exactly as
// `--set` checks it), every record an output names exists.
#include "compiler.h"
#include "sweep.h"

#include <set>

namespace plant::sweep {

namespace {

// The first error of a compilation, as one line (its message, without the caret).
std::string first_error(const Compilation& c) {
    for (const Diagnostic& d : c.sink.sorted())
        if (d.severity == Severity::Error) return std::string(info(d.id).code) + ": " + d.message;
    return "does not compile";
}

bool compile_with(const Spec& spec, const std::string& stdlib, std::vector<std::string> sets, Compilation& c) {
    CompileOptions o;
    o.stdlib_dir = stdlib.empty() ? default_stdlib_dir() : stdlib;
    o.overrides = std::move(sets);
    compile_file(spec.plant, o, c);
    return c.ok();
}

// An error in the value itself (its syntax, unit or type against the parameter's), found in
// the `--set` source. An error the value causes elsewhere in the plant (a pool of 0 bottles)
// belongs to its runs: they become rows with status compile_error.
bool value_error(const Compilation& c, std::string& message) {
    for (const Diagnostic& d : c.sink.sorted())
        if (d.severity == Severity::Error && d.span.valid() && c.sources.name(d.span.file) == "--set") {
            message = std::string(info(d.id).code) + ": " + d.message;
            return true;
        }
    return false;
}

}  // namespace

bool check_spec(const Spec& spec, const std::string& stdlib, std::vector<SpecError>& errors) {
    const size_t before = errors.size();
    Compilation base;
    if (!compile_with(spec, stdlib, {}, base)) {
        errors.push_back({spec.plant_loc, "the plant does not compile: " + first_error(base)});
        return false;
    }
    std::set<std::string> names;
    std::string list;
    const auto& p = base.program;
    if (p.root >= 0)
        for (const auto& obj : p.modules[size_t(p.root)].ast->objects)
            if (obj.is_plant)
                for (const auto& prm : obj.params) {
                    names.insert(prm.name.text);
                    list += (list.empty() ? "" : ", ") + prm.name.text;
                }
    for (const Param& prm : spec.params) {
        if (!names.count(prm.name)) {
            errors.push_back({prm.loc, "the plant has no parameter '" + prm.name + "' (its parameters: " +
                                           (list.empty() ? "none" : list) + ")"});
            continue;
        }
        std::set<std::string> seen;
        for (const Value& v : prm.values) {
            if (!seen.insert(v.text).second) continue;
            Compilation c;
            std::string message;
            if (!compile_with(spec, stdlib, {prm.name + "=" + v.text}, c) && value_error(c, message))
                errors.push_back({v.loc, prm.name + " = " + v.text + ": " + message});
        }
    }
    if (!spec.perturb.empty()) {
        const Param* varied = nullptr;
        for (const Param& prm : spec.params)
            if (prm.name == spec.perturb) varied = &prm;
        if (!varied) {
            errors.push_back({spec.perturb_loc, "replicates perturb '" + spec.perturb + "', which is not varied"});
        } else if (!varied->values.empty()) {
            const std::string v = "(" + varied->values[0].text + ") + 1 * (" + spec.perturb_by + ")";
            Compilation c;
            std::string message;
            if (!compile_with(spec, stdlib, {spec.perturb + "=" + v}, c) && value_error(c, message))
                errors.push_back({spec.perturb_by_loc, "by: " + spec.perturb_by + ": " + message});
        }
    }
    std::set<std::string> records;
    const auto& g = base.graph;
    for (const auto& rec : g.records) records.insert(std::string(g.str(rec.column)));
    for (const Output& o : spec.outputs)
        if (o.kind != Output::Counter && !records.count(o.name))
            errors.push_back({o.loc, "the plant records nothing as '" + o.name + "'"});
    return errors.size() == before;
}

}  // namespace plant::sweep
