// The component registry on the compiler side: which kind words exist, which modes and
// properties each accepts, with their value type and dimension. The slot tables live in
// graph/kinds.h, shared with the runtime.
#pragma once

#include "graph/graph.h"
#include "graph/plugin.h"
#include "units/units.h"

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace plant::sema {

// A property as the compiler checks it: a parameter of the kind, in the one vocabulary every
// kind's parameters are written in (graph::ParamSpec, graph/plugin.h), with the dimension its
// unit names, parsed once.
struct PropSpec {
    std::string_view name;
    graph::ParamType type;
    units::Dim dim;  // Number and Vec3: the dimension of the parameter's unit
    bool required;
    std::string_view doc;
};

struct KindSpec {
    std::string_view word;  // as written in plant files
    graph::CompKind kind;
    std::vector<std::string_view> modes;  // first is the default; empty: no mode
    std::vector<PropSpec> props;
    bool shapes = false, animations = false, variants = false, places = false, routes = false,
         children = false, on = false;
    std::string_view doc = {};  // one line: what the kind is (the language server's hover)
    const graph::KindDesc* plugin = nullptr;  // a plugin kind (graph/plugin.h): its descriptor
};

// The dimension a plugin parameter's unit names (dimensionless when it names none).
units::Dim param_dim(const graph::ParamSpec& p);

// The slots a component of this kind starts with: the fixed slots, or a plugin's.
std::span<const graph::SlotSpec> kind_slots(const KindSpec& k);

// A built-in kind, or a registered plugin kind (its properties are its parameters).
const KindSpec* find_kind(std::string_view word);
std::vector<std::string> kind_words();
const PropSpec* find_prop(const KindSpec& k, std::string_view name);

}  // namespace plant::sema
