# A fixed time step far too large for the scene: the run must stop with exit code 3, name the frame,
# the substep and the cause (for density and speed, where), and leave the frames finished before intact.
file(REMOVE_RECURSE "${SHOT}")
execute_process(COMMAND "${EXE}" simulate "${SCENE}" -o "${SHOT}" --gl egl-surfaceless
                        --set fluid.spacing=0.025 --set time.dt_mode=fixed --set time.dt=0.01
                RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_VARIABLE out)
if(NOT rc EQUAL 3)
  message(FATAL_ERROR "expected exit code 3, got ${rc}: ${err}")
endif()
if(NOT err MATCHES "frame [0-9]+, substep [0-9]+.*: .*(NaN|speed|density|outside)")
  message(FATAL_ERROR "the error does not name frame, substep and cause: ${err}")
endif()
# A stop on density also says where: the densest particle's position and its nearest domain wall.
if(err MATCHES "density [0-9.e+]+ kg/m\\^3 above" AND
   NOT err MATCHES "rest density at \\([-0-9.]+, [-0-9.]+, [-0-9.]+\\) m, [0-9.]+ spacings from the domain's [xyz]-m(in|ax) wall")
  message(FATAL_ERROR "the density stop does not say where: ${err}")
endif()
# A stop on speed says where the fastest particle is, with its own speed: the dam break's front passes
# 1 m/s within its first frames.
execute_process(COMMAND "${EXE}" simulate "${SCENE}" -o "${SHOT}_speed" --gl egl-surfaceless
                        --set fluid.spacing=0.025 --set health.max_speed=1
                RESULT_VARIABLE speed_rc ERROR_VARIABLE speed_err OUTPUT_VARIABLE speed_out)
if(NOT speed_rc EQUAL 3 OR
   NOT speed_err MATCHES "speed [0-9.e+]+ m/s above health.max_speed 1 \\(fastest particle [0-9.e+]+ m/s at \\([-0-9.]+, [-0-9.]+, [-0-9.]+\\) m, [0-9.]+ spacings from the domain's [xyz]-m(in|ax) wall\\)")
  message(FATAL_ERROR "the speed stop does not say where (exit ${speed_rc}): ${speed_err}")
endif()
message(STATUS "speed stop: ${speed_err}")
string(REGEX MATCH "frame ([0-9]+), substep" m "${err}")
math(EXPR last_good "${CMAKE_MATCH_1} - 1")
foreach(f RANGE 1 ${last_good})
  string(LENGTH "000${f}" len)
  math(EXPR start "${len} - 4")
  string(SUBSTRING "000${f}" ${start} 4 padded)
  if(NOT EXISTS "${SHOT}/cache/particles.${padded}.vdb")
    message(FATAL_ERROR "frame ${f} finished before the failure but its cache is missing")
  endif()
endforeach()
message(STATUS "stopped as expected: ${err}")
