# Script mode: `orbis view` shows in a window (on a virtual X display) what `orbis render` draws
# headless: the PNG of the window's last frame must equal, byte for byte, the headless PNG of
# the same scene at the same size. Needs ORBIS, XVFB_RUN, SCENE and OUT_DIR.
set(size --width 320 --height 180)
execute_process(COMMAND ${ORBIS} render ${SCENE} ${size} --out ${OUT_DIR}/headless.png
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "orbis render failed (${rc}):\n${out}${err}")
endif()
execute_process(COMMAND ${XVFB_RUN} -a -s "-screen 0 640x480x24" ${ORBIS} view ${SCENE} ${size} --frames 2
  --out ${OUT_DIR}/window.png RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "window 320x180.*window.png: frame 2 as shown")
  message(FATAL_ERROR "orbis view failed (${rc}):\n${out}${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT_DIR}/headless.png ${OUT_DIR}/window.png
  RESULT_VARIABLE different)
if(different)
  message(FATAL_ERROR "the window showed another picture than the headless render: compare ${OUT_DIR}/headless.png "
                      "and ${OUT_DIR}/window.png")
endif()
