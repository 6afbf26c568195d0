// Operator panels on the page (docs/viewer.md, "Panels"): what the scene says of each panel
// and its elements, and the numbers a status gives them. The page works an element by an
// ordinary `event` message on its input (`line[0].ops.start.press`), the one way in.
#pragma once

#include "engine/engine.h"
#include "graph/graph.h"

#include <nlohmann/json_fwd.hpp>

namespace plant::view {

// [{path, title, pose, elements: [{name, kind, path, label, color, positions, names, unit,
// digits}]}], in component order: every `panel` and the elements it holds; `pose` (px py pz
// qx qy qz qw, world) only for a panel placed in the scene.
nlohmann::json panels_json(const graph::Graph& g);
// One number per element, in the order panels_json lists them: a button's `down`, an
// emergency stop's `engaged`, a selector's `position`, a lamp's `state` (0 off, 1 on, 2
// blinking), a display's `value`.
nlohmann::json panel_values(const engine::Engine& e);

}  // namespace plant::view
