// ANTLR parse tree -> our AST, one function per grammar rule. Compiled as C++17
// because the generated code and the ANTLR headers do not build as C++20.
#include "parse/parser.h"
#include "parse/braces.h"
#include "parse/offsets.h"
#include "graph/utf8.h"

#include "PlantLexer.h"
#include "PlantParser.h"
#include "antlr4-runtime.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <optional>
#include <string>

namespace plant::parse {
namespace {

using P = plant_antlr::PlantParser;

// Words for tokens in "expected ..." messages.
std::string token_words(const antlr4::dfa::Vocabulary& voc, size_t type, const std::string& eof) {
    if (type == antlr4::Token::EOF) return eof;
    std::string sym = voc.getSymbolicName(type);
    if (sym == "ID") return "a name";
    if (sym == "NUMBER") return "a number";
    if (sym == "STRING") return "a string";
    std::string lit = voc.getLiteralName(type);
    if (!lit.empty()) return lit;  // already quoted: 'flow'
    return sym;
}

std::string token_text(antlr4::Token* t, const std::string& eof) {
    if (!t || t->getType() == antlr4::Token::EOF) return eof;
    return "'" + t->getText() + "'";
}

// A character in a message: printable ASCII as itself, anything else by its code point too
// ("U+0000 (NUL, a control character)", "'П' (U+041F)").
std::string describe_char(const std::string& t) {
    if (t.empty()) return "''";
    const auto c0 = static_cast<unsigned char>(t[0]);
    uint32_t cp = c0;
    size_t n = c0 < 0x80 ? 1 : (c0 & 0xE0) == 0xC0 ? 2 : (c0 & 0xF0) == 0xE0 ? 3 : 4;
    if (n > 1) {
        cp = c0 & (0x7F >> n);
        for (size_t k = 1; k < n && k < t.size(); ++k) cp = (cp << 6) | (static_cast<unsigned char>(t[k]) & 0x3F);
    }
    char code[16];
    std::snprintf(code, sizeof code, "U+%04X", static_cast<unsigned>(cp));
    if (cp < 0x20 || cp == 0x7F) {
        const char* name = cp == 0 ? "NUL, " : cp == 0x7F ? "DEL, " : cp == 0x1B ? "ESC, " : "";
        return std::string(code) + " (" + name + "a control character)";
    }
    if (cp < 0x80) return "'" + t.substr(0, 1) + "'";
    return "'" + t.substr(0, n) + "' (" + code + "; names are ASCII letters, digits and '_')";
}

class ErrorListener : public antlr4::BaseErrorListener {
public:
    // `eof` names the end of the input in messages: "end of file", or for a --set
    // value "end of the value".
    ErrorListener(Sink& sink, int32_t file, const Offsets& off, std::string eof = "end of file")
        : sink_(sink), file_(file), off_(off), eof_(std::move(eof)) {}

