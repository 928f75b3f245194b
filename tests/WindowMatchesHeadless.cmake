# Script mode: a program shows in a window (on a virtual X display) what it draws headless. It runs
# COMMAND with HEADLESS_ARGS and "--out OUT_DIR/NAME-headless.png", then under XVFB_RUN with
# WINDOW_ARGS and "--out OUT_DIR/NAME-window.png" (which must write the window's last frame), and
# requires the two PNGs to be equal byte for byte. Arguments are "|"-separated.
string(REPLACE "|" ";" headless_args "${HEADLESS_ARGS}")
string(REPLACE "|" ";" window_args "${WINDOW_ARGS}")
set(headless ${OUT_DIR}/${NAME}-headless.png)
set(window ${OUT_DIR}/${NAME}-window.png)
file(REMOVE ${headless} ${window})
execute_process(COMMAND ${COMMAND} ${headless_args} --out ${headless}
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "headless run failed (${rc}):\n${out}${err}")
endif()
execute_process(COMMAND ${XVFB_RUN} -a -s "-screen 0 640x480x24" ${COMMAND} ${window_args} --out ${window}
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "window 320x180.*${NAME}-window.png: frame 2 as shown")
  message(FATAL_ERROR "window run failed (${rc}):\n${out}${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${headless} ${window} RESULT_VARIABLE different)
if(different)
  message(FATAL_ERROR "the window showed another picture than the headless run: compare ${headless} and ${window}")
endif()
