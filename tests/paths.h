#pragma once
// Where this checkout and its standard library are, for tests that read the tree's files.
// Defined in one file that CMake generates (tests/paths.cpp.in), not as a -D on every test
// file, so that ccache shares the compiled tests between clones in different folders.

namespace plant::test {
extern const char* const source_dir;
extern const char* const stdlib_dir;
}  // namespace plant::test

#define PLANT_SOURCE_DIR (::plant::test::source_dir)
#define PLANT_STDLIB_DIR (::plant::test::stdlib_dir)