    void syntaxError(antlr4::Recognizer* rec, antlr4::Token* bad, size_t line, size_t,
                     const std::string& msg, std::exception_ptr) override {
        Span span{file_, 0, 0};
        if (bad) {
            span.begin = off_.byte(bad->getStartIndex());
            span.end = bad->getType() == antlr4::Token::EOF ? span.begin
                                                              : off_.byte(bad->getStopIndex() + 1);
        }
        // While ANTLR recovers from an error it often reports again further on the same
        // line; the first report is the one that explains it, so one error per line.
        if (line == last_line_) return;
        last_line_ = line;
        auto* parser = dynamic_cast<antlr4::Parser*>(rec);
        if (!parser) {  // a lexer error: ANTLR's message names the character
            sink_.report(DiagId::Syntax, span, "unexpected character: " + msg);
            return;
        }
        if (msg.find("failed predicate") != std::string::npos) {  // {adjacent()}? inside a unit
            sink_.report(DiagId::Syntax, span,
                         "a compound unit is written without spaces, e.g. 50 cm/s or 9.81 m/s^2");
            return;
        }
        if (bad && bad->getType() == P::BAD_CHAR) {
            if (bad->getText() == "\"")  // STRING did not match: no closing quote on this line
                sink_.report(DiagId::Syntax, span, "unterminated string: close it with '\"' on the same line");
            else
                sink_.report(DiagId::Syntax, span, "unexpected character " + describe_char(bad->getText()));
            return;
        }
        std::string expected;
        bool name_fits = false;      // a name may come here
        bool self_expected = false;  // the recovery's set names the very token it rejects
        bool only_name = false;      // nothing but a name fits here
        bool brace_fits = false;     // a `}` may come here
        try {
            auto set = parser->getExpectedTokens();
            for (auto t : set.toList()) brace_fits = brace_fits || parser->getVocabulary().getLiteralName(t) == "'}'";
            name_fits = set.contains(static_cast<size_t>(P::ID));
            only_name = name_fits;
            for (auto t : set.toList())
                only_name = only_name && (t == static_cast<size_t>(P::ID) || parser->getVocabulary().getLiteralName(t) == "'object'");
            self_expected = bad && bad->getType() > 0 && set.contains(static_cast<size_t>(bad->getType()));
            std::set<std::string> words;
            for (auto t : set.toList()) words.insert(token_words(parser->getVocabulary(), t, eof_));
            size_t i = 0;
            for (const auto& w : words) {
                if (i) expected += (i + 1 == words.size()) ? " or " : ", ";
                expected += w;
                ++i;
            }
        } catch (...) {
            expected.clear();
        }
        std::string text = "unexpected " + token_text(bad, eof_);
        // "unexpected 'flow'; expected 'flow', ..." would contradict itself: say less.
        if (!expected.empty() && expected.size() < 300 && !self_expected) text += "; expected " + expected;
        auto& d = sink_.report(DiagId::Syntax, span, text);
        // The end of the file or a keyword that cannot come here, where a `}` could: the `{`
        // it would close (and the block that is likely missing it).
        if (brace_fits && bad && !self_expected && (bad->getType() == antlr4::Token::EOF || keyword_token(bad)))
            for (Note& n : unclosed_brace_notes(file_, braces_before(parser, bad),
                                                  bad->getType() != antlr4::Token::EOF ? token_text(bad, eof_)
                                                  : eof_ == "end of file" ? "the end of the file" : "the " + eof_)) d.notes.push_back(std::move(n));
        // A keyword where a name was meant: `animation out { ... }`, `flow: Belt`.
        auto keyword = [](antlr4::Token* t) {
            std::string w = t ? t->getText() : "";
            return t && t->getType() != P::ID && !w.empty() &&
                   std::all_of(w.begin(), w.end(), [](char ch) { return std::isalpha(static_cast<unsigned char>(ch)) != 0; });
        };
        antlr4::Token* prev = bad && bad->getText() == ":" ? parser->getTokenStream()->LT(-1) : nullptr;
        // A keyword where only a name fits, or one the recovery both rejects and expects
        // (`label flow {`): a name was meant. A keyword starting a statement after a
        // missing brace gets no note.
        if (name_fits && keyword(bad) && (only_name || self_expected))
            d.notes.push_back({{}, "'" + bad->getText() + "' is a keyword and cannot be used as a name"});
        else if (keyword(prev))
            d.notes.push_back({{}, "'" + prev->getText() + "' is a keyword and cannot be used as a name"});
    }

private:
    static bool keyword_token(antlr4::Token* t) {
        const std::string w = t->getText();
        return t->getType() != P::ID && !w.empty() &&
               std::all_of(w.begin(), w.end(), [](char ch) { return std::isalpha(static_cast<unsigned char>(ch)) != 0; });
    }

    // The braces before `bad`, each with the indent of its line (the column of the line's
    // first token, comments included).
    std::vector<Brace> braces_before(antlr4::Parser* parser, antlr4::Token* bad) const {
        antlr4::TokenStream* ts = parser->getTokenStream();
        std::vector<Brace> out;
        size_t line = 0;
        int indent = 0;
        for (size_t i = 0; i < bad->getTokenIndex() && i < ts->size(); ++i) {
            antlr4::Token* t = ts->get(i);
            if (t->getLine() != line) line = t->getLine(), indent = static_cast<int>(t->getCharPositionInLine());
            const std::string w = t->getText();
            if (t->getChannel() == antlr4::Token::DEFAULT_CHANNEL && (w == "{" || w == "}"))
                out.push_back({off_.byte(t->getStartIndex()), static_cast<int>(line), indent, w == "{"});
        }
        return out;
    }

