// Structural/behavioural analysis of one Petri net under the project's firing rule
// (docs/petri.md): every enabled transition fires in the same step, even in a
// forward conflict, and data flows may put a token on a 'fed' place in any step.
// Independent of the graph and of diagnostics so the compiler (W0401, W0402), the
// runtime tests and the docs can all use it.
#pragma once

#include <string>
#include <vector>

namespace plant::petri {

struct Arc {
    int place;
    int weight;
};

struct Transition {
    std::vector<Arc> in, out;  // an arc listed twice counts with the sum of its weights
};

struct Net {
    std::vector<int> initial;  // tokens per place
    std::vector<bool> fed;     // a data flow drives the place's 'put' input
    std::vector<Transition> transitions;
    // Optional, only for the explanations in Report::unbounded_why; "p3"/"t1" if empty.
    std::vector<std::string> place_names;
    std::vector<std::string> transition_names;
};

struct Report {
    std::vector<int> unbounded;               // places proved to grow without bound, ascending
    std::vector<std::string> unbounded_why;   // one sentence per entry of `unbounded`
    std::vector<int> dead;                    // transitions never enabled, ascending
    bool complete = true;                     // false: the exploration limit was hit
};

// One step of the firing rule: puts[p] tokens are added to place p (an empty `puts`
// adds none), then every transition enabled in that marking fires at once.
std::vector<int> step(const Net&, const std::vector<int>& marking, const std::vector<int>& puts);

// Transitions enabled in `marking` (after puts), ascending.
std::vector<int> enabled(const Net&, const std::vector<int>& marking);

// Explores the markings reachable from `initial` under every environment the 'fed'
// places allow (all subsets of puts for up to 6 fed places; otherwise none, all, and
// each one alone). Only sure findings are reported: a place is unbounded when a cycle
// of steps that provably repeats forever adds tokens to it; a transition is dead only
// when the exploration covered every reachable marking within `max_markings`.
Report analyse(const Net&, int max_markings = 20000);

}  // namespace plant::petri
