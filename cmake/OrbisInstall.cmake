# Installs the libraries as components of one CMake package (find_package(orbis COMPONENTS ...)),
# their headers, orbis_embed_shaders, the orbis command with the data/ it reads, and the docs.
include(CMakePackageConfigHelpers)
set(ORBIS_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/orbis)

# One export set per component, so that a component loads only its own and its dependencies'
# targets (cmake/orbisConfig.cmake.in says which components need which).
foreach(component core world renderer window scene)
  install(TARGETS orbis_${component}
    EXPORT orbis-${component}-targets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
    FILE_SET HEADERS DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(EXPORT orbis-${component}-targets
    NAMESPACE orbis::
    DESTINATION ${ORBIS_CMAKE_DIR})
endforeach()

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/orbisConfig.cmake.in
  ${CMAKE_BINARY_DIR}/orbisConfig.cmake
  INSTALL_DESTINATION ${ORBIS_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/orbisConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/orbisConfig.cmake ${CMAKE_BINARY_DIR}/orbisConfigVersion.cmake
  ${CMAKE_CURRENT_LIST_DIR}/OrbisEmbedShaders.cmake
  DESTINATION ${ORBIS_CMAKE_DIR})

# The orbis command and the data/ its example scenes and paths read (SceneExample.h:
# dataDirectory finds it from the installed program). The gazetteer (geonames/) only feeds the
# chapter 9 example and the bench, which are not installed.
if(TARGET orbis)
  install(TARGETS orbis RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/data/ DESTINATION ${CMAKE_INSTALL_DATADIR}/orbis/data
    PATTERN geonames EXCLUDE)
endif()
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR})
