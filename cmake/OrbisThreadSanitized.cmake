# orbis_thread_sanitized_copy(target [REPLACE library copy ...]): ${target}_tsan, a static library of
# the target's sources, include directories and libraries compiled under ThreadSanitizer, for the
# threading tests (tests/CMakeLists.txt: ctest -L tsan). Called where the target is made, so that
# its sources' properties (core's -ffp-contract=off) hold for the copy too. REPLACE pairs name the
# libraries linked as their own copies (world links core's). Only in trees that build the tests
# without sanitizers of their own: TSan cannot share a process with ASan.
function(orbis_thread_sanitized_copy target)
  if(NOT ORBIS_BUILD_TESTS OR ORBIS_SANITIZE)
    return()
  endif()
  cmake_parse_arguments(ARG "" "" "REPLACE" ${ARGN})
  set(copy ${target}_tsan)
  get_target_property(sources ${target} SOURCES)
  add_library(${copy} STATIC ${sources})
  target_include_directories(${copy}
    PUBLIC $<TARGET_PROPERTY:${target},INTERFACE_INCLUDE_DIRECTORIES>
    PRIVATE $<TARGET_PROPERTY:${target},INCLUDE_DIRECTORIES>)
  get_target_property(libraries ${target} LINK_LIBRARIES)
  set(replace ${ARG_REPLACE})
  while(replace)
    list(POP_FRONT replace library replacement)
    list(TRANSFORM libraries REPLACE "^${library}$" "${replacement}")
  endwhile()
  target_link_libraries(${copy} PUBLIC ${libraries})
  target_compile_options(${copy} PRIVATE -fsanitize=thread -g)
  target_link_options(${copy} INTERFACE -fsanitize=thread)
  orbis_set_warnings(${copy})
endfunction()
