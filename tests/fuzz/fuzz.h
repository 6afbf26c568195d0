// Fuzz targets (docs/testing.md, "Fuzzing"): each file defines the libFuzzer entry point
//   extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);
// and states its invariant. Built two ways from the same source: with clang's libFuzzer
// (scripts/fuzz.sh: coverage-guided campaigns) and with driver.cpp (every build: the
// bounded runs of the test suite, under ASan + UBSan in the asan build).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

namespace plant::fuzz {

inline std::string_view text(const uint8_t* data, size_t size) {
    return {reinterpret_cast<const char*>(data), size};
}

// An invariant broken: print what and abort, so both drivers report the input.
[[noreturn]] inline void broken(const char* what) {
    std::fprintf(stderr, "fuzz invariant broken: %s\n", what);
    std::abort();
}

}  // namespace plant::fuzz
