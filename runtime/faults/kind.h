// Faults scheduled in the plant file (docs/plc.md, "Faults from the plant file"): a
// component whose entries force slots at given times and release them, as an instructor
// sets them to train diagnosis.
//
//   faults drill {
//       open 20 s => line[0].s2.seen(until = 100 s)
//       stuck 30 s => line[0].b1.stop(value = true)
//       invert 40 s => line[0].s1.occupied
//       release 60 s => line[0].b1.stop
//   }
//
// The key is the time the force begins; the path any input or output (a port: every slot it
// forwards to). The kind has no behaviour in the step: each entry is a timed event
// (engine::plant_events), applied by engine::apply_event like `--event "20s force PATH
// open"` — the one way in, so a run with the component and a run of the same plant without
// it but with those --event lines give the same trace.
#pragma once

namespace plant::faults {

// Registers the kind once per process; every program that compiles or loads plants with
// scheduled faults calls it first.
void register_faults_kind();

}  // namespace plant::faults
