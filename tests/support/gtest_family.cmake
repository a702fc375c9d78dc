# Run after a test executable is built (rdv_test_in_one_process, rdv_test_per_suite:
# tests/CMakeLists.txt): lists its tests and writes the ctest file that declares them, as
# gtest_discover_tests does, with the executable run once for all of them, or once per suite
# (gtest_family.py):
#   EXE_NAME (or EXE_NAME/Suite per suite)  runs the tests and writes the report
#   Suite.Name  one per test, its verdict read from the report
# Variables: EXE, EXE_NAME, LABEL, REPORTS (a directory), PYTHON, SCRIPT, OUT, PER_SUITE.
execute_process(COMMAND "${EXE}" --gtest_list_tests OUTPUT_VARIABLE listing RESULT_VARIABLE code)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "${EXE} --gtest_list_tests failed (${code})")
endif()
set(text "")
macro(add_runner name report fixture)
  string(APPEND text "add_test([=[${name}]=] \"${PYTHON}\" \"${SCRIPT}\" run \"${EXE}\" \"${report}\" ${ARGN})\n")
  string(APPEND text "set_tests_properties([=[${name}]=] PROPERTIES LABELS ${LABEL} TIMEOUT 1500 FIXTURES_SETUP ${fixture})\n")
endmacro()
if(NOT PER_SUITE)
  set(report "${REPORTS}/${EXE_NAME}.json")
  set(fixture "gtest_${EXE_NAME}")
  add_runner("${EXE_NAME}" "${report}" "${fixture}")
endif()
string(REPLACE "\n" ";" lines "${listing}")
set(suite "")
foreach(line IN LISTS lines)
  if(line MATCHES "^([A-Za-z0-9_]+)\\.")
    set(suite "${CMAKE_MATCH_1}")
    if(PER_SUITE)
      set(report "${REPORTS}/${EXE_NAME}/${suite}.json")
      set(fixture "gtest_${EXE_NAME}_${suite}")
      add_runner("${EXE_NAME}/${suite}" "${report}" "${fixture}" "[=[${suite}.*]=]")
    endif()
  elseif(line MATCHES "^  ([A-Za-z0-9_]+)" AND suite)
    set(test "${suite}.${CMAKE_MATCH_1}")
    string(APPEND text "add_test([=[${test}]=] \"${PYTHON}\" \"${SCRIPT}\" show \"${report}\" [=[${test}]=])\n")
    string(APPEND text "set_tests_properties([=[${test}]=] PROPERTIES LABELS ${LABEL} TIMEOUT 30 FIXTURES_REQUIRED ${fixture})\n")
  endif()
endforeach()
file(WRITE "${OUT}" "${text}")