    Sink& sink_;
    int32_t file_;
    const Offsets& off_;
    std::string eof_;
    size_t last_line_ = 0;  // lines count from 1
};

// Limits that keep the parser and the compiler's recursive passes within the stack.
constexpr int kMaxNesting = 200;     // brackets and braces, and runs of prefix operators
constexpr int kMaxExprDepth = 400;  // operators on the way down one expression tree (an evaluation
                                     // frame under AddressSanitizer is about 10 KiB: 400 keeps it under 4 MiB)

class Builder {
public:
    Builder(int32_t file, const Offsets& off, const std::string& text, Sink& sink)
        : file_(file), off_(off), text_(text), sink_(sink) {}

    Span span(antlr4::ParserRuleContext* c) const {
        if (!c || !c->start) return Span{file_, 0, 0};
        auto* stop = c->stop ? c->stop : c->start;
        uint32_t b = off_.byte(c->start->getStartIndex());
        uint32_t e = stop->getType() == antlr4::Token::EOF ? b : off_.byte(stop->getStopIndex() + 1);
        return Span{file_, b, std::max(b, e)};
    }
    Span span(antlr4::Token* t) const {
        if (!t) return Span{file_, 0, 0};
        uint32_t b = off_.byte(t->getStartIndex());
        return Span{file_, b, off_.byte(t->getStopIndex() + 1)};
    }
    Span span(antlr4::tree::TerminalNode* n) const { return span(n ? n->getSymbol() : nullptr); }

    ast::Ident ident(antlr4::tree::TerminalNode* n) const {
        if (!n) return {};
        return ast::Ident{n->getText(), span(n)};
    }
    ast::Ident ident(antlr4::Token* t) const {
        if (!t) return {};
        return ast::Ident{t->getText(), span(t)};
    }

    ast::Module module(P::ModuleContext* c) {
        ast::Module m;
        m.file = file_;
        for (auto* item : c->item()) {
            if (auto* imp = item->importDecl()) {
                for (auto* d : imp->dotted()) {
                    std::string name;
                    for (auto* id : d->ID()) name += (name.empty() ? "" : ".") + id->getText();
                    m.imports.push_back(ast::Import{name, span(d)});
                }
            } else if (auto* o = item->objectDecl()) {
                m.objects.push_back(object(o));
            } else if (auto* p = item->plantDecl()) {
                ast::ObjectDecl d;
                d.is_plant = true;
                d.name = ident(p->ID());
                d.span = span(p);
                params(p->paramList(), d.params);
                for (auto* mem : p->member()) member(mem, d.members);
                m.objects.push_back(std::move(d));
            }
        }
        return m;
    }

    ast::ObjectDecl object(P::ObjectDeclContext* c) {
        ast::ObjectDecl d;
        d.name = ident(c->ID());
        d.span = span(c);
        params(c->paramList(), d.params);
        for (auto* mem : c->member()) member(mem, d.members);
        return d;
    }

    void params(P::ParamListContext* pl, std::vector<ast::Param>& out) {
        if (!pl) return;
        for (auto* p : pl->param()) {
            ast::Param param;
            param.name = ident(p->ID());
            param.type = ident(p->ident());
            if (p->def) param.default_value = expr(p->def);
            if (p->cond) param.constraint = expr(p->cond);
            param.span = span(p);
            out.push_back(std::move(param));
        }
    }

    // NAME=VALUE from the command line: a named argument for the plant.
    ast::Arg cli_set(P::CliSetContext* c) {
        ast::Arg a;
        a.name = ident(c->ID());
        a.value = expr(c->expr());
        a.span = ast::join(a.name->span, a.value ? a.value->span : Span{});  // not the EOF
        return a;
    }

