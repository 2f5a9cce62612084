# Toolchain for the bare-metal Cortex-M4F image (preset cortexm). Debian: gcc-arm-none-eabi,
# libnewlib-arm-none-eabi, libstdc++-arm-none-eabi-newlib. Float ABI hard, single-precision FPU.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
set(CMAKE_ASM_COMPILER arm-none-eabi-gcc)
set(CMAKE_OBJCOPY arm-none-eabi-objcopy CACHE FILEPATH "objcopy")
set(CMAKE_SIZE arm-none-eabi-size CACHE FILEPATH "size")
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)  # no startup code yet when CMake probes

set(DYNWEIGH_CORTEXM_CPU "-mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard")
# Control-loop code everywhere: no exceptions, no RTTI, no errno from math (sqrtf inline), no
# guards or atexit for statics, sections per function so the linker drops what is unused.
# _DEFAULT_SOURCE: newlib hides M_PI under -std=c++17 (glibc shows it because g++ defines _GNU_SOURCE).
set(CMAKE_CXX_FLAGS_INIT "${DYNWEIGH_CORTEXM_CPU} -ffunction-sections -fdata-sections -fno-exceptions -fno-rtti \
-fno-math-errno -fno-threadsafe-statics -fno-use-cxa-atexit -fno-unwind-tables -fno-asynchronous-unwind-tables -DEIGEN_NO_MALLOC \
-D_DEFAULT_SOURCE")
set(CMAKE_C_FLAGS_INIT "${DYNWEIGH_CORTEXM_CPU} -ffunction-sections -fdata-sections")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${DYNWEIGH_CORTEXM_CPU} -nostartfiles --specs=nano.specs --specs=nosys.specs -Wl,--gc-sections")

# Headers-only host packages (Eigen) are found on the host; libraries and programs are not.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
