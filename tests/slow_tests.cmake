# Read by ctest after the doctest cases are discovered (TEST_INCLUDE_FILES): the slowest of
# them start first, beside the short ones, instead of last (ctest starts the highest COST
# first, and a fresh clone has no timings of its own). Seconds in the asan build, 2026-11-27.
# The slow tests that are not doctest cases get their COST in tests/CMakeLists.txt.
foreach(slow
    "stdlib: a sorting line fed twice as fast as its filling station loses no bottle in 600 s=67"
    "stdlib: a line fed every 0.7 s into a separator that passes one a second loses no bottle in 600 s=70"
    "validate: every golden graph, damaged in each way the compiler guards, is refused=54"
    "soak: the bottling plant for a simulated hour=35"
    "steady transport: the bottling plant over 600 s counts, routes and commissions the same bottles on and off=12"
    "faults: a drill in the plant file runs as its --event lines do=13"
    "std.separator: 12 touching bottles held for 120 s stay on the band, none lost, then one passes per cycle=11"
    "serve: a plant's scheduled faults apply as plant run applies them=6"
    "plants/bottling.plant: bottles are filled, capped and commissioned in the lane of their code=5")
  string(FIND "${slow}" "=" at REVERSE)
  string(SUBSTRING "${slow}" 0 ${at} name)
  math(EXPR at "${at} + 1")
  string(SUBSTRING "${slow}" ${at} -1 seconds)
  set_tests_properties("${name}" PROPERTIES COST ${seconds})  # a name no longer there is ignored
endforeach()
# The OPC UA server's bad clients (tests/unit/opcua/robustness_test.cpp) keep the plant paced to
# the wall clock: label wallclock, as the real-time PLC run.
foreach(name "opcua robustness: malformed chunks, unknown services and nodes, read-only writes, clients gone"
             "opcua robustness: 50 clients at once, each with a session, reads and a subscription"
             "opcua robustness: a flood of reads for 3 s")
  set_tests_properties("${name}" PROPERTIES LABELS wallclock COST 15)  # a name not there is ignored
endforeach()
