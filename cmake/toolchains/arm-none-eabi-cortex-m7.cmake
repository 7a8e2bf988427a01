# Cross-compiling neurov for an ARM Cortex-M7 with its double-precision FPU
# (FPv5-D16), hard-float ABI, with Debian's gcc-arm-none-eabi and newlib:
#
#   cmake -S . -B build-m7 -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/arm-none-eabi-cortex-m7.cmake
#   cmake --build build-m7 && cmake --install build-m7 --prefix <firmware sysroot>
#
# This builds neurov_c (the C interface) for the target; firmware then links
# neurov::neurov_c, or uses the header-only neurov::neurov with the same flags.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)

set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
set(CMAKE_ASM_COMPILER arm-none-eabi-gcc)
set(CMAKE_AR arm-none-eabi-ar CACHE FILEPATH "")
set(CMAKE_RANLIB arm-none-eabi-ranlib CACHE FILEPATH "")
set(CMAKE_SIZE arm-none-eabi-size CACHE FILEPATH "")

# Bare metal has no loader and no default startup code, so CMake's compiler
# checks must not try to link a program.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(_neurov_m7 "-mcpu=cortex-m7 -mfpu=fpv5-d16 -mfloat-abi=hard -mthumb")
# Sections per function and object, so the final link keeps only what firmware
# calls. No -ffast-math: neurov's NaN/Inf guards rely on IEEE semantics.
# Add flags with the CFLAGS/CXXFLAGS environment variables, which CMake puts in
# front of these; setting CMAKE_CXX_FLAGS on the command line replaces them.
set(CMAKE_C_FLAGS_INIT "${_neurov_m7} -ffunction-sections -fdata-sections")
set(CMAKE_CXX_FLAGS_INIT
    "${_neurov_m7} -ffunction-sections -fdata-sections -fno-exceptions -fno-rtti -fno-threadsafe-statics")
set(CMAKE_ASM_FLAGS_INIT "${_neurov_m7}")
# -Os for the optimised builds: flash is the scarce resource. Set in the cache
# because CMake appends its own -O3 to a toolchain's *_FLAGS_RELEASE_INIT.
foreach(_lang C CXX)
  set(CMAKE_${_lang}_FLAGS_RELEASE "-Os -DNDEBUG" CACHE STRING "")
  set(CMAKE_${_lang}_FLAGS_MINSIZEREL "-Os -DNDEBUG" CACHE STRING "")
endforeach()
# newlib-nano; the firmware's own linker script and startup code come with it.
set(CMAKE_EXE_LINKER_FLAGS_INIT "${_neurov_m7} --specs=nano.specs -Wl,--gc-sections")

# Libraries and headers for the target come from the target's sysroot; Eigen
# and neurov's own package are header-only and architecture-independent, so
# CMake packages are also looked for on the host.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
