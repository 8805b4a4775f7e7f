# The GPU backend for AMD GPUs (-DMPMVS_ENABLE_HIP=ON): the CUDA backend's own sources,
# kernels/*.cu, compiled as HIP by hipcc; kernels/gpu_runtime.h maps the CUDA runtime names
# they use to HIP's, so there is one copy of every kernel. Defines the target mpmvs_cuda (the
# GPU backend, whichever runtime it uses) as the CUDA build does. CMake's HIP language is not
# used: it expects ROCm's own layout (<root>/lib/cmake/hip-lang), which Debian's hipcc
# package does not have.
find_program(MPMVS_HIPCC hipcc)
if(NOT MPMVS_HIPCC)
  message(FATAL_ERROR "MPMVS_ENABLE_HIP=ON needs hipcc (Debian: apt-get install hipcc)")
endif()
find_library(MPMVS_AMDHIP64_LIBRARY amdhip64)
if(NOT MPMVS_AMDHIP64_LIBRARY)
  message(FATAL_ERROR "MPMVS_ENABLE_HIP=ON needs the HIP runtime libamdhip64 (Debian: libamdhip64-dev)")
endif()
execute_process(COMMAND ${MPMVS_HIPCC} --version OUTPUT_VARIABLE MPMVS_HIPCC_VERSION_TEXT ERROR_QUIET)
string(REGEX MATCH "HIP version: [0-9.]+" MPMVS_HIPCC_VERSION "${MPMVS_HIPCC_VERSION_TEXT}")
string(REPLACE "HIP version: " "HIP " MPMVS_HIPCC_VERSION "${MPMVS_HIPCC_VERSION}")

set(MPMVS_HIP_FLAGS -x hip -c -O3 -std=c++17 -fPIC -Wall -Wextra -I${PROJECT_SOURCE_DIR})
foreach(arch IN LISTS MPMVS_HIP_ARCHITECTURES)
  list(APPEND MPMVS_HIP_FLAGS --offload-arch=${arch})
endforeach()
file(GLOB MPMVS_GPU_HEADERS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/kernels/*.h
  ${PROJECT_SOURCE_DIR}/kernels/*.cuh)
set(MPMVS_HIP_OBJECTS)
foreach(source IN LISTS MPMVS_GPU_SOURCES)
  get_filename_component(name ${source} NAME_WE)
  set(object ${CMAKE_CURRENT_BINARY_DIR}/hip/${name}.o)
  add_custom_command(OUTPUT ${object}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_CURRENT_BINARY_DIR}/hip
    COMMAND ${MPMVS_HIPCC} ${MPMVS_HIP_FLAGS} ${source} -o ${object}
    DEPENDS ${source} ${MPMVS_GPU_HEADERS}
    COMMENT "hipcc kernels/${name}.cu (${MPMVS_HIP_ARCHITECTURES})"
    VERBATIM)
  list(APPEND MPMVS_HIP_OBJECTS ${object})
endforeach()
add_library(mpmvs_cuda STATIC ${MPMVS_HIP_OBJECTS})
set_target_properties(mpmvs_cuda PROPERTIES LINKER_LANGUAGE CXX)
target_link_libraries(mpmvs_cuda PUBLIC mpmvs_kernels_common ${MPMVS_AMDHIP64_LIBRARY})
message(STATUS "mp-mvs: HIP backend ON (hipcc ${MPMVS_HIPCC_VERSION}, AMD targets ${MPMVS_HIP_ARCHITECTURES}); the CUDA backend is off")
