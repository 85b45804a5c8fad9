# Runs `statepack inspect --json ARCHIVE` and fails unless its output equals the file EXPECTED.
# Regenerate after an intended format change: statepack inspect --json ARCHIVE > EXPECTED
execute_process(COMMAND ${STATEPACK} inspect --json ${ARCHIVE} OUTPUT_VARIABLE actual RESULT_VARIABLE code)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "statepack inspect --json ${ARCHIVE} failed (${code})")
endif()
file(READ ${EXPECTED} expected)
if(NOT actual STREQUAL expected)
  message(FATAL_ERROR "${ARCHIVE} no longer decodes to ${EXPECTED}; if the format change is intended, "
                      "regenerate it: statepack inspect --json ${ARCHIVE} > ${EXPECTED}")
endif()
