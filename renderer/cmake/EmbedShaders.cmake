# Script mode: writes OUTPUT, a C++ file holding the text of every file under SHADER_ROOT as a
# raw-string literal, looked up by its path relative to SHADER_ROOT ("renderer/builtin/constants.glsl").
# Run at build time by renderer/CMakeLists.txt whenever a shader changes.
if(NOT SHADER_ROOT OR NOT OUTPUT)
  message(FATAL_ERROR "EmbedShaders.cmake needs -DSHADER_ROOT=... -DOUTPUT=...")
endif()

file(GLOB_RECURSE files LIST_DIRECTORIES false RELATIVE ${SHADER_ROOT} ${SHADER_ROOT}/*)
list(SORT files)
set(delimiter "orbis_glsl")
set(text "// Generated from shaders/ by renderer/cmake/EmbedShaders.cmake at build time: do not edit.\n")
string(APPEND text "#include \"EmbeddedShaderTable.h\"\n\nnamespace orbis::renderer::detail {\n\n")
string(APPEND text "const EmbeddedShaderFile kEmbeddedShaderFiles[] = {\n")
set(count 0)
foreach(file IN LISTS files)
  get_filename_component(name ${file} NAME)
  if(name MATCHES "^\\." OR name MATCHES "^README")
    continue()
  endif()
  file(READ ${SHADER_ROOT}/${file} content)
  string(FIND "${content}" ")${delimiter}\"" clash)
  if(NOT clash EQUAL -1)
    message(FATAL_ERROR "shaders/${file} contains the embedding delimiter )${delimiter}\"")
  endif()
  string(APPEND text "    {\"${file}\", R\"${delimiter}(${content})${delimiter}\"},\n")
  math(EXPR count "${count} + 1")
endforeach()
string(APPEND text "    {nullptr, nullptr},\n};\n\nconst std::size_t kEmbeddedShaderFileCount = ${count};\n\n} // namespace orbis::renderer::detail\n")

# Rewrite only when the text changed, so that an unchanged shader set recompiles nothing.
file(WRITE ${OUTPUT}.new "${text}")
file(COPY_FILE ${OUTPUT}.new ${OUTPUT} ONLY_IF_DIFFERENT)
file(REMOVE ${OUTPUT}.new)
