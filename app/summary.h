// `plant run`'s summary of a run (engine::RunSummary): for people, or as JSON for programs
// (`--summary=json`; `plant sweep` reads it). The JSON's fields: docs/runtime.md, "The
// summary as JSON".
#pragma once

#include "engine/run.h"

#include <iosfwd>

namespace plant::app {

void write_summary_text(const engine::RunSummary& s, std::ostream& out);
void write_summary_json(const engine::RunSummary& s, std::ostream& out);

}  // namespace plant::app
