# check_glsl.cmake: one program stage as the renderer composes it
# (sss_gl_compile, runtime/src/render/gl_util.c: "#version 430 core", the
# #defines the C code puts in front, then the shader text) validated with
# glslangValidator, so that a shader error fails the build instead of a
# user's first frame. Run at build time (runtime/CMakeLists.txt,
# sss_glsl_check):
#   cmake -DVALIDATOR=glslangValidator -DSTAGE=comp|vert|frag
#         -DDEFINES=A=1|B=2 -DSOURCES=a.glsl|b.glsl -DOUT=dir/name -P check_glsl.cmake
# Writes the composed text to OUT.glsl (the file the errors' line numbers
# refer to) and, when it validates, the stamp OUT.ok.
string(REPLACE "|" ";" DEFINES "${DEFINES}")
string(REPLACE "|" ";" SOURCES "${SOURCES}")
set(text "#version 430 core\n")
foreach(d IN LISTS DEFINES)
  string(REPLACE "=" " " d "${d}")
  string(APPEND text "#define ${d}\n")
endforeach()
foreach(s IN LISTS SOURCES)
  file(READ "${s}" body)
  string(APPEND text "${body}")
endforeach()
file(WRITE "${OUT}.glsl" "${text}")
file(REMOVE "${OUT}.ok")
execute_process(COMMAND "${VALIDATOR}" -S "${STAGE}" "${OUT}.glsl"
                RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
if(NOT rc EQUAL 0)
  string(REPLACE ";" "|" DEFINES "${DEFINES}")
  message(FATAL_ERROR "GLSL validation failed: ${SOURCES} (stage ${STAGE}, defines '${DEFINES}'), "
                      "composed in ${OUT}.glsl:\n${log}")
endif()
file(WRITE "${OUT}.ok" "ok\n")
