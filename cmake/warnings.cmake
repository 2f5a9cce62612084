# One place for the warning policy: every target of ours calls dynweigh_warnings().
function(dynweigh_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion)
  if(DYNWEIGH_CROSS_CORTEXM)
    # The M4F's FPU is single precision: a double would be a software library call in the loop.
    target_compile_options(${target} PRIVATE -Wdouble-promotion)
  endif()
  if(DYNWEIGH_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# Control-loop code: no exceptions, no RTTI, no heap inside Eigen.
function(dynweigh_loop_code target)
  target_compile_options(${target} PRIVATE -fno-exceptions -fno-rtti)
  target_compile_definitions(${target} PRIVATE EIGEN_NO_MALLOC)
endfunction()
