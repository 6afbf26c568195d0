#include "petri/analysis.h"

#include <doctest/doctest.h>

#include <string>
#include <vector>

using namespace plant::petri;

namespace {

enum SwitchPlace {
    BasePos, WorkingPos, MoveToBasePos, MoveToWorkingPos,
    BasePosStartAnim, WorkingPosStartAnim, BasePosAnimCtrl, WorkingPosAnimCtrl, kPlaces
};

plant::petri::Transition tr(std::vector<int> in, std::vector<int> out) {
    plant::petri::Transition t;
    for (int p : in) t.in.push_back({p, 1});
    for (int p : out) t.out.push_back({p, 1});
    return t;
}

// the track switch's net (stdlib/switch.plant); without the two draining transitions when `drains` is false.
Net track_switch(bool drains) {
    Net n;
    n.initial.assign(kPlaces, 0);
    n.initial[BasePos] = 1;
    n.initial[WorkingPosAnimCtrl] = 1;
    n.fed.assign(kPlaces, false);
    n.fed[MoveToBasePos] = n.fed[MoveToWorkingPos] = true;
    n.place_names = {"BasePos", "WorkingPos", "MoveToBasePos", "MoveToWorkingPos",
                     "BasePosStartAnim", "WorkingPosStartAnim", "BasePosAnimCtrl",
                     "WorkingPosAnimCtrl"};
    n.transitions.push_back(tr({BasePos, MoveToWorkingPos, WorkingPosAnimCtrl},
                               {WorkingPos, WorkingPosStartAnim, BasePosAnimCtrl}));
    n.transitions.push_back(tr({WorkingPos, MoveToBasePos, BasePosAnimCtrl},
                               {BasePos, BasePosStartAnim, WorkingPosAnimCtrl}));
    n.transition_names = {"tw", "tb"};
    if (drains) {
        n.transitions.push_back(tr({WorkingPos, MoveToWorkingPos}, {WorkingPos}));
        n.transitions.push_back(tr({BasePos, MoveToBasePos}, {BasePos}));
        n.transition_names.insert(n.transition_names.end(), {"tcw", "tcb"});
    }
    n.transitions.push_back(tr({WorkingPosStartAnim}, {}));
    n.transitions.push_back(tr({BasePosStartAnim}, {}));
    n.transition_names.insert(n.transition_names.end(), {"aw", "ab"});
    return n;
}

}  // namespace

TEST_CASE("petri: step adds puts first, then fires every enabled transition at once") {
    Net n;  // t0: 2 A -> 3 B; t1: A + B -> C
    n.initial = {0, 0, 0};
    n.fed = {true, false, false};
    plant::petri::Transition t0, t1;
    t0.in = {{0, 2}};
    t0.out = {{1, 3}};
    t1.in = {{0, 1}, {1, 1}};
    t1.out = {{2, 1}};
    n.transitions = {t0, t1};

    CHECK(step(n, {1, 0, 0}, {}) == std::vector<int>{1, 0, 0});      // 1 < weight 2
    CHECK(step(n, {1, 0, 0}, {1, 0, 0}) == std::vector<int>{0, 3, 0});  // the put enables t0
    CHECK(step(n, {3, 0, 0}, {}) == std::vector<int>{1, 3, 0});
    // Both fire on {A=2, B=1}: A loses 2+1 but clamps at 0; B loses 1 and gains 3.
    CHECK(step(n, {2, 1, 0}, {}) == std::vector<int>{0, 3, 1});
    CHECK(step(n, {5, 2, 0}, {1, 0, 0}) == std::vector<int>{3, 4, 1});
    CHECK(enabled(n, {2, 1, 0}) == std::vector<int>{0, 1});
}

TEST_CASE("petri: a forward conflict fires both consumers of one token") {
    Net n;  // A -> B and A -> C
    n.initial = {1, 0, 0};
    n.fed = {false, false, false};
    n.transitions = {tr({0}, {1}), tr({0}, {2})};
    CHECK(step(n, n.initial, {}) == std::vector<int>{0, 1, 1});
    Report r = analyse(n);
    CHECK(r.complete);
    CHECK(r.unbounded.empty());
    CHECK(r.dead.empty());
}

TEST_CASE("petri: the track switch neither accumulates nor has dead transitions") {
    Report r = analyse(track_switch(true));
    CHECK(r.complete);
    CHECK(r.unbounded.empty());
    CHECK(r.dead.empty());
}

