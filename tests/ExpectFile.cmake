# Script mode: checks that FILE exists and that its contents match EXPECT_REGEX.
if(NOT EXISTS ${FILE})
  message(FATAL_ERROR "${FILE} does not exist")
endif()
file(READ ${FILE} contents)
if(NOT contents MATCHES "${EXPECT_REGEX}")
  message(FATAL_ERROR "${FILE} does not match '${EXPECT_REGEX}':\n${contents}")
endif()
