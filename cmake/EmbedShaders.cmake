# Embeds GPU sources (shaders/*.comp, *.vert, *.frag, *.glsl, *.h) into a generated C++ file, so that the
# binary carries its shaders and never looks for them on disk at run time. Each library embeds the files
# it runs.
#
#   sphfx_embed_shaders(TARGET target FUNCTION name FILES a.comp b.glsl ...)
#
# Generates <name>.cpp defining `const sphfx::ShaderTable& sphfx::<name>()` (ShaderTable is declared in
# sphfx/gpu/shader_sources.h) and adds it to `target`. Files are named relative to shaders/.
set(SPHFX_SHADER_DIR "${PROJECT_SOURCE_DIR}/shaders")
set_property(GLOBAL PROPERTY SPHFX_EMBEDDED_SHADERS "")

function(sphfx_embed_shaders)
  cmake_parse_arguments(ARG "" "TARGET;FUNCTION" "FILES" ${ARGN})
  set(out "${CMAKE_CURRENT_BINARY_DIR}/${ARG_FUNCTION}.cpp")
  set(inputs "")
  foreach(f IN LISTS ARG_FILES)
    list(APPEND inputs "${SPHFX_SHADER_DIR}/${f}")
  endforeach()
  set_property(GLOBAL APPEND PROPERTY SPHFX_EMBEDDED_SHADERS ${ARG_FILES})
  add_custom_command(
    OUTPUT "${out}"
    COMMAND "${CMAKE_COMMAND}" -DOUT=${out} -DDIR=${SPHFX_SHADER_DIR} -DFUNCTION=${ARG_FUNCTION}
            "-DFILES=${ARG_FILES}" -P "${PROJECT_SOURCE_DIR}/cmake/EmbedShadersScript.cmake"
    DEPENDS ${inputs} "${PROJECT_SOURCE_DIR}/cmake/EmbedShadersScript.cmake"
    COMMENT "Embedding ${ARG_FUNCTION}"
    VERBATIM)
  target_sources(${ARG_TARGET} PRIVATE "${out}")
endfunction()

# The files of shaders/ whose names start with one of `prefixes`, sorted, into `var`.
function(sphfx_shader_files var)
  set(found "")
  foreach(prefix IN LISTS ARGN)
    file(GLOB matches CONFIGURE_DEPENDS RELATIVE "${SPHFX_SHADER_DIR}" "${SPHFX_SHADER_DIR}/${prefix}*")
    list(APPEND found ${matches})
  endforeach()
  list(SORT found)
  set(${var} ${found} PARENT_SCOPE)
endfunction()

# Fails the configure step if a file under shaders/ is embedded by no library, or by two.
function(sphfx_check_embedded_shaders)
  get_property(embedded GLOBAL PROPERTY SPHFX_EMBEDDED_SHADERS)
  file(GLOB all CONFIGURE_DEPENDS RELATIVE "${SPHFX_SHADER_DIR}" "${SPHFX_SHADER_DIR}/*")
  foreach(f IN LISTS all)
    list(FIND embedded "${f}" at)
    if(at EQUAL -1)
      message(FATAL_ERROR "shaders/${f} is embedded by no library: name it with a stage's prefix "
                          "(sim_, sph_, render_) or add it to the GPU layer's list in gpu/CMakeLists.txt")
    endif()
    list(REMOVE_AT embedded ${at})
    list(FIND embedded "${f}" again)
    if(NOT again EQUAL -1)
      message(FATAL_ERROR "shaders/${f} is embedded by two libraries")
    endif()
  endforeach()
endfunction()
