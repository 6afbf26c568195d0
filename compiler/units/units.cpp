#include "units/units.h"

#include <array>
#include <cmath>
#include <numbers>

namespace plant::units {
namespace {

struct Atom {
    std::string_view name;
    double scale;  // below 1 stored as 1 / (1 / scale), see Unit
    Dim dim;
    double div() const { return scale < 1 ? std::round(1.0 / scale) == 1.0 / scale ? 1.0 / scale : 1.0 : 1.0; }
    double mul() const { return scale < 1 && div() != 1.0 ? 1.0 : scale; }
};

constexpr double kDeg = std::numbers::pi / 180.0;

constexpr std::array kAtoms = {
    Atom{"m", 1, dims::length},       Atom{"cm", 0.01, dims::length},
    Atom{"mm", 0.001, dims::length},  Atom{"km", 1e3, dims::length},
    Atom{"um", 0.000001, dims::length},   Atom{"kg", 1, dims::mass},
    Atom{"g", 1e-3, dims::mass},      Atom{"mg", 1e-6, dims::mass},
    Atom{"t", 1e3, dims::mass},       Atom{"s", 1, dims::time},
    Atom{"ms", 1e-3, dims::time},     Atom{"us", 1e-6, dims::time},
    Atom{"min", 60, dims::time},      Atom{"h", 3600, dims::time},
    Atom{"deg", kDeg, dims::angle},   Atom{"rad", 1, dims::angle},
    Atom{"Hz", 1, dims::frequency},   Atom{"kHz", 1e3, dims::frequency},
    Atom{"rpm", 2 * std::numbers::pi / 60.0, dims::angular_velocity},
    Atom{"N", 1, dims::force},        Atom{"kN", 1e3, dims::force},
    Atom{"mN", 1e-3, dims::force},
};

struct Named {
    std::string_view name;
    Dim dim;
};

// Order matters for dim_name: the first name of a dimension is the one printed.
constexpr std::array kNamed = {
    Named{"real", dims::none},
    Named{"length", dims::length},
    Named{"mass", dims::mass},
    Named{"time", dims::time},
    Named{"angle", dims::angle},
    Named{"velocity", dims::velocity},
    Named{"acceleration", dims::acceleration},
    Named{"frequency", dims::frequency},
    Named{"force", dims::force},
    Named{"angular_velocity", dims::angular_velocity},
    Named{"gain", dims::gain},
    Named{"area", dims::area},
    Named{"volume", dims::volume},
    Named{"inertia", dims::inertia},
};

const Atom* find_atom(std::string_view name) {
    for (const auto& a : kAtoms)
        if (a.name == name) return &a;
    return nullptr;
}

void append_factor(std::string& out, std::string_view base, int exp) {
    if (exp == 0) return;
    if (!out.empty()) out += '*';
    out += base;
    if (exp == 1) return;
    out += '^';
    out += std::to_string(exp);
}

// "a*b^2/c" from the four base names, or "1/..." without a numerator.
std::string quotient(Dim d, const std::array<std::string_view, 4>& base) {
    std::string num, den;
    const std::array<int, 4> exps = {d.L, d.M, d.T, d.A};
    for (size_t i = 0; i < exps.size(); ++i) {
        if (exps[i] > 0) append_factor(num, base[i], exps[i]);
        if (exps[i] < 0) append_factor(den, base[i], -exps[i]);
    }
    if (num.empty()) num.push_back('1');  // (push_back: GCC 12 warns -Wrestrict on assign)
    if (!den.empty()) {
        num += '/';
        num += den;
    }
    return num;
}

}  // namespace

std::string dim_name(Dim d) {
    if (d.none()) return "dimensionless";
    for (const auto& n : kNamed)
        if (n.dim == d) return std::string(n.name);
    return quotient(d, {"length", "mass", "time", "angle"});
}

std::string si_unit(Dim d) {
    if (d == dims::force) return "N";
    if (d == dims::frequency) return "Hz";
    return quotient(d, {"m", "kg", "s", "rad"});
}

std::optional<Unit> parse_unit(std::string_view text, std::string* bad_atom, bool* bad_exponent) {
    auto too_large = [&] {
        if (bad_exponent) *bad_exponent = true;
        if (bad_atom) *bad_atom = std::string(text);
        return std::nullopt;
    };
    Unit result{1.0, 1.0, dims::none};
    int sign = 1;  // +1 before the first '/', -1 after it
    size_t i = 0;
    while (i < text.size()) {
        size_t j = i;
        while (j < text.size() && text[j] != '*' && text[j] != '/' && text[j] != '^') ++j;
        std::string_view atom_text = text.substr(i, j - i);
        int exp = 1;
        if (j < text.size() && text[j] == '^') {
            size_t k = j + 1;
            bool neg = k < text.size() && text[k] == '-';
            if (neg) ++k;
            int e = 0;
            size_t digits = k;
            while (k < text.size() && text[k] >= '0' && text[k] <= '9') {
                e = e * 10 + (text[k++] - '0');
                if (e > kMaxExponent) return too_large();  // before int overflows, too
            }
            if (k == digits) {
                if (bad_atom) *bad_atom = std::string(text);
                return std::nullopt;
            }
            exp = neg ? -e : e;
            j = k;
        }
        const Atom* atom = find_atom(atom_text);
        if (!atom) {
            if (bad_atom) *bad_atom = std::string(atom_text);
            return std::nullopt;
        }
        int e = sign * exp;
        // Degrees are pi/180: keep pi in mul and 180 in div.
        double am = atom->name == "deg" ? std::numbers::pi : atom->mul();
        double ad = atom->name == "deg" ? 180.0 : atom->div();
        if (e > 0) {
            result.mul *= std::pow(am, e);
            result.div *= std::pow(ad, e);
        } else {
            result.mul *= std::pow(ad, -e);
            result.div *= std::pow(am, -e);
        }
        const std::optional<Dim> power = atom->dim.power(e);
        const std::optional<Dim> dim = power ? result.dim.times(*power) : std::nullopt;
        if (!dim) return too_large();
        result.dim = *dim;
        if (j < text.size()) {
            if (text[j] == '/') sign = -1;
            ++j;
        }
        i = j;
    }
    return result;
}

std::vector<std::string> unit_atoms() {
    std::vector<std::string> out;
    for (const auto& a : kAtoms) out.emplace_back(a.name);
    return out;
}

std::optional<Dim> dim_of_type(std::string_view type_name) {
    for (const auto& n : kNamed)
        if (n.name == type_name) return n.dim;
    return std::nullopt;
}

std::vector<std::string> dimension_type_names() {
    std::vector<std::string> out;
    for (const auto& n : kNamed) out.emplace_back(n.name);
    return out;
}

}  // namespace plant::units
