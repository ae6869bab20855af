# The installed sphfx works on its own: `cmake --install` into an empty prefix, then, from a folder that is
# neither the source nor the build tree, the installed binary finds its shipped scene and the reference
# tables (a study run measured against Martin & Moyce) through <prefix>/share/sphfx.
#   -DBUILD=<build tree> -DWORK=<scratch folder>
file(REMOVE_RECURSE "${WORK}")
set(prefix "${WORK}/prefix")
set(elsewhere "${WORK}/elsewhere")
file(MAKE_DIRECTORY "${elsewhere}")
execute_process(COMMAND "${CMAKE_COMMAND}" --install "${BUILD}" --prefix "${prefix}"
                RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${code}):\n${out}\n${err}")
endif()
set(exe "${prefix}/bin/sphfx")
foreach(f bin/sphfx share/sphfx/scenes/dam_break.json share/sphfx/studies/stability.json
          share/sphfx/studies/reference/dam_break_martin_moyce_n2.csv)
  if(NOT EXISTS "${prefix}/${f}")
    message(FATAL_ERROR "the install lacks ${f}")
  endif()
endforeach()

# A relative scene path that does not exist here is the shipped one.
execute_process(COMMAND "${CMAKE_COMMAND}" -E env --unset=SPHFX_DATA_DIR "${exe}" -q scene scenes/dam_break.json
                WORKING_DIRECTORY "${elsewhere}" RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code EQUAL 0 OR NOT out MATCHES "\"spacing\"")
  message(FATAL_ERROR "installed sphfx scene scenes/dam_break.json failed (${code}):\n${out}\n${err}")
endif()

# A one-run study on the installed scene: the front is measured against the installed reference table.
file(WRITE "${elsewhere}/tiny_study.json" "{
  \"name\": \"install\", \"timeout\": 600,
  \"cases\": [{\"name\": \"dam_break\", \"scene\": \"${prefix}/share/sphfx/scenes/dam_break.json\",
               \"validation\": \"dam_break\",
               \"set\": [\"fluid.spacing=0.04\", \"time.end_frame=12\"]}]
}
")
execute_process(COMMAND "${CMAKE_COMMAND}" -E env --unset=SPHFX_DATA_DIR
                        "${exe}" study tiny_study.json -o study --gl egl-surfaceless
                WORKING_DIRECTORY "${elsewhere}" RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "installed sphfx study failed (${code}):\n${out}\n${err}")
endif()
file(READ "${elsewhere}/study/results.csv" csv)
message(STATUS "results.csv:\n${csv}")