    void member(P::MemberContext* c, std::vector<ast::Member>& out) {
        if (auto* x = c->portDecl()) {
            ast::PortDecl d;
            d.is_input = x->dir && x->dir->getText() == "in";
            auto ids = x->ID();
            if (ids.size() >= 2) {
                d.name = ident(ids[0]);
                d.type = ident(ids[1]);
            }
            for (auto* p : x->path()) d.targets.push_back(path(p));
            d.span = span(x);
            out.emplace_back(std::move(d));
        } else if (auto* x = c->letDecl()) {
            out.emplace_back(ast::LetDecl{ident(x->ID()), expr(x->expr()), span(x)});
        } else if (auto* x = c->flowDecl()) {
            ast::FlowDecl d;
            if (x->ID()) d.name = ident(x->ID());
            auto paths = x->path();
            if (paths.size() >= 2) {
                d.from = path(paths[0]);
                d.to = path(paths[1]);
            }
            // Each option once: a second condition or 'once' would silently win or do nothing.
            std::optional<Span> first_once;
            for (auto* opt : x->flowOption()) {
                if (opt->ID() && d.condition) {
                    auto& r = sink_.report(DiagId::DuplicateProperty, span(opt),
                                           fmt::format("a flow takes one condition; it already has 'when {}'", d.condition->text));
                    r.notes.push_back({d.condition->span, "the first condition"});
                } else if (opt->ID()) {
                    d.condition = ident(opt->ID());
                } else if (first_once) {
                    auto& r = sink_.report(DiagId::DuplicateProperty, span(opt), "'once' is given twice");
                    r.notes.push_back({*first_once, "first given here"});
                } else {
                    first_once = span(opt);
                    d.once = true;
                }
            }
            d.span = span(x);
            out.emplace_back(std::move(d));
        } else if (auto* x = c->logicDecl()) {
            ast::LogicDecl d;
            d.name = ident(x->ID());
            for (auto* t : x->logicTerm())
                d.terms.push_back(ast::LogicTerm{t->neg != nullptr, path(t->path()), span(t)});
            for (auto* op : x->op) d.ops.push_back(ident(op));
            d.span = span(x);
            out.emplace_back(std::move(d));
        } else if (auto* x = c->forDecl()) {
            auto d = std::make_unique<ast::ForDecl>();
            d->var = ident(x->ID());
            auto es = x->expr();
            if (!es.empty()) d->from = expr(es[0]);
            if (es.size() >= 2) d->to = expr(es[1]);
            for (auto* m : x->member()) member(m, d->body);
            d->span = span(x);
            out.emplace_back(std::move(d));
        } else if (auto* x = c->ifDecl()) {
            auto d = std::make_unique<ast::IfDecl>();
            d->cond = expr(x->expr());
            for (auto* m : x->thenBody) member(m, d->then_body);
            for (auto* m : x->elseBody) member(m, d->else_body);
            d->span = span(x);
            out.emplace_back(std::move(d));
        } else if (auto* x = c->recordDecl()) {
            ast::RecordDecl d;
            d.path = path(x->path());
            if (x->expr()) d.column = expr(x->expr());
            d.span = span(x);
            out.emplace_back(std::move(d));
        } else if (auto* x = c->settingDecl()) {
            out.emplace_back(ast::SettingDecl{ident(x->ID()), expr(x->expr()), span(x)});
        } else if (auto* x = c->instanceDecl()) {
            ast::InstanceDecl d;
            auto ids = x->ID();
            if (ids.size() >= 2) {
                d.name = ident(ids[0]);
                d.type = ident(ids[1]);
            }
            if (x->expr()) d.index = expr(x->expr());
            if (x->args()) {
                d.args = args(x->args());
                d.args_span = span(x->args());
            }
            if (x->placement()) d.placement = placement(x->placement());
            d.span = span(x);
            out.emplace_back(std::move(d));
        } else if (auto* x = c->componentDecl()) {
            out.emplace_back(component(x));
        }
    }

