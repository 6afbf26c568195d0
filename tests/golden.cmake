# Golden-file tests (see tests/golden_runner.cpp). Update with scripts/update-goldens.sh.
add_executable(plant_golden ${CMAKE_CURRENT_SOURCE_DIR}/golden_runner.cpp)
target_compile_options(plant_golden PRIVATE ${PLANT_WARNINGS})
target_link_libraries(plant_golden PRIVATE plant_compiler plant_runtime plant_plc plant_opcua plant_faults plant_panel plant_app)
add_test(NAME golden COMMAND plant_golden ${CMAKE_CURRENT_SOURCE_DIR}/golden)
set_tests_properties(golden PROPERTIES ENVIRONMENT "PLANT_STDLIB=${PLANT_STDLIB_DIR}")
# The shipped plants' compiled graphs: plants/**/NAME.plant -> tests/plants/**/NAME.graph.
add_test(NAME golden_plants COMMAND plant_golden --sources=${CMAKE_SOURCE_DIR}/plants ${CMAKE_CURRENT_SOURCE_DIR}/plants)
set_tests_properties(golden_plants PROPERTIES ENVIRONMENT "PLANT_STDLIB=${PLANT_STDLIB_DIR}")

# Every example compiles without errors, and its graph renders with dot when available.
file(GLOB PLANT_EXAMPLES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/examples/*.plant)
foreach(example ${PLANT_EXAMPLES})
  get_filename_component(name ${example} NAME_WE)
  add_test(NAME example_check_${name} COMMAND plant check ${example})
endforeach()

find_program(DOT_TOOL dot)
file(GLOB PLANT_SHIPPED CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/plants/*.plant)
if(DOT_TOOL)
  foreach(plant_file ${PLANT_SHIPPED})
    get_filename_component(name ${plant_file} NAME_WE)
    add_test(NAME plant_dot_${name}
             COMMAND bash -o pipefail -c "\"$<TARGET_FILE:plant>\" graph \"${plant_file}\" | \"${DOT_TOOL}\" -Tsvg -o /dev/null")
  endforeach()
  foreach(example ${PLANT_EXAMPLES})
    get_filename_component(name ${example} NAME_WE)
    add_test(NAME example_dot_${name}
             COMMAND bash -o pipefail -c "\"$<TARGET_FILE:plant>\" graph \"${example}\" | \"${DOT_TOOL}\" -Tsvg -o /dev/null")
  endforeach()
endif()

# docs/language.md's slot tables match the slot declarations (graph/kinds.h).
add_executable(plant_slot_docs ${CMAKE_CURRENT_SOURCE_DIR}/slot_docs.cpp)
target_compile_options(plant_slot_docs PRIVATE ${PLANT_WARNINGS})
target_link_libraries(plant_slot_docs PRIVATE plant_compiler plant_panel)  # the panel kinds have slots
add_test(NAME slot_tables_doc COMMAND plant_slot_docs ${CMAKE_SOURCE_DIR}/docs/language.md)
