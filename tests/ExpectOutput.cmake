# Script mode: runs COMMAND with ARGS ("|"-separated) and checks its exit code (EXPECT_RC) and
# that its output, stdout and stderr together, matches EXPECT_REGEX. With EXPECT_NO_FILE, that
# path must not exist afterwards (a failed run leaves no partial output); it is removed first.
if(DEFINED EXPECT_NO_FILE)
  file(REMOVE ${EXPECT_NO_FILE})
endif()
string(REPLACE "|" ";" args "${ARGS}")
execute_process(COMMAND ${COMMAND} ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc STREQUAL "${EXPECT_RC}")
  message(FATAL_ERROR "exit code ${rc}, expected ${EXPECT_RC}\nstdout:\n${out}\nstderr:\n${err}")
endif()
if(NOT "${out}${err}" MATCHES "${EXPECT_REGEX}")
  message(FATAL_ERROR "output does not match '${EXPECT_REGEX}'\nstdout:\n${out}\nstderr:\n${err}")
endif()
if(DEFINED EXPECT_NO_FILE AND EXISTS ${EXPECT_NO_FILE})
  message(FATAL_ERROR "${EXPECT_NO_FILE} was written although the command failed")
endif()
