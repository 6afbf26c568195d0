// A diagnostic is a value: severity, registered code, source span, message, notes.
// The compiler keeps going after an error and collects every diagnostic in a Sink;
// rendering (text with caret, or JSON) happens once at the end, sorted by position.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace plant {

// A byte range in one source file; turned into line:col only when printed.
struct Span {
    int32_t file = -1;  // index into SourceMap, -1 for "no position"
    uint32_t begin = 0;
    uint32_t end = 0;
    bool valid() const { return file >= 0; }
};

enum class Severity : uint8_t { Note, Warning, Error };

enum class DiagId : uint16_t {
#define PLANT_DIAG(Id, Code, Sev, Summary) Id,
#include "diag/codes.def"
#undef PLANT_DIAG
};

struct DiagInfo {
    DiagId id;
    std::string_view code;
    Severity severity;
    std::string_view summary;
};
const DiagInfo& info(DiagId id);
std::vector<DiagInfo> all_diagnostics();

struct Note {
    Span span;  // may be invalid: a note without a position
    std::string message;
};

struct Diagnostic {
    DiagId id;
    Severity severity;
    Span span;
    std::string message;
    std::vector<Note> notes;
};

// The loaded source files. Positions are byte offsets; line/col are 1-based, col
// counts bytes.
class SourceMap {
public:
    int32_t add(std::string display_name, std::string text);
    const std::string& name(int32_t file) const { return files_[file].name; }
    const std::string& text(int32_t file) const { return files_[file].text; }
    int32_t size() const { return static_cast<int32_t>(files_.size()); }
    struct LineCol { uint32_t line; uint32_t col; };
    LineCol line_col(int32_t file, uint32_t offset) const;
    std::string_view line_text(int32_t file, uint32_t line) const;

private:
    struct File {
        std::string name;
        std::string text;
        std::vector<uint32_t> line_starts;
    };
    std::vector<File> files_;
};

class Sink {
public:
    Diagnostic& report(DiagId id, Span span, std::string message);
    // Shorthand for adding a note to the diagnostic just reported.
    const std::vector<Diagnostic>& all() const { return diags_; }
    bool has_errors() const;
    int count(Severity s) const;
    // Sorted by (file, begin, code), stable; duplicates (same code, span and message) removed.
    std::vector<Diagnostic> sorted() const;

private:
    std::vector<Diagnostic> diags_;
};

// "file:line:col: error[E0101]: message" + source line + caret + notes.
std::string render_text(const Diagnostic& d, const SourceMap& sm);
std::string render_all_text(const std::vector<Diagnostic>& ds, const SourceMap& sm);
// One JSON document: {"diagnostics":[{"severity","code","file","line","col",
// "end_line","end_col","message","notes":[...]}]}
std::string render_json(const std::vector<Diagnostic>& ds, const SourceMap& sm);

// "did you mean" helper: the closest candidate by edit distance, or "" if none is close.
std::string closest_name(std::string_view wanted, const std::vector<std::string>& candidates);

// The same over candidates offered one at a time (in the order of the list above), for a caller
// that holds them elsewhere than in one list.
class ClosestName {
public:
    explicit ClosestName(std::string_view wanted);
    void offer(const std::string& candidate);
    std::string best() const { return best_ ? *best_ : std::string(); }

private:
    std::string_view wanted_;
    std::size_t limit_;
    const std::string* best_ = nullptr;
    std::pair<std::size_t, std::size_t> best_rank_{};
};

}  // namespace plant
