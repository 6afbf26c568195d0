// Tokens with layout marks for the formatter. Compiled as C++17 with the builder (ANTLR).
#include "parse/layout.h"
#include "parse/offsets.h"
#include "parse/parser.h"

#include "PlantLexer.h"
#include "PlantParser.h"
#include "antlr4-runtime.h"

#include <map>

namespace plant::parse {
namespace {

using P = plant_antlr::PlantParser;

// Walks the parse tree once and records the marks by token index.
class Marker {
public:
    std::map<size_t, Starts> starts;
    std::vector<size_t> prefix, glued;

    void walk(antlr4::tree::ParseTree* node) {
        if (auto* term = dynamic_cast<antlr4::tree::TerminalNode*>(node)) {
            terminal(term);
            return;
        }
        auto* ctx = dynamic_cast<antlr4::ParserRuleContext*>(node);
        if (!ctx || !ctx->getStart()) return;
        const size_t first = ctx->getStart()->getTokenIndex();
        if (auto* m = dynamic_cast<P::MemberContext*>(ctx))
            starts[first] = m->portDecl() ? Starts::Port : m->instanceDecl() ? Starts::Instance : Starts::Other;
        else if (auto* c = dynamic_cast<P::CompItemContext*>(ctx))
            starts[first] = c->transitionDecl() ? Starts::Transition : c->animationDecl() ? Starts::Animation : Starts::Other;
        else if (dynamic_cast<P::ItemContext*>(ctx) || dynamic_cast<P::AnimItemContext*>(ctx))
            starts[first] = Starts::Other;
        else if (auto* u = dynamic_cast<P::UnaryExprContext*>(ctx))
            prefix.push_back(u->op->getTokenIndex());
        else if (dynamic_cast<P::ArgsContext*>(ctx) || dynamic_cast<P::ParamListContext*>(ctx))
            glued.push_back(first);  // the `(` of a call or a parameter list
        else if (dynamic_cast<P::UnitContext*>(ctx) && ctx->getStop())
            for (size_t i = first + 1; i <= ctx->getStop()->getTokenIndex(); ++i) glued.push_back(i);
        for (auto* child : ctx->children) walk(child);
    }

private:
    void terminal(antlr4::tree::TerminalNode* term) {
        antlr4::Token* t = term->getSymbol();
        if (t->getText() != "[") return;
        auto* parent = term->parent;
        // An index (`seg[i]`, `piece[i]: ...`), not a list literal.
        if (dynamic_cast<P::PathSegContext*>(parent) || dynamic_cast<P::InstanceDeclContext*>(parent) ||
            dynamic_cast<P::NameExprContext*>(parent))
            glued.push_back(t->getTokenIndex());
    }
};

Lex lex_of(size_t type) {
    switch (type) {
        case plant_antlr::PlantLexer::DOC_COMMENT: return Lex::DocComment;
        case plant_antlr::PlantLexer::LINE_COMMENT: return Lex::LineComment;
        case plant_antlr::PlantLexer::BLOCK_COMMENT: return Lex::BlockComment;
        default: return Lex::Code;
    }
}

}  // namespace

std::optional<std::vector<LayoutToken>> layout_tokens(const SourceMap& sources, int32_t file, Sink& sink) {
    // The builder's parse reports the syntax errors, with the same words as `plant check`.
    const int before = sink.count(Severity::Error);
    parse_module(sources, file, sink);
    if (sink.count(Severity::Error) > before) return std::nullopt;

    const std::string& text = sources.text(file);
    const Offsets offsets(text);
    antlr4::ANTLRInputStream input(text);
    plant_antlr::PlantLexer lexer(&input);
    antlr4::CommonTokenStream stream(&lexer);
    P parser(&stream);
    lexer.removeErrorListeners();
    parser.removeErrorListeners();
    parser.getInterpreter<antlr4::atn::ParserATNSimulator>()->setPredictionMode(antlr4::atn::PredictionMode::SLL);
    parser.setErrorHandler(std::make_shared<antlr4::BailErrorStrategy>());
    P::ModuleContext* tree = nullptr;
    try {
        tree = parser.module();
    } catch (const antlr4::ParseCancellationException&) {
        stream.seek(0);
        parser.reset();
        parser.setErrorHandler(std::make_shared<antlr4::DefaultErrorStrategy>());
        parser.getInterpreter<antlr4::atn::ParserATNSimulator>()->setPredictionMode(antlr4::atn::PredictionMode::LL);
        tree = parser.module();
    }
    Marker marks;
    marks.walk(tree);

    std::vector<LayoutToken> out;
    std::vector<int> index_of(stream.size(), -1);
    for (antlr4::Token* t : stream.getTokens()) {
        if (t->getType() == antlr4::Token::EOF) break;
        LayoutToken lt;
        lt.begin = offsets.byte(t->getStartIndex());
        lt.end = offsets.byte(t->getStopIndex() + 1);
        lt.lex = lex_of(t->getType());
        index_of[t->getTokenIndex()] = static_cast<int>(out.size());
        out.push_back(lt);
    }
    auto at = [&](size_t i) -> LayoutToken* { return i < index_of.size() && index_of[i] >= 0 ? &out[index_of[i]] : nullptr; };
    for (auto [i, s] : marks.starts)
        if (auto* t = at(i)) t->starts = s;
    for (size_t i : marks.prefix)
        if (auto* t = at(i)) t->prefix = true;
    for (size_t i : marks.glued)
        if (auto* t = at(i)) t->glued = true;
    return out;
}

}  // namespace plant::parse
