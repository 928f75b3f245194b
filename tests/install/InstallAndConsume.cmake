# Script mode: installs ORBIS_BINARY_DIR into WORK_DIR/prefix, then builds and runs one consumer
# per kind of user program against it, each finding only the components it needs, and runs the
# installed orbis command on its installed data.
# -DORBIS_BINARY_DIR= -DCONSUMERS_DIR= -DWORK_DIR= -DGENERATOR=
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)

# run_step(COMMAND...): fails the test with the output when the command fails; the output is
# left in step_output.
function(run_step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "step failed (${result}): ${ARGN}\n${out}\n${err}")
  endif()
  set(step_output "${out}${err}" PARENT_SCOPE)
endfunction()

function(expect text regex what)
  if(NOT text MATCHES "${regex}")
    message(FATAL_ERROR "${what}: expected /${regex}/ in:\n${text}")
  endif()
endfunction()

function(expect_not text regex what)
  if(text MATCHES "${regex}")
    message(FATAL_ERROR "${what}: /${regex}/ (\"${CMAKE_MATCH_0}\") should not appear in:\n${text}")
  endif()
endfunction()

run_step(${CMAKE_COMMAND} --install ${ORBIS_BINARY_DIR} --prefix ${prefix})

# consume(kind NOT_FOUND regex NOT_LINKED regex ARGS...): configures, builds and runs the consumer
# of that kind. Configuring must not look for what matches NOT_FOUND (dependencies of components
# it did not ask for); neither the link line nor the shared libraries the program needs (its
# NEEDED entries) may match NOT_LINKED. Not ldd's closure: under -fsanitize GCC links with
# --no-as-needed, so every library of the link line is needed, GDAL too for the world component,
# and ldd would report what GDAL itself needs (fontconfig, through poppler). The program's output
# is left in consumer_output.
function(consume kind)
  cmake_parse_arguments(ARG "" "NOT_FOUND;NOT_LINKED" "ARGS" ${ARGN})
  set(build ${WORK_DIR}/${kind})
  run_step(${CMAKE_COMMAND} -S ${CONSUMERS_DIR}/${kind} -B ${build} -G ${GENERATOR}
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release)
  expect_not("${step_output}" "${ARG_NOT_FOUND}" "configuring the ${kind} consumer")
  run_step(${CMAKE_COMMAND} --build ${build} --verbose)
  expect_not("${step_output}" "${ARG_NOT_LINKED}" "linking the ${kind} consumer")
  run_step(readelf --dynamic ${build}/consumer)
  expect_not("${step_output}" "${ARG_NOT_LINKED}" "the ${kind} consumer's shared libraries")
  run_step(${build}/consumer ${ARG_ARGS})
  message(STATUS "${kind} consumer: ${step_output}")
  set(consumer_output "${step_output}" PARENT_SCOPE)
endfunction()

set(gl "libGL|libEGL|libOSMesa|-lGL|-lEGL|-lOSMesa|osmesa")
consume(core NOT_FOUND "egl|osmesa|glfw|fontconfig|GDAL|CURL|turbojpeg|nlohmann"
  NOT_LINKED "${gl}|glfw|gdal|curl|fontconfig")
expect("${consumer_output}" "centre height -6356752" "core consumer")

consume(world NOT_FOUND "egl|osmesa|glfw|fontconfig" NOT_LINKED "${gl}|glfw|fontconfig"
  ARGS ${prefix}/share/orbis/data/natural-earth/countries-110m.geojson)
expect("${consumer_output}" "countries 177, named 177" "world consumer")
expect("${consumer_output}" "scene width 320" "world consumer")

consume(renderer NOT_FOUND "glfw|fontconfig|GDAL|CURL|turbojpeg" NOT_LINKED "glfw|gdal|curl|fontconfig")
expect("${consumer_output}" "inside 255 0 0, outside 255 255 255" "renderer consumer")
expect("${consumer_output}" "window: .*link orbis::window" "renderer consumer")

consume(scene NOT_FOUND "glfw" NOT_LINKED "glfw")
expect("${consumer_output}" "globe drawn, corner background, [1-9][0-9]* commands" "scene consumer")

# The installed command reads the installed data, not the source tree's.
run_step(${prefix}/bin/orbis validate capitals)
expect("${step_output}" "${prefix}/share/orbis/data/scenes/capitals.json: ok \\(1 layer\\)" "orbis validate")
run_step(${prefix}/bin/orbis render countries --out ${WORK_DIR}/countries.png --width 64 --height 32)
expect("${step_output}" "countries.png: 64x32" "orbis render")
run_step(${prefix}/bin/orbis help)
expect("${step_output}" "example in ${prefix}/share/orbis/data " "orbis help")
foreach(installed share/doc/orbis/README.md share/doc/orbis/scene-format.md lib/cmake/orbis/OrbisEmbedShaders.cmake)
  if(NOT EXISTS ${prefix}/${installed})
    message(FATAL_ERROR "not installed: ${installed}")
  endif()
endforeach()
