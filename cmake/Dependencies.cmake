# Every third-party dependency, found once. All come from Debian 12 packages
# (scripts/debian-packages.txt); scripts/setup.sh installs them.

find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(spectra 1.0 REQUIRED CONFIG PATHS /usr/share/spectra/cmake)
find_package(OpenMesh REQUIRED CONFIG)
find_package(Threads REQUIRED)
find_package(Qt6 6.4 REQUIRED COMPONENTS Core Gui Widgets Network OpenGL OpenGLWidgets Charts Test)

# SuiteSparse 5.x ships no CMake package: find CHOLMOD by hand and wrap it in an imported target.
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
find_library(CHOLMOD_LIBRARY cholmod REQUIRED)
find_library(SUITESPARSE_CONFIG_LIBRARY suitesparseconfig REQUIRED)
add_library(SuiteSparse::CHOLMOD INTERFACE IMPORTED)
target_include_directories(SuiteSparse::CHOLMOD SYSTEM INTERFACE ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(SuiteSparse::CHOLMOD INTERFACE ${CHOLMOD_LIBRARY} ${SUITESPARSE_CONFIG_LIBRARY})

# Eigen hands its large dense products (the Lanczos re-orthogonalisation GEMVs of the basis solve) to OpenBLAS,
# which runs them on both cores: 15–20% faster basis at 100k vertices (docs/benchmarks.md). Defined for every
# target, so no two translation units instantiate Eigen's kernels differently (one definition rule).
set(BLA_VENDOR OpenBLAS)
find_package(BLAS REQUIRED)
add_compile_definitions(EIGEN_USE_BLAS)
# Eigen's fast-math square root on AVX-512 uses _mm512_rsqrt14_pd, which GCC 12 flags as "used uninitialized"
# (GCC bug 105593, fixed in GCC 13) wherever a norm is vectorised. The exact square root costs nothing measurable.
add_compile_definitions(EIGEN_FAST_MATH=0)

# Mesh codecs and simplification (meshoptimizer 0.18), general compression (zstd) and the NATS C client (cnats).
find_package(meshoptimizer REQUIRED CONFIG)
find_package(zstd REQUIRED CONFIG)
# Debian 12's cnats CMake package names a static library the package does not ship, so cnats comes through
# pkg-config: the target PkgConfig::NATS.
find_package(PkgConfig REQUIRED)
pkg_check_modules(NATS REQUIRED IMPORTED_TARGET libnats)

if(SHAPECAST_BUILD_TESTS)
  find_package(GTest REQUIRED)
  include(GoogleTest)
endif()
