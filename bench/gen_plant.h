// Generator of synthetic plant files for the compiler-scaling benchmark.
//
// Every generated plant holds N instances of one small object type, `Cell`: a static
// physics body with a box shape, a trigger on that body, a one-shot timer, a state net
// with two places and one transition, two ports and two internal flows. Neighbouring
// cells are chained (`cell[i].done -> cell[i + 1].start`), and the cells are laid out
// on a grid of `cols` columns, 30 cm apart.
//
// Two forms of the same plant:
//   Loop  `for` loops inside the plant: the source stays ~40 lines whatever N is, so
//         the cost is all in elaboration.
//   Flat  every instance and every neighbour flow written out on its own line
//         (`cell[17]: Cell at (...)`), so the parser sees ~2N lines too.
// Both lower to the same graph (same DOs, components, slots and flows); only source
// positions and the last bit of some poses differ (0.3 * 3 vs 90 cm).
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <string_view>

namespace plant::bench {

enum class Form { Loop, Flat };

std::string_view form_name(Form f);
bool parse_form(std::string_view s, Form& f);

struct GenStats {
    int64_t lines = 0;
    int64_t bytes = 0;
};

// Writes the plant with `instances` cells (>= 1) to `out`.
GenStats generate_plant(std::ostream& out, int64_t instances, Form form, int64_t cols = 100);

// As generate_plant, into the file `path`; false if it cannot be written.
bool write_plant_file(const std::string& path, int64_t instances, Form form, GenStats& stats,
                      int64_t cols = 100);

}  // namespace plant::bench
