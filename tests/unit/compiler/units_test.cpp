#include "units/units.h"

#include <cmath>
#include <doctest/doctest.h>
#include <numbers>

using namespace plant::units;

TEST_CASE("units: atoms and compounds convert to SI") {
    auto cm = parse_unit("cm");
    REQUIRE(cm);
    CHECK(cm->si(50) == doctest::Approx(0.5));
    CHECK(cm->dim == dims::length);

    auto v = parse_unit("cm/s");
    REQUIRE(v);
    CHECK(v->si(50) == doctest::Approx(0.5));
    CHECK(v->dim == dims::velocity);

    auto a = parse_unit("m/s^2");
    REQUIRE(a);
    CHECK(a->dim == dims::acceleration);

    auto k = parse_unit("N*s/m");
    REQUIRE(k);
    CHECK(k->dim == dims::gain);
    CHECK(parse_unit("kg/s")->dim == dims::gain);

    auto deg = parse_unit("deg");
    REQUIRE(deg);
    CHECK(deg->si(180) == doctest::Approx(std::numbers::pi));
    CHECK(parse_unit("Hz")->dim == dims::frequency);
    CHECK(parse_unit("g")->si(80) == doctest::Approx(0.08));
    CHECK(parse_unit("ms")->si(400) == doctest::Approx(0.4));
    CHECK(parse_unit("m^-1")->dim == dims::length.pow(-1));
}

TEST_CASE("units: unknown atoms are named") {
    std::string bad;
    CHECK_FALSE(parse_unit("cm/sec", &bad));
    CHECK(bad == "sec");
    CHECK_FALSE(parse_unit("m^", &bad));
}

TEST_CASE("units: dimension names") {
    CHECK(dim_name(dims::velocity) == "velocity");
    CHECK(dim_name(dims::none) == "dimensionless");
    CHECK(dim_name(dims::length.pow(2) / dims::time) == "length^2/time");
    CHECK(si_unit(dims::gain) == "kg/s");
    CHECK(dim_of_type("force") == dims::force);
    CHECK_FALSE(dim_of_type("speed"));
}
