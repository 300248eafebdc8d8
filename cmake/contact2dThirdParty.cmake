# Imported targets for the two dependencies that ship neither a CMake config nor a .pc file
# (SuiteSparse 5.12, gmsh 4.8). Included by the top-level CMakeLists.txt and by the installed
# contact2dConfig.cmake, so a program that links the installed static libraries resolves the
# same libraries the build did. Sets contact2d_THIRD_PARTY_MISSING to what it could not find.
set(contact2d_THIRD_PARTY_MISSING "")

if(NOT TARGET contact2d::suitesparse)
  find_path(C2D_SUITESPARSE_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
  set(_c2d_suitesparse_libs "")
  foreach(_c2d_ss umfpack cholmod amd colamd camd ccolamd suitesparseconfig)
    find_library(C2D_SS_${_c2d_ss}_LIBRARY ${_c2d_ss})
    if(C2D_SS_${_c2d_ss}_LIBRARY)
      list(APPEND _c2d_suitesparse_libs "${C2D_SS_${_c2d_ss}_LIBRARY}")
    else()
      list(APPEND contact2d_THIRD_PARTY_MISSING "SuiteSparse library ${_c2d_ss}")
    endif()
  endforeach()
  if(NOT C2D_SUITESPARSE_INCLUDE_DIR)
    list(APPEND contact2d_THIRD_PARTY_MISSING "SuiteSparse header cholmod.h")
  endif()
  add_library(contact2d::suitesparse INTERFACE IMPORTED)
  set_target_properties(contact2d::suitesparse PROPERTIES
                        INTERFACE_INCLUDE_DIRECTORIES "${C2D_SUITESPARSE_INCLUDE_DIR}"
                        INTERFACE_LINK_LIBRARIES "${_c2d_suitesparse_libs};Eigen3::Eigen")
  unset(_c2d_suitesparse_libs)
endif()

# Eigen's dense products and triangular solves (the condensed contact surface's blocks) through
# the system BLAS: libblas.so.3, OpenBLAS when libopenblas0-pthread is installed, whose kernels
# are chosen for the CPU at run time, where Eigen's own are compiled for the baseline x86-64
# (SSE2). Measured on Cattaneo-Mindlin (11k DOFs, one thread): 2.1 s -> 1.8 s for the process.
# A compile definition of every translation unit that includes Eigen, so it travels with core.
if(NOT TARGET contact2d::blas)
  find_library(C2D_BLAS_LIBRARY NAMES blas)
  if(NOT C2D_BLAS_LIBRARY)
    list(APPEND contact2d_THIRD_PARTY_MISSING "BLAS (libblas.so)")
  endif()
  add_library(contact2d::blas INTERFACE IMPORTED)
  set_target_properties(contact2d::blas PROPERTIES
                        INTERFACE_LINK_LIBRARIES "${C2D_BLAS_LIBRARY}"
                        INTERFACE_COMPILE_DEFINITIONS EIGEN_USE_BLAS)
endif()

if(NOT TARGET contact2d::gmsh)
  find_path(C2D_GMSH_INCLUDE_DIR gmsh.h)
  find_library(C2D_GMSH_LIBRARY gmsh)
  if(NOT C2D_GMSH_INCLUDE_DIR OR NOT C2D_GMSH_LIBRARY)
    list(APPEND contact2d_THIRD_PARTY_MISSING "gmsh (gmsh.h and libgmsh)")
  endif()
  add_library(contact2d::gmsh UNKNOWN IMPORTED)
  set_target_properties(contact2d::gmsh PROPERTIES IMPORTED_LOCATION "${C2D_GMSH_LIBRARY}"
                        INTERFACE_INCLUDE_DIRECTORIES "${C2D_GMSH_INCLUDE_DIR}")
endif()
