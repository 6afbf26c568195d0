// `plant lsp [--stdlib DIR]`: the command line of the language server (compiler/lsp). A
// `--help` and a wrong flag are answered on the terminal instead of starting a server
// that waits for a client.
#include "app/cli.h"
#include "app/command.h"
#include "compiler.h"
#include "lsp/lsp.h"

#include <iostream>

namespace plant::lsp {

namespace {

constexpr const char* kAbout = R"(A language server (the Language Server Protocol, JSON-RPC over stdin and stdout) for
editors: diagnostics as you type, hover, go to definition, completion, the outline, find
references and formatting. An editor starts it; it is not run by hand. Setting it up in
VS Code, Neovim, Emacs and Helix: docs/editors.md.)";
constexpr const char* kFooter = R"(Exit code: 0 after the client's `shutdown` and `exit`, 1 when the input ends without
them, 2 bad usage.
)";

int lsp_command(const std::vector<std::string>& args) {
    app::Cli cli("lsp", "[--stdlib DIR]", kAbout, kFooter);
    std::string stdlib = default_stdlib_dir();
    bool stdio = false;  // what VS Code's client and others add to say the transport: stdio is the only one
    cli.value("--stdlib", stdlib, "where `import std.x` looks (default: $PLANT_STDLIB or the bundled stdlib)", "DIR",
              "a DIR");
    cli.flag("--stdio", stdio, "talk over stdin and stdout (the only way; editors say it)");
    std::vector<std::string> words;
    cli.positionals(words);
    if (const int code = cli.parse(args, std::cout, std::cerr); code >= 0) return code;
    if (!words.empty()) return cli.usage_error(std::cerr, "unexpected argument '" + words[0] + "'");
    if (stdlib.empty()) return cli.usage_error(std::cerr, "--stdlib needs a DIR");
    std::ios::sync_with_stdio(false);
    return serve(std::cin, std::cout, stdlib);
}

}  // namespace

}  // namespace plant::lsp

namespace plant::app {

extern const Command kLspCommand{"lsp", "a language server (LSP) on stdin/stdout for editors", lsp::lsp_command};

}  // namespace plant::app
