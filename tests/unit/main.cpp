#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include "faults/kind.h"
#include "faults/operable.h"
#include "opcua/kind.h"
#include "panel/kind.h"
#include "plc/kind.h"

int main(int argc, char** argv) {
    plant::plc::register_modbus_kind();  // the plugin kinds this program has (docs/architecture.md)
    plant::opcua::register_opcua_kind();
    plant::faults::register_faults_kind();
    plant::panel::register_panel_kinds();
    plant::faults::register_operable_kind();
    return doctest::Context(argc, argv).run();
}
