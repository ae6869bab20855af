# Embeds GPU sources (shaders/*.comp, *.vert, *.frag, *.glsl, *.h) into a generated C++ file, so that the
# binary carries its shaders and never looks for them on disk at run time.
#
#   sphfx_embed_shaders(TARGET target DIR dir FILES a.comp b.glsl ...)
#
# Generates embedded_shaders.cpp defining sphfx::embeddedShaderTable() (declared in
# sphfx/core/shader_sources.h) and adds it to `target`.
function(sphfx_embed_shaders)
  cmake_parse_arguments(ARG "" "TARGET;DIR" "FILES" ${ARGN})
  set(out "${CMAKE_CURRENT_BINARY_DIR}/embedded_shaders.cpp")
  set(inputs "")
  foreach(f IN LISTS ARG_FILES)
    list(APPEND inputs "${ARG_DIR}/${f}")
  endforeach()
  add_custom_command(
    OUTPUT "${out}"
    COMMAND "${CMAKE_COMMAND}" -DOUT=${out} -DDIR=${ARG_DIR} "-DFILES=${ARG_FILES}"
            -P "${PROJECT_SOURCE_DIR}/cmake/EmbedShadersScript.cmake"
    DEPENDS ${inputs} "${PROJECT_SOURCE_DIR}/cmake/EmbedShadersScript.cmake"
    COMMENT "Embedding shader sources"
    VERBATIM)
  target_sources(${ARG_TARGET} PRIVATE "${out}")
endfunction()
