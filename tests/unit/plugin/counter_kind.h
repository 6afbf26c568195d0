// A component kind that exists only in the tests: a counter, brought in as a plugin
// (graph/plugin.h, engine/plugin.h) to prove that a kind is new files plus one
// registration line. `counter c { start = 2; limit = 5; idle_after = 1 s }`:
// `add` counts one up, `reset` goes back to `start`; `value` is the count, `reached`
// fires when it gets to `limit`, `idle` once when nothing was added for `idle_after`.
// Entries: `tap N => OUTPUT (weight = W)` adds W in every step the void output is active
// (N only names the tap); `notify N => INPUT` names inputs a controller outside the step
// would drive, as a PLC link does — the counter only lists them (a test of the compiler).
#pragma once

namespace plant::test {

// Registers the kind once per process (both sides: descriptor and behaviour).
void register_counter_kind();

}  // namespace plant::test
