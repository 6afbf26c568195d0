// The text form of a Graph: line based, stable and diffable, for golden tests and
// for reading what the compiler produced. Driven by the X-macros of graph.h only,
// so a new field or table appears here without code changes.
//
//   plant-graph 2
//   plant "Bottling"
//   settings rate=150 gravity=(0 0 -9.81)
//   count files 1
//   file 0 "examples/belt.plant"
//   count do_types 1
//   dotype 0 name="Belt" instance_num=1 src=0:3:1
//   count dos 2
//   do 0 path="" parent=-1 ... pose=(0 0 0|0 0 0 1) src=-
//   ...
//   end
//
// Every table, in PLANT_GRAPH_TABLES order, is a `count <table> N` line followed by
// N records (an optional_table() only when it has records; absent, it is empty) `<element> <id> field=value ...` in field order. Names are written
// inline as quoted strings (`-` for none) and interned again when loading, so the
// names table is not written and its order may change; Graph::same_as compares
// names by text. Doubles use the shortest form that reads back exactly.
// The loader skips blank lines and lines starting with '#', for hand-edited files.
//
// Guarantee: to_text(load(to_text(g))) == to_text(g), byte for byte.
//
// The number after `plant-graph` is the format's version: any change to what the text form
// holds (a table, a field, a field's type, an enumeration's words, a kind's fixed slots)
// takes a new one, so that a graph written before is refused by name ("written by an older
// compiler ... compile it again") instead of failing somewhere inside. The test
// `graph text: the format's version changes whenever its fingerprint does` pins each
// version to format_fingerprint(), a hash of all of that (docs/graph.md).
#pragma once

#include "graph.h"

#include <cstdint>
#include <iosfwd>
#include <string>

namespace plant::graph {

constexpr int kFormatVersion = 4;

// A hash (FNV-1a, 64 bit) of what the text form holds: every table's name, element word and
// fields with their types, in order; every enumeration's words; every built-in kind's fixed
// slots. It changes when the format does.
uint64_t format_fingerprint();

std::string to_text(const Graph&);
void write_text(const Graph&, std::ostream&);

// How much read_text checks: the text form only, or also what the records promise each
// other (validate.h: ids and ranges inside their tables, the components' fixed slots,
// finite numbers), which the runtime relies on.
enum class Check { Form, Full };

// Replaces `g` only on success. On failure returns false with `error` as
// "line N: message"; any input, however broken, fails cleanly. A problem found by
// validate() names the record and the line it was read from: "line N: comp 7: ...".
bool read_text(std::istream&, Graph& g, std::string& error, Check check = Check::Full);

// As read_text; `error` is then "<path>: line N: message" or "<path>: cannot open".
bool load_text_file(const std::string& path, Graph& g, std::string& error, Check check = Check::Full);

}  // namespace plant::graph
