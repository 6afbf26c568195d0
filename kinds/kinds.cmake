# The component kinds on the kind table that ship with plant (docs/architecture.md, "The
# kind table"), in the order their start and sense hooks run: the body first (its sensing
# takes out what left the world before any kind looks), the field's start first (its outputs
# were published before every other kind's), the graphics before the rest (a gripper
# follows a graphics' pose of this step), the trigger before the gripper and the exit, which
# work on what it found inside; the exit after the gripper moved what it holds; the state
# last (its places publish their tokens after the other kinds' start, as they did); the
# connector, with no hooks (a node of the logic network), after them. Each is
# a folder kinds/NAME:
#   graph.h   its fixed slots and graph record's fields (the graph contract)
#   kind.cpp  its descriptor row: word, modes, parameters, table, loader check, docs (plant_graph)
#   lower.cpp its lowering into the graph (plant_compiler)
#   run.cpp   its behaviour: state, start, sense, act (plant_runtime)
# Adding one is its folder and its word here; kinds/list.h, generated from this list, is
# how graph/, the compiler and the runtime find the rows.
set(PLANT_KINDS body field graphics trigger constraint timer gripper exit source label state router logic)

set(PLANT_KINDS_GENERATED ${CMAKE_BINARY_DIR}/generated)
set(plant_kind_includes "")
set(plant_kind_list "")
foreach(k ${PLANT_KINDS})
  string(TOUPPER ${k} upper)
  string(APPEND plant_kind_includes "#include \"kinds/${k}/graph.h\"\n")
  string(APPEND plant_kind_list " K(${k}, ${upper})")
endforeach()
set(PLANT_KIND_INCLUDES "${plant_kind_includes}")
set(PLANT_KIND_LIST "${plant_kind_list}")
configure_file(${CMAKE_CURRENT_LIST_DIR}/list.h.in ${PLANT_KINDS_GENERATED}/kinds/list.h @ONLY)

# The sources one side adds for every kind: plant_kind_sources(plant_graph kind.cpp).
function(plant_kind_sources target file)
  foreach(k ${PLANT_KINDS})
    target_sources(${target} PRIVATE ${CMAKE_SOURCE_DIR}/kinds/${k}/${file})
  endforeach()
endfunction()
