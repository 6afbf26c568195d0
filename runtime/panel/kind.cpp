#include "panel/kind.h"

#include "engine/plugin.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <string_view>

namespace plant::panel {
namespace {

using graph::Dir;
using graph::KindDesc;
using graph::ParamSpec;
using graph::ParamType;
using graph::PluginPhase;
using graph::SlotSpec;
using graph::SlotType;

// ---- the panel: a titled frame that holds the elements ----
constexpr std::array<std::string_view, 5> kElements = {"button", "estop", "selector", "lamp", "display"};
constexpr std::array kPanelParams = {
    ParamSpec{"title", ParamType::String, "", false, 0, "the panel's title on the page"},
};

// The colours a button's cap or a lamp's lens may have ("" : the page's default, grey for a
// button, green for a lamp).
constexpr std::array<std::string_view, 6> kColors = {"green", "red", "yellow", "white", "blue", "black"};

constexpr ParamSpec kLabel{"label", ParamType::String, "", false, 0, "what the panel prints under it (its name when empty)"};
constexpr ParamSpec kColor{"color", ParamType::String, "", false, 0, "green, red, yellow, white, blue or black"};

// ---- a push button: momentary, down while held ----
namespace button {
enum Slot : int { press, release, hold, pressed, released, down };
constexpr std::array kSlots = {
    SlotSpec{"press", SlotType::Void, Dir::In, "pushes the button down (the page's press, an event, a coil)"},
    SlotSpec{"release", SlotType::Void, Dir::In, "lets it come up"},
    SlotSpec{"hold", SlotType::Bool, Dir::In, "true pushes it down, false lets it up (a coil)"},
    SlotSpec{"pressed", SlotType::Void, Dir::Out, "it went down this step"},
    SlotSpec{"released", SlotType::Void, Dir::Out, "it came up this step"},
    SlotSpec{"down", SlotType::Bool, Dir::Out, "whether it is held down"},
};
constexpr std::array kParams = {kLabel, kColor};
}  // namespace button

// ---- an emergency stop: latches when struck, released by a reset ----
namespace estop {
enum Slot : int { press, reset, pressed, cleared, engaged, latched };
constexpr std::array kSlots = {
    SlotSpec{"press", SlotType::Void, Dir::In, "strikes the mushroom: it latches"},
    SlotSpec{"reset", SlotType::Void, Dir::In, "releases the latch (the reset key)"},
    SlotSpec{"pressed", SlotType::Void, Dir::Out, "it latched this step"},
    SlotSpec{"cleared", SlotType::Void, Dir::Out, "a reset released it this step"},
    SlotSpec{"engaged", SlotType::Bool, Dir::Out, "whether it is latched"},
    SlotSpec{"latched", SlotType::Void, Dir::Out, "active in every step it is latched (`not halt.latched` in a connector)"},
};
constexpr std::array kParams = {kLabel};
}  // namespace estop

// ---- a selector switch of 2 or 3 positions, numbered from 0 (the leftmost) ----
namespace selector {
enum Slot : int { turn, position, changed, to0, to1, to2, at0, at1, at2 };
constexpr std::array kSlots = {
    SlotSpec{"turn", SlotType::Int, Dir::In, "turns it to a position, 0 the leftmost; a number that is not one is ignored"},
    SlotSpec{"position", SlotType::Int, Dir::Out, "the position it is at (from the start: `initial`)"},
    SlotSpec{"changed", SlotType::Void, Dir::Out, "it was turned to another position this step"},
    SlotSpec{"to0", SlotType::Void, Dir::Out, "it was turned to position 0 this step"},
    SlotSpec{"to1", SlotType::Void, Dir::Out, "it was turned to position 1 this step"},
    SlotSpec{"to2", SlotType::Void, Dir::Out, "it was turned to position 2 this step (3 positions)"},
    SlotSpec{"at0", SlotType::Void, Dir::Out, "active in every step it is at position 0 (`not mode.at0` in a connector)"},
    SlotSpec{"at1", SlotType::Void, Dir::Out, "active in every step it is at position 1"},
    SlotSpec{"at2", SlotType::Void, Dir::Out, "active in every step it is at position 2"},
};
enum Param : int { label, positions, names, initial };
constexpr std::array kParams = {
    kLabel,
    ParamSpec{"positions", ParamType::Int, "", false, 2, "how many positions: 2 or 3"},
    ParamSpec{"names", ParamType::String, "", false, 0, "the positions' names, left to right, split by '/' (\"Manual/Auto\")"},
    ParamSpec{"initial", ParamType::Int, "", false, 0, "the position at the start"},
};
}  // namespace selector

// ---- a lamp: off, on or blinking ----
namespace lamp {
enum Slot : int { on, off, blink, set, lit, state };
constexpr double kOff = 0, kOn = 1, kBlinking = 2;  // what `state` shows
constexpr std::array kSlots = {
    SlotSpec{"on", SlotType::Void, Dir::In, "lights it steadily"},
    SlotSpec{"off", SlotType::Void, Dir::In, "puts it out"},
    SlotSpec{"blink", SlotType::Void, Dir::In, "makes it blink"},
    SlotSpec{"set", SlotType::Int, Dir::In, "0 off, 1 on, 2 blinking (a place's tokens); another number is ignored"},
    SlotSpec{"lit", SlotType::Bool, Dir::In, "true on, false off"},
    SlotSpec{"state", SlotType::Int, Dir::Out, "what it shows: 0 off, 1 on, 2 blinking"},
};
constexpr std::array kParams = {kLabel, kColor};
}  // namespace lamp

// ---- a numeric display ----
namespace display {
enum Slot : int { set, count, value };
constexpr std::array kSlots = {
    SlotSpec{"set", SlotType::Real, Dir::In, "shows a number"},
    SlotSpec{"count", SlotType::Int, Dir::In, "shows a whole number (a count)"},
    SlotSpec{"value", SlotType::Real, Dir::Out, "the number shown (0 at the start)"},
};
enum Param : int { label, unit, digits };
constexpr std::array kParams = {
    kLabel,
    ParamSpec{"unit", ParamType::String, "", false, 0, "printed after the number"},
    ParamSpec{"digits", ParamType::Int, "", false, 0, "decimals shown, 0 to 6"},
};
}  // namespace display

// ---- checks: the element inside a panel, its parameters in range ----
const graph::PluginParam& param(const graph::Graph& g, graph::PluginId plugin, int k) {
    return g.plugin_params[g.plugins[plugin].param_adr + k];
}

// An element's component is named PANEL.NAME, PANEL a panel of the same object (the
// compiler makes it so; a graph written by hand is checked here).
bool inside_panel(const graph::Graph& g, graph::PluginId plugin, std::string_view word, graph::PluginProblem& problem) {
    const graph::Comp& c = g.comps[g.plugins[plugin].comp];
    const std::string_view name = g.str(c.name);
    const size_t dot = name.rfind('.');
    auto is_panel = [&](graph::CompId k) {
        const graph::Comp& p = g.comps[k];
        if (p.owner != c.owner || g.str(p.name) != name.substr(0, dot)) return false;
        const graph::KindDesc* d = graph::plugin_of(g, k);
        return d && d->word == "panel";
    };
    if (dot != std::string_view::npos) {
        // The owner's components first (the validator has checked they are a range; the
        // compiler puts all of them there), then, found in none of them, every component (a
        // graph written by hand need not).
        const graph::Do& o = g.dos[c.owner];
        for (graph::CompId k : graph::children(o.comp_adr, o.comp_num))
            if (is_panel(k)) return true;
        for (graph::CompId k : graph::ids_of(g.comps))
            if (is_panel(k)) return true;
    }
    problem = {-1, fmt::format("a {} belongs inside a panel: '{}' is in none", word, name)};
    return false;
}

bool color_known(const graph::Graph& g, graph::PluginId plugin, int k, std::string_view word, graph::PluginProblem& problem) {
    const std::string_view color = g.str(param(g, plugin, k).text);
    if (color.empty()) return true;
    for (std::string_view c : kColors)
        if (c == color) return true;
    problem = {-1, fmt::format("a {} is green, red, yellow, white, blue or black, not '{}'", word, color)};
    return false;
}

bool check_button(const graph::Graph& g, graph::PluginId plugin, graph::PluginProblem& problem) {
    return inside_panel(g, plugin, "button", problem) && color_known(g, plugin, 1, "button", problem);
}
bool check_estop(const graph::Graph& g, graph::PluginId plugin, graph::PluginProblem& problem) {
    return inside_panel(g, plugin, "estop", problem);
}
bool check_lamp(const graph::Graph& g, graph::PluginId plugin, graph::PluginProblem& problem) {
    return inside_panel(g, plugin, "lamp", problem) && color_known(g, plugin, 1, "lamp", problem);
}

bool check_selector(const graph::Graph& g, graph::PluginId plugin, graph::PluginProblem& problem) {
    if (!inside_panel(g, plugin, "selector", problem)) return false;
    const double n = param(g, plugin, selector::positions).num;
    if (n != 2 && n != 3) {
        problem = {-1, fmt::format("a selector has 2 or 3 positions, not {}", n)};
        return false;
    }
    const std::string_view names = g.str(param(g, plugin, selector::names).text);
    if (!names.empty()) {
        const auto given = 1 + std::count(names.begin(), names.end(), '/');
        if (given != n) {
            problem = {-1, fmt::format("the selector's names \"{}\" name {} positions, but it has {}", names, given, n)};
            return false;
        }
    }
    const double at = param(g, plugin, selector::initial).num;
    if (at < 0 || at >= n || at != std::floor(at)) {
        problem = {-1, fmt::format("the selector's initial position is between 0 and {}, not {}", n - 1, at)};
        return false;
    }
    return true;
}

bool check_display(const graph::Graph& g, graph::PluginId plugin, graph::PluginProblem& problem) {
    if (!inside_panel(g, plugin, "display", problem)) return false;
    const double d = param(g, plugin, display::digits).num;
    if (d < 0 || d > 6 || d != std::floor(d)) {
        problem = {-1, fmt::format("a display shows 0 to 6 decimals, not {}", d)};
        return false;
    }
    return true;
}

// ---- behaviour: phase 5, when an input is active; one number of state each ----

// The button's state is whether it is down; press before release, so that a press and a
// release in one step (a click while paused) still give `pressed`.
void act_button(engine::PluginCtx& c) {
    auto s = c.state();
    auto go = [&](bool want) {
        if ((s[0] != 0) == want) return;
        s[0] = want ? 1 : 0;
        c.emit(want ? button::pressed : button::released, 0);
        c.emit(button::down, s[0]);
    };
    if (c.active(button::hold) && c.value(button::hold) != 0) go(true);
    if (c.active(button::press)) go(true);
    if (c.active(button::release)) go(false);
    if (c.active(button::hold) && c.value(button::hold) == 0) go(false);
}

void act_estop(engine::PluginCtx& c) {
    auto s = c.state();
    if (c.active(estop::reset) && s[0] != 0) {
        s[0] = 0;
        c.emit(estop::cleared, 0);
        c.emit(estop::engaged, 0);
    }
    if (c.active(estop::press) && s[0] == 0) {  // struck while being reset: it stays latched
        s[0] = 1;
        c.emit(estop::pressed, 0);
        c.emit(estop::engaged, 1);
    }
}

// Phase 2: seen by this step's logic, so a connector can hold a Start back.
void sense_estop(engine::PluginCtx& c) {
    if (c.state()[0] != 0) c.emit(estop::latched, 0);
}

void start_selector(engine::PluginCtx& c) {
    c.state()[0] = c.param(selector::initial);
    c.emit(selector::position, c.state()[0]);
}

void act_selector(engine::PluginCtx& c) {
    auto s = c.state();
    const double to = c.value(selector::turn);
    if (!c.active(selector::turn) || to == s[0] || to < 0 || to >= c.param(selector::positions) || to != std::floor(to))
        return;
    s[0] = to;
    c.emit(selector::position, to);
    c.emit(selector::changed, 0);
    c.emit(selector::to0 + int(to), 0);
}

// Phase 2: the position as activity, seen by this step's logic.
void sense_selector(engine::PluginCtx& c) { c.emit(selector::at0 + int(c.state()[0]), 0); }

// The last active input in this order decides: set, lit, off, on, blink.
void act_lamp(engine::PluginCtx& c) {
    auto s = c.state();
    double shown = s[0];
    if (c.active(lamp::set)) {
        const double v = c.value(lamp::set);
        if (v == lamp::kOff || v == lamp::kOn || v == lamp::kBlinking) shown = v;
    }
    if (c.active(lamp::lit)) shown = c.value(lamp::lit) != 0 ? lamp::kOn : lamp::kOff;
    if (c.active(lamp::off)) shown = lamp::kOff;
    if (c.active(lamp::on)) shown = lamp::kOn;
    if (c.active(lamp::blink)) shown = lamp::kBlinking;
    if (shown == s[0]) return;
    s[0] = shown;
    c.emit(lamp::state, shown);
}

void act_display(engine::PluginCtx& c) {
    auto s = c.state();
    if (c.active(display::set)) s[0] = c.value(display::set);
    if (c.active(display::count)) s[0] = c.value(display::count);
    c.emit(display::value, s[0]);
}

constexpr KindDesc kPanel{"panel",   "an operator panel: buttons, selectors, an emergency stop, lamps, displays",
                          {},        kPanelParams,
                          {},        PluginPhase::None,
                          PluginPhase::None, nullptr,
                          kElements, {},
                          true};  // placed: drawn in the scene as well as on the page
constexpr KindDesc kButton{"button", "a push button of a panel: down while held",
                           button::kSlots, button::kParams, {}, PluginPhase::None, PluginPhase::Actuators,
                           graph::plugin_check<check_button>, {}, "panel"};
constexpr KindDesc kEstop{"estop", "an emergency stop of a panel: latches when struck, released by a reset",
                          estop::kSlots, estop::kParams, {}, PluginPhase::Sensors, PluginPhase::Actuators,
                          graph::plugin_check<check_estop>, {}, "panel"};
constexpr KindDesc kSelector{"selector", "a selector switch of a panel: 2 or 3 positions",
                             selector::kSlots, selector::kParams, {}, PluginPhase::Sensors, PluginPhase::Actuators,
                             graph::plugin_check<check_selector>, {}, "panel"};
constexpr KindDesc kLamp{"lamp", "a lamp of a panel: off, on or blinking",
                         lamp::kSlots, lamp::kParams, {}, PluginPhase::None, PluginPhase::Actuators,
                         graph::plugin_check<check_lamp>, {}, "panel"};
constexpr KindDesc kDisplay{"display", "a numeric display of a panel",
                            display::kSlots, display::kParams, {}, PluginPhase::None, PluginPhase::Actuators,
                            graph::plugin_check<check_display>, {}, "panel"};

}  // namespace

void register_panel_kinds() {
    static constexpr engine::KindBehaviour kPanelRun{0, nullptr, nullptr, nullptr, nullptr};
    static constexpr engine::KindBehaviour kButtonRun{1, nullptr, nullptr, act_button, nullptr};
    static constexpr engine::KindBehaviour kEstopRun{1, nullptr, sense_estop, act_estop, nullptr};
    static constexpr engine::KindBehaviour kSelectorRun{1, start_selector, sense_selector, act_selector, nullptr};
    static constexpr engine::KindBehaviour kLampRun{1, nullptr, nullptr, act_lamp, nullptr};
    static constexpr engine::KindBehaviour kDisplayRun{1, nullptr, nullptr, act_display, nullptr};
    static const bool registered =
        engine::register_plugin(kPanel, kPanelRun) && engine::register_plugin(kButton, kButtonRun) &&
        engine::register_plugin(kEstop, kEstopRun) && engine::register_plugin(kSelector, kSelectorRun) &&
        engine::register_plugin(kLamp, kLampRun) && engine::register_plugin(kDisplay, kDisplayRun);
    if (!registered) std::abort();  // only other kinds with these words could refuse them
}

}  // namespace plant::panel