    ast::ComponentDecl component(P::ComponentDeclContext* c) {
        ast::ComponentDecl d;
        d.kind = ident(c->kindName);
        d.name = ident(c->compName);
        if (c->modeName) d.mode = ident(c->modeName);
        if (c->path()) d.on = path(c->path());
        if (c->placement()) d.placement = placement(c->placement());
        d.span = span(c);
        for (auto* item : c->compItem()) {
            if (auto* x = item->property()) {
                d.properties.push_back(property(x));
            } else if (auto* x = item->shapeDecl()) {
                ast::ShapeDecl s;
                s.kind = ident(x->ID());
                if (x->args()) s.args = args(x->args());
                if (x->placement()) s.placement = placement(x->placement());
                s.span = span(x);
                d.shapes.push_back(std::move(s));
            } else if (auto* x = item->animationDecl()) {
                d.animations.push_back(animation(x));
            } else if (auto* x = item->variantDecl()) {
                d.variants.push_back(ast::VariantDecl{ident(x->ID()), expr(x->expr()), span(x)});
            } else if (auto* x = item->placeDecl()) {
                for (auto* pi : x->placeInit()) {
                    ast::PlaceDecl p{ident(pi->ID()), nullptr, span(pi)};
                    if (pi->expr()) p.initial = expr(pi->expr());
                    d.places.push_back(std::move(p));
                }
            } else if (auto* x = item->transitionDecl()) {
                d.transitions.push_back(transition(x));
            } else if (auto* x = item->routeDecl()) {
                ast::RouteDecl r;
                if (x->expr()) {
                    r.pattern = x->expr()->getText();
                    r.pattern_expr = expr(x->expr());
                    r.pattern_span = span(x->expr());
                } else {
                    r.pattern = "*";
                    r.pattern_span = span(x->start);
                }
                r.output = ident(x->ID());
                r.span = span(x);
                d.routes.push_back(std::move(r));
            } else if (auto* x = item->entryDecl()) {
                ast::EntryDecl e;
                e.word = ident(x->ID());
                e.key = expr(x->expr());
                e.target = path(x->path());
                if (x->args()) e.options = args(x->args());
                e.span = span(x);
                d.entries.push_back(std::move(e));
            } else if (auto* x = item->componentDecl()) {
                d.children.push_back(component(x));
            }
        }
        return d;
    }

    ast::Ident ident(P::IdentContext* c) const {
        if (!c) return {};
        return ast::Ident{c->getStart()->getText(), span(c)};  // one token; getText() would build a stream
    }

    ast::Property property(P::PropertyContext* c) {
        return ast::Property{ident(c->ident()), expr(c->expr()), span(c)};
    }

    ast::AnimationDecl animation(P::AnimationDeclContext* c) {
        ast::AnimationDecl a;
        a.name = ident(c->ID());
        a.span = span(c);
        for (auto* item : c->animItem()) {
            if (item->property()) {
                a.properties.push_back(property(item->property()));
            } else if (item->rotation()) {
                a.rotations.push_back(rotation(item->rotation()));
            } else if (item->placement()) {
                ast::KeyDecl k;
                k.time = expr(item->expr());
                k.placement = placement(item->placement());
                k.span = span(item);
                a.keys.push_back(std::move(k));
            } else if (item->expr()) {
                a.moves.push_back(expr(item->expr()));
            }
        }
        return a;
    }

    ast::TransitionDecl transition(P::TransitionDeclContext* c) {
        ast::TransitionDecl t;
        t.name = ident(c->ID());
        t.span = span(c);
        // `->` splits the arc lists; an omitted side is an empty list.
        auto lists = c->arcList();
        antlr4::tree::TerminalNode* arrow = nullptr;
        for (auto* ch : c->children)
            if (auto* term = dynamic_cast<antlr4::tree::TerminalNode*>(ch))
                if (term->getText() == "->") arrow = term;
        for (auto* list : lists) {
            bool before = arrow && list->start->getTokenIndex() < arrow->getSymbol()->getTokenIndex();
            auto& side = before ? t.inputs : t.outputs;
            for (auto* a : list->arc()) {
                ast::ArcDecl arc;
                arc.place = ident(a->ID());
                if (a->NUMBER()) {
                    arc.weight_written = true;
                    arc.weight = number(a->NUMBER()->getText());
                    arc.weight_span = span(a->NUMBER());
                }
                arc.span = span(a);
                side.push_back(std::move(arc));
            }
        }
        return t;
    }

