// The timer's part of the graph contract (docs/language.md, "timer"): its fixed slots and
// the fields of its graph record (a row of `timers`). The rest of the kind is in this
// folder: kind.cpp (its descriptor row), lower.cpp (the compiler's lowering) and run.cpp
// (its behaviour in the step). graph/graph.h and graph/kinds.h read this header through
// the generated kind list (kinds/list.h).
#pragma once

// clang-format off
#define PLANT_SLOTS_TIMER(S) \
    S(start, "start", Void, In, "starts (or restarts) the timer") \
    S(stop, "stop", Void, In, "stops the timer") \
    S(tick, "tick", Void, Out, "the period or delay elapsed") \
    S(elapsed, "elapsed", Real, Out, "seconds since start") \
    S(running, "running", Bool, Out, "whether the timer runs")

#define PLANT_FIELDS_TIMER(F)    \
    F(CompId, comp)             \
    F(double, period)            \
    F(bool, periodic)            \
    F(bool, autostart)
// clang-format on
