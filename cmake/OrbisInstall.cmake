# Installs the libraries, their headers and a CMake package that find_package(orbis) finds.
include(CMakePackageConfigHelpers)

install(TARGETS orbis_core orbis_world orbis_renderer orbis_scene
  EXPORT orbisTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  FILE_SET HEADERS DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})

install(EXPORT orbisTargets
  NAMESPACE orbis::
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/orbis)

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/orbisConfig.cmake.in
  ${CMAKE_BINARY_DIR}/orbisConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/orbis)
write_basic_package_version_file(${CMAKE_BINARY_DIR}/orbisConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/orbisConfig.cmake ${CMAKE_BINARY_DIR}/orbisConfigVersion.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/orbis)
