# The GPU backend's own code run on the CPU (-DMPMVS_HIP_CPU_DIR=<HIP-CPU source tree>):
# kernels/*.cu compiled as HIP by the host compiler against HIP-CPU, a header-only runtime
# that executes HIP programs on the CPU (kernels/gpu_runtime.h, MPMVS_HIP_CPU), into the
# target mpmvs_cuda. For tests only (tests/gpu/run_on_hip_cpu.sh): it proves the device code,
# launch geometry and uploads without a GPU. HIP-CPU is never part of this repository.
if(NOT EXISTS ${MPMVS_HIP_CPU_DIR}/include/hip/hip_runtime.h)
  message(FATAL_ERROR "MPMVS_HIP_CPU_DIR=${MPMVS_HIP_CPU_DIR} is not a HIP-CPU source tree (no include/hip/hip_runtime.h)")
endif()
find_package(TBB REQUIRED)  # HIP-CPU runs a kernel's blocks with the C++17 parallel algorithms
set_source_files_properties(${MPMVS_GPU_SOURCES} PROPERTIES LANGUAGE CXX)
add_library(mpmvs_cuda STATIC ${MPMVS_GPU_SOURCES})
target_compile_options(mpmvs_cuda PRIVATE -x c++)
target_compile_definitions(mpmvs_cuda PRIVATE MPMVS_HIP_CPU=1)
target_include_directories(mpmvs_cuda SYSTEM PRIVATE ${MPMVS_HIP_CPU_DIR}/include)
target_link_libraries(mpmvs_cuda PUBLIC mpmvs_kernels_common TBB::tbb Threads::Threads)
mpmvs_kernel_compile_options(mpmvs_cuda)
message(STATUS "mp-mvs: HIP-CPU backend ON (the GPU backend's code on the CPU, ${MPMVS_HIP_CPU_DIR}); the CUDA backend is off")
