// `plant lsp [--stdlib DIR]`: the command line of the language server. Its own arguments
// are read here, like `plant fmt`'s and `plant sweep`'s, so `--help` and a wrong flag are
// answered on the terminal instead of starting a server that waits for a client.
#include "lsp/lsp.h"

#include <istream>
#include <ostream>

namespace plant::lsp {

namespace {

constexpr const char* kLspHelp = R"(usage: plant lsp [--stdlib DIR]

A language server (the Language Server Protocol, JSON-RPC over stdin and stdout) for
editors: diagnostics as you type, hover, go to definition, completion, the outline, find
references and formatting. An editor starts it; it is not run by hand. Setting it up in
VS Code, Neovim, Emacs and Helix: docs/editors.md.

  --stdlib DIR  where `import std.x` looks (default: $PLANT_STDLIB or the bundled stdlib)
Exit code: 0 after the client's `shutdown` and `exit`, 1 when the input ends without
them, 2 bad usage.
)";

int usage(std::ostream& err, const std::string& message) {
    err << "plant lsp: error: " << message << "\n(see `plant lsp --help`)\n";
    return 2;
}

}  // namespace

int lsp_main(const std::vector<std::string>& args, std::istream& in, std::ostream& out, std::ostream& err,
             const std::string& default_stdlib) {
    std::string stdlib = default_stdlib;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "-h" || a == "--help") return out << kLspHelp, 0;
        if (a == "--stdlib") {
            if (i + 1 >= args.size()) return usage(err, "--stdlib needs a DIR");
            stdlib = args[++i];
        } else if (a.rfind("--stdlib=", 0) == 0) {
            stdlib = a.substr(9);
        } else if (a == "--stdio") {
            // What VS Code's client and others add to say the transport: stdio is the only one.
        } else {
            return usage(err, "unexpected argument '" + a + "'");
        }
    }
    if (stdlib.empty()) return usage(err, "--stdlib needs a DIR");
    return serve(in, out, stdlib);
}

}  // namespace plant::lsp
