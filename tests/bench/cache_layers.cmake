# bench/cache_speeds --layers on a shot's first frame, the fluid block's cubic lattice: every layer of
# A / s^2 particles lies one spacing above the one below, the bottom one half a spacing above the floor
# (here at y = -0.1 m, so the heights are measured from the domain's floor, not from y = 0), each
# part keeps the lattice's order, and each part moves with the block's starting velocity (0, -0.3, 0.4)
# m/s: mean v_y -0.3, RMS speed 0.5.
file(REMOVE_RECURSE "${SHOT}")
execute_process(COMMAND "${SPHFX}" -q simulate "${SCENE}" -o "${SHOT}" --set fluid.spacing=0.02
                        --set "domain.min=[0,-0.1,0]" --set time.end_frame=1
                        --set "fluid.blocks=[{\"shape\":\"box\",\"min\":[0,-0.1,0],\"max\":[0.2,0.2,0.2],
                                              \"velocity\":[0,-0.3,0.4]}]"
                RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "simulate failed (${code}):\n${err}")
endif()
execute_process(COMMAND "${CACHE_SPEEDS}" "${SHOT}" 1 --top 0 --layers RESULT_VARIABLE code OUTPUT_VARIABLE out
                ERROR_VARIABLE err)
# Quoted pieces: a semicolon in an unquoted CMake argument would split it.
string(CONCAT expected "layers 15 of 100 particles: bottom 0.5000 s above the floor, top 14.5000 s; "
       "gaps (s): lower third 1.0000, middle 1.0000, upper third 1.0000, top layer 1.0000")
string(CONCAT order "lattice order (1: cubic, 0: rows shifted half a spacing): lower third 1.000, "
       "middle 1.000, upper third 1.000, top layer 1.000")
string(CONCAT motion "motion (m/s): mean v_y lower third -0.3000, middle -0.3000, upper third -0.3000, "
       "top layer -0.3000; RMS speed 0.5000, 0.5000, 0.5000, 0.5000")
foreach(line IN ITEMS "${expected}" "${order}" "${motion}")
  string(FIND "${out}" "${line}" pos)
  if(NOT code EQUAL 0 OR pos EQUAL -1)
    message(FATAL_ERROR "cache_speeds --layers (${code}) lacks \"${line}\":\n${out}\n${err}")
  endif()
endforeach()