    ast::Placement placement(P::PlacementContext* c) {
        ast::Placement p;
        if (c->expr()) p.at = expr(c->expr());
        for (auto* r : c->rotation()) p.rotations.push_back(rotation(r));
        p.span = span(c);
        return p;
    }

    ast::Rotation rotation(P::RotationContext* c) {
        ast::Rotation r;
        auto* ax = c->axis();
        if (ax && ax->ID()) {
            r.axis_name = ident(ax->ID());
        } else if (ax) {
            auto v = std::make_unique<ast::Expr>();
            v->kind = ast::ExprKind::Tuple;
            v->span = span(ax);
            for (auto* e : ax->expr()) v->kids.push_back(expr(e));
            r.axis_vec = std::move(v);
        }
        r.angle = expr(c->expr());
        r.span = span(c);
        return r;
    }

    std::vector<ast::Arg> args(P::ArgsContext* c) {
        std::vector<ast::Arg> out;
        for (auto* a : c->arg()) {
            ast::Arg arg;
            if (a->ID()) arg.name = ident(a->ID());
            arg.value = expr(a->expr());
            arg.span = span(a);
            out.push_back(std::move(arg));
        }
        return out;
    }

    ast::Path path(P::PathContext* c) {
        ast::Path p;
        if (!c) return p;
        p.span = span(c);
        if (auto* cast = dynamic_cast<P::CastPathContext*>(c)) {
            p.cast_base = std::make_unique<ast::Path>(path(cast->path()));
            p.cast_type = ident(cast->ID());
            for (auto* s : cast->pathSeg()) p.segs.push_back(seg(s));
        } else if (auto* plain = dynamic_cast<P::PlainPathContext*>(c)) {
            for (auto* s : plain->pathSeg()) p.segs.push_back(seg(s));
        }
        return p;
    }

    ast::PathSeg seg(P::PathSegContext* c) {
        ast::PathSeg s;
        s.name = ident(c->ident());
        if (c->expr()) s.index = expr(c->expr());
        return s;
    }

    ast::ExprPtr make(ast::ExprKind k, antlr4::ParserRuleContext* c) {
        auto e = std::make_unique<ast::Expr>();
        e->kind = k;
        e->span = span(c);
        return e;
    }

    // The first expression deeper than kMaxExprDepth, if any: it is not built further
    // (the compiler's passes over expressions recurse).
    const std::optional<Span>& too_deep() const { return too_deep_; }

    ast::ExprPtr expr(P::ExprContext* c) {
        if (!c) return make(ast::ExprKind::Number, nullptr);
        struct Depth {
            int& d;
            explicit Depth(int& x) : d(++x) {}
            ~Depth() { --d; }
        } guard(depth_);
        if (depth_ > kMaxExprDepth) {
            if (!too_deep_) too_deep_ = span(c);
            return make(ast::ExprKind::Number, c);
        }
        if (auto* x = dynamic_cast<P::PrimaryExprContext*>(c)) return primary(x->primary());
        if (auto* x = dynamic_cast<P::UnaryExprContext*>(c)) {
            auto e = make(ast::ExprKind::Unary, c);
            e->text = x->op ? x->op->getText() : "-";
            e->kids.push_back(expr(x->expr()));
            return e;
        }
        if (auto* x = dynamic_cast<P::BinaryExprContext*>(c)) {
            auto e = make(ast::ExprKind::Binary, c);
            e->text = x->op ? x->op->getText() : "+";
            for (auto* k : x->expr()) e->kids.push_back(expr(k));
            while (e->kids.size() < 2) e->kids.push_back(make(ast::ExprKind::Number, nullptr));
            return e;
        }
        return make(ast::ExprKind::Number, c);
    }

