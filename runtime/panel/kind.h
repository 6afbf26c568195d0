// Operator panels (docs/language.md, "panel"): a `panel` component holds the elements an
// operator works a line with, each a component of its own kind with ordinary slots:
//
//   panel ops {
//       title = "Line 1"
//       button start { label = "Start"; color = "green" }
//       estop halt { label = "Emergency stop" }
//       selector mode { label = "Mode"; positions = 2; names = "Manual/Auto"; initial = 1 }
//       lamp running { label = "Running"; color = "green" }
//       display count { label = "Bottles" }
//   }
//
// Buttons, selectors and the emergency stop are worked through their inputs (`press`,
// `release`, `hold`, `turn`, `reset`), which the page, `--event`, an events file and a PLC
// coil reach the one way in (engine::apply_event); what they do is on their outputs
// (`pressed`, `down`, `position`, `engaged`, ...), which flows, connectors and nets read.
// Lamps and displays take inputs and show them on outputs (`state`, `value`) that the page
// and a PLC read. Each element's behaviour runs in phase 5, so an operator's press is seen
// by the logic phase of the step after the one the event arrived in, like any actuator.
#pragma once

namespace plant::panel {

// Registers `panel` and its element kinds (button, estop, selector, lamp, display) once
// per process; every program that compiles or runs plants with panels calls it first.
void register_panel_kinds();

}  // namespace plant::panel
