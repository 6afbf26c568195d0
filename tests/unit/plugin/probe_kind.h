// A second kind that exists only in the tests: a probe, brought in as a plugin to prove that
// a plugin's parameters take the whole property vocabulary, not only numbers and texts:
//
//   probe p { offset = (1 cm, 2 cm, 3 cm); names = ["a", "b"]; object = Bottle
//             watch = t; label = "front" }
//
// At the start it emits what it was given, read through PluginCtx's accessors: `z` the
// offset's z in m, `names` how many strings `names` holds, `chars`
// their characters and the label's, `watches_timer` whether `watch`
// names a timer (1) or another component (0), `typed` whether `object` was given and names
// the type `Bottle` (1).
#pragma once

namespace plant::test {

// Registers the kind once per process (both sides: descriptor and behaviour).
void register_probe_kind();

}  // namespace plant::test
