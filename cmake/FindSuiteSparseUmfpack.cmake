# Finds UMFPACK (SuiteSparse) as packaged by Debian, for Eigen's UmfPackSupport.
find_path(UMFPACK_INCLUDE_DIR umfpack.h PATH_SUFFIXES suitesparse)
find_library(UMFPACK_LIBRARY umfpack)
find_library(SUITESPARSE_AMD_LIBRARY amd)
find_library(SUITESPARSE_CONFIG_LIBRARY suitesparseconfig)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(SuiteSparseUmfpack REQUIRED_VARS UMFPACK_INCLUDE_DIR UMFPACK_LIBRARY
                                                                   SUITESPARSE_AMD_LIBRARY SUITESPARSE_CONFIG_LIBRARY)
if(SuiteSparseUmfpack_FOUND AND NOT TARGET SuiteSparse::UMFPACK)
  add_library(SuiteSparse::UMFPACK INTERFACE IMPORTED)
  set_target_properties(SuiteSparse::UMFPACK PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${UMFPACK_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${UMFPACK_LIBRARY};${SUITESPARSE_AMD_LIBRARY};${SUITESPARSE_CONFIG_LIBRARY}")
endif()
