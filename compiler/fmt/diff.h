// A unified diff of two texts (`plant fmt --check`): every difference, each with three
// lines of context, as `diff -u` and `git diff` print them, so `patch -p0` applies it.
#pragma once

#include <string>
#include <string_view>

namespace plant::formatter {

// Empty when the texts are equal. `name` goes on both the `---` and the `+++` line.
// A text that does not end in a line end gets `\ No newline at end of file`.
std::string unified_diff(std::string_view before, std::string_view after, std::string_view name, int context = 3);

}  // namespace plant::formatter
