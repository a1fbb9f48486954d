# sss_embed_glsl.cmake: the build-time embedding of runtime/shaders/*.glsl
# into C (embed_glsl.cmake), for every library that compiles shaders from
# text: libsss hands the evaluation's GLSL to engines (sss/gpu.h), libsss_render
# builds its programs from it. The shaders stay in runtime/shaders/, one
# source of truth. Included once by the top-level CMakeLists.txt.
set(SSS_SHADER_DIR ${PROJECT_SOURCE_DIR}/runtime/shaders)

# Generates OUT.c / OUT.h in the current binary directory from the GLSL
# files (names under runtime/shaders/), each as the NUL-terminated array
# sss_glsl_NAME_STAGE, and puts the two generated paths in VAR: a source
# list can take them before its library is declared.
function(sss_embed_glsl_sources var out)
  set(files)
  foreach(f ${ARGN})
    list(APPEND files ${SSS_SHADER_DIR}/${f})
  endforeach()
  string(REPLACE ";" "|" arg "${files}")
  set(gen ${CMAKE_CURRENT_BINARY_DIR}/${out})
  add_custom_command(OUTPUT ${gen}.c ${gen}.h
    COMMAND ${CMAKE_COMMAND} -DOUT_C=${gen}.c -DOUT_H=${gen}.h "-DFILES=${arg}"
            -P ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/embed_glsl.cmake
    DEPENDS ${files} ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/embed_glsl.cmake
    COMMENT "Embedding GLSL into ${out}.c" VERBATIM)
  set(${var} ${gen}.c ${gen}.h PARENT_SCOPE)
endfunction()

# The same, compiled into target (its generated header on its private
# include path).
function(sss_embed_glsl target out)
  sss_embed_glsl_sources(gen ${out} ${ARGN})
  target_sources(${target} PRIVATE ${gen})
  target_include_directories(${target} PRIVATE ${CMAKE_CURRENT_BINARY_DIR})
endfunction()
