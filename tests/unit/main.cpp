#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include "plc/kind.h"

int main(int argc, char** argv) {
    plant::plc::register_modbus_kind();  // the plugin kinds this program has (docs/architecture.md)
    return doctest::Context(argc, argv).run();
}
