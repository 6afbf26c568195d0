#pragma once
// Times printed for people — the run summary, event lines (the viewer's log, saved events
// files, --event echoed back) — sit on the step grid with a fixed number of decimals: the
// fewest that put a step's printed time within a quarter step of the step (3 at 150 Hz:
// 0.000, 0.007, 0.013, 0.020, ...; 4 at 600 Hz). A time read back (an events file, --event)
// is due in the step it was printed for: due() (events.h) gives an event half a unit of the
// last decimal of slack. A trace is data that tools difference and fit: its time column has
// three decimals more (within a two-thousandth of a step: 0.006667 at 150 Hz).

#include <string>

namespace plant::engine {

// The decimals of a time at step length `dt` (s): ceil(log10(2 / dt)), at least 1.
int time_decimals(double dt);
// The decimals of a trace's time column: time_decimals(dt) + 3.
int trace_time_decimals(double dt);
// `t` with time_decimals(dt) decimals ("4.593"), without a unit.
std::string time_text(double t, double dt);
// Half a unit of the last printed decimal (0.0005 s at 150 Hz).
double time_slack(double dt);

}  // namespace plant::engine
