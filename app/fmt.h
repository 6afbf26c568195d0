// `plant fmt FILE... [--check] [--stdout]`: the command line of the formatter (compiler/fmt),
// the `fmt` row of the command table.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace plant::formatter {

// Exit code: 0 done (with --check: every file is formatted), 1 a file has syntax errors
// or cannot be read or written (with --check: or would change), 2 bad usage.
int fmt_main(const std::vector<std::string>& args, std::istream& in, std::ostream& out, std::ostream& err);

}  // namespace plant::formatter
