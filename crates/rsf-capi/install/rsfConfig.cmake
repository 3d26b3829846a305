# CMake package of rsf's C ABI (installed by `make install` at the repository's root):
#   find_package(rsf CONFIG REQUIRED)   # with -DCMAKE_PREFIX_PATH=<prefix>
#   target_link_libraries(host PRIVATE rsf::rsf)          # the shared library
#   target_link_libraries(host PRIVATE rsf::rsf_static)   # the static library
# A Fortran host compiles the module source ${rsf_FORTRAN_MODULE} with its own sources
# (a compiled .mod file is tied to one compiler version, so the source is what is installed).
# Relocatable: every path is relative to this file (<prefix>/lib/cmake/rsf/).
get_filename_component(_rsf_prefix "${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
set(rsf_INCLUDE_DIR "${_rsf_prefix}/include")
set(rsf_FORTRAN_MODULE "${_rsf_prefix}/include/rsf.f90")
if(NOT TARGET rsf::rsf)
  add_library(rsf::rsf SHARED IMPORTED)
  set_target_properties(rsf::rsf PROPERTIES
    IMPORTED_LOCATION "${_rsf_prefix}/lib/librsf_capi.so"
    INTERFACE_INCLUDE_DIRECTORIES "${_rsf_prefix}/include")
  add_library(rsf::rsf_static STATIC IMPORTED)
  set_target_properties(rsf::rsf_static PROPERTIES
    IMPORTED_LOCATION "${_rsf_prefix}/lib/librsf_capi.a"
    INTERFACE_INCLUDE_DIRECTORIES "${_rsf_prefix}/include"
    INTERFACE_LINK_LIBRARIES "pthread;dl;m")
endif()
unset(_rsf_prefix)
