# Run after a test executable is built (rdv_test_in_one_process, tests/CMakeLists.txt): lists
# its tests and writes the ctest file that declares them, as gtest_discover_tests does, but with
# the executable run once for all of them (gtest_family.py):
#   EXE_NAME  the executable's test, which runs all of them and writes REPORT
#   Suite.Name  one per test, its verdict read from REPORT
# Variables: EXE, EXE_NAME, LABEL, REPORT, PYTHON, SCRIPT, OUT.
execute_process(COMMAND "${EXE}" --gtest_list_tests OUTPUT_VARIABLE listing RESULT_VARIABLE code)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "${EXE} --gtest_list_tests failed (${code})")
endif()
set(fixture "gtest_${EXE_NAME}")
set(text "add_test([=[${EXE_NAME}]=] \"${PYTHON}\" \"${SCRIPT}\" run \"${EXE}\" \"${REPORT}\")\n")
string(APPEND text "set_tests_properties([=[${EXE_NAME}]=] PROPERTIES LABELS ${LABEL} TIMEOUT 1500 FIXTURES_SETUP ${fixture})\n")
string(REPLACE "\n" ";" lines "${listing}")
set(suite "")
foreach(line IN LISTS lines)
  if(line MATCHES "^([A-Za-z0-9_]+)\\.")
    set(suite "${CMAKE_MATCH_1}")
  elseif(line MATCHES "^  ([A-Za-z0-9_]+)" AND suite)
    set(test "${suite}.${CMAKE_MATCH_1}")
    string(APPEND text "add_test([=[${test}]=] \"${PYTHON}\" \"${SCRIPT}\" show \"${REPORT}\" [=[${test}]=])\n")
    string(APPEND text "set_tests_properties([=[${test}]=] PROPERTIES LABELS ${LABEL} TIMEOUT 30 FIXTURES_REQUIRED ${fixture})\n")
  endif()
endforeach()
file(WRITE "${OUT}" "${text}")
