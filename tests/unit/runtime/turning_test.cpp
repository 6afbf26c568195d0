// A turning field (a field's radius and pivot, docs/semantics.md §2): its target at a body's
// centre of mass p is (speed/radius)·ẑ × (p − pivot), so a body on a frictionless floor in it
// moves on a circle about the pivot, at speed·r/radius at r from it, with no rail.
#include "engine/engine.h"
#include "engine/runtime.h"
#include "scene_builder.h"

#include <doctest/doctest.h>

#include <cmath>

using namespace plant::test;
using plant::engine::Engine;

TEST_CASE("runtime: a turning field carries a body round its pivot at its speed times r over its radius") {
    const double radius = 0.3, speed = 0.5;
    for (const double r : {0.3, 0.15}) {
        SceneBuilder b;
        b.body(0, "floor", BodyMode::Static, {box({4, 4, 0.2})}, 0, at(0, 0, -0.1));
        // Its box's centre is 10 cm from its pivot: the pivot is given in the field's frame.
        const int32_t f = b.field(0, "turn", {2, 2, 0.5}, at(0.1, 0, 0.25), {1, 0, 0}, speed, 16);
        b.g.fields[plant::graph::FieldId(f)].radius = radius;
        b.g.fields[plant::graph::FieldId(f)].pivot = {-0.1, 0, 0};
        const int32_t cube =
            b.body(b.dobj("cube"), "body", BodyMode::Dynamic, {box({0.04, 0.04, 0.04})}, 0.04, at(r, 0, 0.02));
        Engine e(b.g);
        const double dt = e.internals().dt;
        const plant::graph::BodyId id(cube);
        double nearest = r, farthest = r, angle = 0, last = 0;
        for (int i = 0; i < 150 * 2; ++i) {
            e.step();
            const plant::graph::Vec3 c = e.body_com(id), v = e.body_velocity(id);
            const double d = std::hypot(c[0], c[1]);
            nearest = std::min(nearest, d);
            farthest = std::max(farthest, d);
            const double a = std::atan2(c[1], c[0]);
            angle += std::remainder(a - last, 2 * M_PI);
            last = a;
            if (i >= 150) {  // settled: along the circle, at its speed there
                // A step moves it along a chord, the tangent in the middle of the step.
                const double mx = c[0] - v[0] * dt / 2, my = c[1] - v[1] * dt / 2, md = std::hypot(mx, my);
                const double tangential = (-my * v[0] + mx * v[1]) / md, radial = (mx * v[0] + my * v[1]) / md;
                CHECK(tangential == doctest::Approx(speed * md / radius).epsilon(0.01));
                CHECK(std::abs(radial) < 0.002 * speed);  // 1 mm/s: it keeps to its circle
            }
        }
        MESSAGE("r " << r << ": from " << nearest << " to " << farthest << " m from the pivot, turned " << angle << " rad");
        CHECK(nearest > r - 1e-3);         // it is not pulled in
        CHECK(farthest < r + 0.002 * r / radius);  // 2 mm at 30 cm: it keeps to its circle
        // Anticlockwise at speed / radius rad/s (less the first steps' speeding up): 2 s.
        CHECK(angle == doctest::Approx(2 * speed / radius).epsilon(0.03));
    }
}