    ast::ExprPtr primary(P::PrimaryContext* c) {
        if (auto* x = dynamic_cast<P::NumberLitContext*>(c)) {
            auto e = make(ast::ExprKind::Number, c);
            e->number = x->NUMBER() ? number(x->NUMBER()->getText()) : 0.0;
            if (auto* u = x->unit()) {
                e->text = text_.substr(off_.byte(u->getStart()->getStartIndex()),
                                       off_.byte(u->getStop()->getStopIndex() + 1) - off_.byte(u->getStart()->getStartIndex()));
                e->unit_span = span(u);
            }
            return e;
        }
        if (auto* x = dynamic_cast<P::StringLitContext*>(c)) {
            auto e = make(ast::ExprKind::String, c);
            e->text = unquote(x->STRING()->getText());
            return e;
        }
        if (auto* x = dynamic_cast<P::BoolLitContext*>(c)) {
            auto e = make(ast::ExprKind::Bool, c);
            e->boolean = x->value && x->value->getText() == "true";
            return e;
        }
        if (auto* x = dynamic_cast<P::ParenExprContext*>(c)) {
            auto inner = expr(x->expr());
            inner->span = span(c);
            return inner;
        }
        if (auto* x = dynamic_cast<P::TupleExprContext*>(c)) {
            auto e = make(ast::ExprKind::Tuple, c);
            for (auto* k : x->expr()) e->kids.push_back(expr(k));
            return e;
        }
        if (auto* x = dynamic_cast<P::ListExprContext*>(c)) {
            auto e = make(ast::ExprKind::List, c);
            for (auto* k : x->expr()) e->kids.push_back(expr(k));
            return e;
        }
        if (auto* x = dynamic_cast<P::CallExprContext*>(c)) {
            auto e = make(ast::ExprKind::Call, c);
            e->text = x->ID()->getText();
            e->args = args(x->args());
            return e;
        }
        if (auto* x = dynamic_cast<P::NameExprContext*>(c)) {
            auto e = make(ast::ExprKind::Name, c);
            auto ids = x->ID();
            if (!ids.empty()) e->text = ids[0]->getText();
            for (size_t i = 1; i < ids.size(); ++i) e->members.push_back(ident(ids[i]));
            if (x->expr()) e->index = expr(x->expr());
            return e;
        }
        return make(ast::ExprKind::Number, c);
    }

    // Never throws: a literal too large for a double is +inf, reported by the checks.
    static double number(const std::string& s) { return std::strtod(s.c_str(), nullptr); }

