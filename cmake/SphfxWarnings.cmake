# Warnings are errors-in-waiting: keep the build clean with -Wall -Wextra.
function(sphfx_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wno-missing-field-initializers)
endfunction()
