// The graphics' row of the kind table (graph/plugin.h): what the compiler, the loader, the
// language server and the docs know of it.
#include "graph/kinds.h"
#include "graph/plugin.h"

#include <fmt/format.h>

namespace plant::kinds::graphics {

using namespace plant::graph;

namespace {

constexpr SlotSpec kSlots[] = {PLANT_SLOTS_GRAPHICS(PLANT_SLOT_SPEC)};
constexpr ParamSpec kParams[] = {
    {"model", ParamType::String, "", false, 0, "model reference the viewer interprets (never loaded by the runtime)"},
    {"show", ParamType::String, "", false, 0, "the variant shown at start; the model itself when absent"},
};

// Its parent comes before it (the runtime poses parents first); its initial variant is one
// of its own. Its animations and variants are checked as rows of their tables (validate.cpp).
bool check(const Graph& g, int32_t row, PluginProblem& problem) {
    const Graphics& gr = g.graphics[GraphicsId(row)];
    if (!(gr.parent.v < row)) problem.message = "field 'parent' must name an earlier graphics (or be -1)";
    else if (gr.variant < -1 || gr.variant >= gr.variant_num)
        problem.message = fmt::format("field 'variant' = {} is not -1 or the index of one of its {} variants",
                                      gr.variant, gr.variant_num);
    return problem.message.empty();
}

}  // namespace

constexpr KindDesc desc{
    .word = "graphics",
    .doc = "what the viewer draws: a model, its animations and variants, child graphics",
    .slots = kSlots,
    .params = kParams,
    .check = check,
    .placed = true,  // its pose at the start (relative to the body it is `on`, or its parent)
    .kind = CompKind::Graphics,
    .on = true,
    .blocks = kAnimations | kVariants | kChildren,  // child graphics
    PLANT_KIND_TABLE(graphics),
};

}  // namespace plant::kinds::graphics
