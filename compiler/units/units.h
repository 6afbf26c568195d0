// Physical dimensions and units. A quantity is an SI value plus a dimension: the
// exponents of length, mass, time and angle. Angle is kept as its own base so that
// `90 deg` cannot be used where a length is wanted, even though SI calls it 1.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace plant::units {

// Each exponent lies within ±kMaxExponent (kept in 8 bits): the checked operations below
// refuse a result outside it, where the plain ones would wrap.
constexpr int kMaxExponent = 99;

struct Dim {
    int8_t L = 0, M = 0, T = 0, A = 0;
    friend bool operator==(const Dim&, const Dim&) = default;
    Dim operator*(Dim o) const {
        return {int8_t(L + o.L), int8_t(M + o.M), int8_t(T + o.T), int8_t(A + o.A)};
    }
    Dim operator/(Dim o) const {
        return {int8_t(L - o.L), int8_t(M - o.M), int8_t(T - o.T), int8_t(A - o.A)};
    }
    Dim pow(int n) const { return {int8_t(L * n), int8_t(M * n), int8_t(T * n), int8_t(A * n)}; }
    bool none() const { return L == 0 && M == 0 && T == 0 && A == 0; }

    // The exponents given, or nothing when one leaves ±kMaxExponent.
    static std::optional<Dim> of(long l, long m, long t, long a) {
        for (long e : {l, m, t, a})
            if (e < -kMaxExponent || e > kMaxExponent) return std::nullopt;
        return Dim{int8_t(l), int8_t(m), int8_t(t), int8_t(a)};
    }
    std::optional<Dim> times(Dim o) const { return of(long(L) + o.L, long(M) + o.M, long(T) + o.T, long(A) + o.A); }
    std::optional<Dim> over(Dim o) const { return of(long(L) - o.L, long(M) - o.M, long(T) - o.T, long(A) - o.A); }
    std::optional<Dim> power(long n) const { return of(L * n, M * n, T * n, A * n); }
};

namespace dims {
constexpr Dim none{};
constexpr Dim length{1, 0, 0, 0};
constexpr Dim mass{0, 1, 0, 0};
constexpr Dim time{0, 0, 1, 0};
constexpr Dim angle{0, 0, 0, 1};
constexpr Dim velocity{1, 0, -1, 0};
constexpr Dim acceleration{1, 0, -2, 0};
constexpr Dim frequency{0, 0, -1, 0};
constexpr Dim force{1, 1, -2, 0};
constexpr Dim angular_velocity{0, 0, -1, 1};
constexpr Dim gain{0, 1, -1, 0};  // conveyor gain k: N per (m/s) = kg/s
constexpr Dim area{2, 0, 0, 0};
constexpr Dim volume{3, 0, 0, 0};
constexpr Dim inertia{2, 1, 0, 0};  // kg·m²
}  // namespace dims

// "velocity", or a formula such as "length^2/time" for unnamed dimensions.
std::string dim_name(Dim d);
// The SI unit text of a dimension, e.g. "m/s", "kg/s", "1".
std::string si_unit(Dim d);

struct Unit {
    double mul;  // SI value of 1 unit is mul / div: kept apart so that 50 cm is 50 / 100,
    double div;  // one correctly rounded division instead of a product with 0.01
    Dim dim;
    double si(double x) const { return x * mul / div; }
};

// Parses a unit written after a number: "cm", "cm/s", "m/s^2", "N*s/m", "deg/s".
// Returns nothing for an unknown atom, `bad_atom` then names it, or for an exponent outside
// ±kMaxExponent (written, or reached by the unit's product), `bad_exponent` then says so.
std::optional<Unit> parse_unit(std::string_view text, std::string* bad_atom = nullptr, bool* bad_exponent = nullptr);
std::vector<std::string> unit_atoms();

// Parameter type names that are dimensions: "length", "velocity", "gain", "real" ...
std::optional<Dim> dim_of_type(std::string_view type_name);
std::vector<std::string> dimension_type_names();

}  // namespace plant::units