TEST_CASE("petri: without its draining transitions the switch accumulates MoveTo tokens") {
    Report r = analyse(track_switch(false));
    CHECK(r.complete);
    REQUIRE(r.unbounded == std::vector<int>{MoveToBasePos, MoveToWorkingPos});
    REQUIRE(r.unbounded_why.size() == 2);
    INFO(r.unbounded_why[0]);
    INFO(r.unbounded_why[1]);
    CHECK(r.unbounded_why[0].find("fed by a flow") == 0);
    CHECK(r.unbounded_why[0].find("no transition consumes it") != std::string::npos);
    CHECK(r.unbounded_why[1].find("'WorkingPos'") != std::string::npos);
    CHECK(r.unbounded_why[1].find("'tw' also needs 'BasePos'") != std::string::npos);
    CHECK(r.dead.empty());
}

TEST_CASE("petri: a transition needing more tokens than a place ever holds is dead") {
    Net n;  // A fed; t0: A -> B (drains every put at once); t1: 2 A -> C; t2: B ->
    n.initial = {0, 0, 0};
    n.fed = {true, false, false};
    plant::petri::Transition heavy;
    heavy.in = {{0, 2}};
    heavy.out = {{2, 1}};
    n.transitions = {tr({0}, {1}), heavy, tr({1}, {})};
    Report r = analyse(n);
    CHECK(r.complete);
    CHECK(r.unbounded.empty());
    CHECK(r.dead == std::vector<int>{1});
}

TEST_CASE("petri: a weight-2 drain bounds a fed place (no false accumulation)") {
    Net n;  // A fed, t: 2 A -> ; A stays within {0, 1} between steps
    n.initial = {0};
    n.fed = {true};
    plant::petri::Transition t;
    t.in = {{0, 2}};
    n.transitions = {t};
    Report r = analyse(n);
    CHECK(r.complete);
    CHECK(r.unbounded.empty());
    CHECK(r.dead.empty());
}

TEST_CASE("petri: a producer loop makes its output unbounded") {
    Net n;  // t: A -> A + B
    n.initial = {1, 0};
    n.fed = {false, false};
    n.transitions = {tr({0}, {0, 1})};
    n.transition_names = {"t"};
    Report r = analyse(n);
    CHECK(r.complete);
    REQUIRE(r.unbounded == std::vector<int>{1});
    CHECK(r.unbounded_why[0] ==
          "produced by 't'; when 'p0' is marked no transition consumes it");
    CHECK(r.dead.empty());
}

TEST_CASE("petri: an unfed net with nothing enabled is quiet but dead") {
    Net n;  // A + B -> C with only A marked
    n.initial = {1, 0, 0};
    n.fed = {false, false, false};
    n.transitions = {tr({0, 1}, {2})};
    Report r = analyse(n);
    CHECK(r.complete);
    CHECK(r.unbounded.empty());
    CHECK(r.dead == std::vector<int>{0});
}

TEST_CASE("petri: hitting the exploration limit reports no dead transitions") {
    // Ten fed places, each drained by a weight-3 transition: 3^10 bounded markings,
    // explored with the reduced environment set (none, all, each alone).
    Net n;
    n.initial.assign(10, 0);
    n.fed.assign(10, true);
    for (int p = 0; p < 10; ++p) {
        plant::petri::Transition t;
        t.in = {{p, 3}};
        n.transitions.push_back(t);
    }
    plant::petri::Transition never;  // needs a token on a place that never gets one
    never.in = {{0, 1}, {9, 5}};
    n.transitions.push_back(never);

    Report r = analyse(n, 200);
    CHECK_FALSE(r.complete);
    CHECK(r.dead.empty());
    CHECK(r.unbounded.empty());
}

TEST_CASE("petri: an unbounded place is still reported when the limit is hit") {
    Net n;  // A fed, never consumed; B fed, drained only at 1000 tokens: too many markings
    n.initial = {0, 0};
    n.fed = {true, true};
    plant::petri::Transition t;
    t.in = {{1, 1000}};
    n.transitions = {t};
    Report r = analyse(n, 50);
    CHECK_FALSE(r.complete);
    CHECK(r.unbounded == std::vector<int>{0});
    CHECK(r.dead.empty());
}
