# Locates OpenSubdiv (Debian libosd-dev) for the kernel tests and benchmarks only and
# defines the interface target `nomec_opensubdiv`. Never used by nomec_kernel itself.
if(NOT TARGET nomec_opensubdiv)
  find_library(NOMEC_OSD_CPU_LIBRARY NAMES osdCPU REQUIRED)
  find_path(NOMEC_OSD_INCLUDE_DIR opensubdiv/version.h REQUIRED)
  add_library(nomec_opensubdiv INTERFACE)
  target_link_libraries(nomec_opensubdiv INTERFACE ${NOMEC_OSD_CPU_LIBRARY})
  target_include_directories(nomec_opensubdiv SYSTEM INTERFACE ${NOMEC_OSD_INCLUDE_DIR})
endif()