    static std::string unquote(const std::string& s) {
        std::string out;
        for (size_t i = 1; i + 1 < s.size(); ++i) {
            char ch = s[i];
            if (ch == '\\' && i + 2 < s.size()) {
                char n = s[++i];
                out += n == 'n' ? '\n' : n == 't' ? '\t' : n;
            } else {
                out += ch;
            }
        }
        return out;
    }

private:
    int32_t file_;
    const Offsets& off_;
    const std::string& text_;
    Sink& sink_;
    int depth_ = 0;
    std::optional<Span> too_deep_;
};

}  // namespace

// ANTLR's pipeline over one source text, our error listener on lexer and parser.
// (Members in construction order: each takes the one before it.)
struct Pipeline {
    Pipeline(const std::string& text, Sink& sink, int32_t file, const Offsets& offsets,
             std::string eof = "end of file")
        : input(text), lexer(&input), tokens(&lexer), parser(&tokens), listener(sink, file, offsets, std::move(eof)) {
        lexer.removeErrorListeners();
        lexer.addErrorListener(&listener);
        parser.removeErrorListeners();
        parser.addErrorListener(&listener);
    }
    antlr4::ANTLRInputStream input;
    plant_antlr::PlantLexer lexer;
    antlr4::CommonTokenStream tokens;
    plant_antlr::PlantParser parser;
    ErrorListener listener;
};

// What a file with errors that stop its checking contributes: nothing.
static ast::Module empty_module(int32_t file) {
    ast::Module m;
    m.file = file;
    return m;
}

// Text reaches ANTLR only as UTF-8: its input stream converts with wstring_convert, which
// throws on anything else. A file's readers report E0008 before this; a --set value, a
// sweep's value or an editor's buffer arrive here first.
static bool utf8_text(const SourceMap& sources, int32_t file, Sink& sink) {
    const std::string& text = sources.text(file);
    const size_t bad = graph::invalid_utf8(text);
    if (bad == std::string::npos) return true;
    auto& d = sink.report(DiagId::InvalidText, Span{file, static_cast<uint32_t>(bad), static_cast<uint32_t>(bad + 1)},
                          fmt::format("not valid UTF-8: byte 0x{:02X} here", static_cast<unsigned char>(text[bad])));
    d.notes.push_back({{}, "plant text is UTF-8; a Latin-1 'ä' is one such byte"});
    return false;
}

ast::Module parse_module(const SourceMap& sources, int32_t file, Sink& sink) {
    if (!utf8_text(sources, file, sink)) return empty_module(file);
    const std::string& text = sources.text(file);
    Offsets offsets(text);
    Pipeline p(text, sink, file, offsets);
    auto& tokens = p.tokens;
    auto& parser = p.parser;

    // Nesting the parser would recurse through without bound: brackets and braces, and
    // runs of prefix operators (`- - - x`). Stop at the first too deep one.
    tokens.fill();
    int open = 0, prefix = 0;
    for (antlr4::Token* t : tokens.getTokens()) {
        const std::string s = t->getText();
        if (t->getType() == antlr4::Token::EOF) break;
        open += s == "(" || s == "[" || s == "{" ? 1 : s == ")" || s == "]" || s == "}" ? -1 : 0;
        prefix = s == "-" || s == "not" ? prefix + 1 : 0;
        if (open > kMaxNesting || prefix > kMaxNesting) {
            sink.report(DiagId::NestingTooDeep, Span{file, offsets.byte(t->getStartIndex()),
                                                     offsets.byte(t->getStopIndex() + 1)},
                        "more than " + std::to_string(kMaxNesting) + " nested brackets, braces or prefix operators");
            return empty_module(file);
        }
    }

    // Two-stage parse: the fast SLL prediction almost always suffices; only when it
    // fails is the input parsed again with full LL prediction and error recovery, so the
    // diagnostics are the same as with LL alone.
    const int before = sink.count(Severity::Error);
    plant_antlr::PlantParser::ModuleContext* tree = nullptr;
    parser.getInterpreter<antlr4::atn::ParserATNSimulator>()->setPredictionMode(antlr4::atn::PredictionMode::SLL);
    parser.removeErrorListeners();
    parser.setErrorHandler(std::make_shared<antlr4::BailErrorStrategy>());
    try {
        tree = parser.module();
    } catch (const antlr4::ParseCancellationException&) {
        tree = nullptr;
    }
    if (!tree) {
        tokens.seek(0);
        parser.reset();
        parser.addErrorListener(&p.listener);
        parser.setErrorHandler(std::make_shared<antlr4::DefaultErrorStrategy>());
        parser.getInterpreter<antlr4::atn::ParserATNSimulator>()->setPredictionMode(antlr4::atn::PredictionMode::LL);
        tree = parser.module();
    }
    if (sink.count(Severity::Error) > before) {
        // The tree after recovery may be partial; only syntax errors are reported for this file.
        return empty_module(file);
    }
    Builder builder(file, offsets, text, sink);
    ast::Module m = builder.module(tree);
    if (builder.too_deep()) {
        sink.report(DiagId::NestingTooDeep, *builder.too_deep(),
                    "an expression nested more than " + std::to_string(kMaxExprDepth) + " operators deep; split it with `let`");
        return empty_module(file);
    }
    return m;
}

std::optional<ast::Arg> parse_set(const SourceMap& sources, int32_t file, Sink& sink) {
    if (!utf8_text(sources, file, sink)) return std::nullopt;
    const std::string& text = sources.text(file);
    Offsets offsets(text);
    Pipeline p(text, sink, file, offsets, "end of the value");
    const int before = sink.count(Severity::Error);
    auto* tree = p.parser.cliSet();
    if (sink.count(Severity::Error) > before) return std::nullopt;
    Builder builder(file, offsets, text, sink);
    return builder.cli_set(tree);
}

}  // namespace plant::parse
