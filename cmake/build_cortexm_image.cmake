# The Cortex-M image as its preset builds it: `cmake --preset cortexm` once (the tree keeps its own
# cache after that), then `cmake --build --preset cortexm`. Run by the host build
# (tests/targets/CMakeLists.txt) from the source tree, so the cortexm tests of `ctest --preset host`
# run on the very image a user builds with the preset: build/cortexm/dynweigh-cortexm.elf.
#   cmake -DSOURCE_DIR=<tree> -P cmake/build_cortexm_image.cmake
if(NOT EXISTS "${SOURCE_DIR}/build/cortexm/CMakeCache.txt")
  execute_process(COMMAND ${CMAKE_COMMAND} --preset cortexm WORKING_DIRECTORY "${SOURCE_DIR}" COMMAND_ERROR_IS_FATAL ANY)
endif()
# The outer make's jobserver is not the preset's: the preset says its own jobs.
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=MAKEFLAGS --unset=MFLAGS ${CMAKE_COMMAND} --build --preset cortexm WORKING_DIRECTORY "${SOURCE_DIR}" COMMAND_ERROR_IS_FATAL ANY)
