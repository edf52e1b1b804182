# `cmake --install`: headers, libraries, the CMake package (find_package(dmgplace) with targets
# dmgplace::formats, dmgplace::runtime and, as a component, dmgplace::tools) and dmgplace.pc.
include(CMakePackageConfigHelpers)
set(DMGPLACE_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/dmgplace)
set(inc ${CMAKE_INSTALL_INCLUDEDIR}/dmgplace)

# Public headers: each library's include/ folder, all of it (internal/ is never installed). formats:
# the artifact API; runtime: the embedding API (dmgplace/runtime.hpp) and the plain types it uses,
# no OMPL, FCL or Embree type; tools: the offline API.
foreach(lib formats runtime tools)
  install(DIRECTORY ${lib}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endforeach()
install(DIRECTORY ${PROJECT_BINARY_DIR}/include/dmgplace DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})  # export.hpp

# Libraries. Helper INTERFACE targets (system include paths, absolute library paths) go along so
# that a static build's link dependencies resolve in the consumer.
set_target_properties(dmgplace_formats dmgplace_runtime dmgplace_query dmgplace_tools PROPERTIES INSTALL_RPATH "$ORIGIN")
set_target_properties(dmgplace PROPERTIES INSTALL_RPATH "$ORIGIN/../${CMAKE_INSTALL_LIBDIR}")
install(TARGETS dmgplace_formats dmgplace_runtime dmgplace_query dmgplace_hdf5 dmgplace_ompl EXPORT dmgplaceTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS dmgplace_tools dmgplace_pcl dmgplace_urdfdom EXPORT dmgplaceToolsTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS dmgplace RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT dmgplaceTargets NAMESPACE dmgplace:: DESTINATION ${DMGPLACE_CMAKE_DIR})
install(EXPORT dmgplaceToolsTargets NAMESPACE dmgplace:: DESTINATION ${DMGPLACE_CMAKE_DIR})

configure_package_config_file(cmake/dmgplaceConfig.cmake.in ${PROJECT_BINARY_DIR}/dmgplaceConfig.cmake
                              INSTALL_DESTINATION ${DMGPLACE_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/dmgplaceConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/dmgplaceConfig.cmake ${PROJECT_BINARY_DIR}/dmgplaceConfigVersion.cmake
        DESTINATION ${DMGPLACE_CMAKE_DIR})

# pkg-config: the runtime (formats + runtime), the embedding use. A static build lists the
# libraries' own dependencies as Libs.private.
if(BUILD_SHARED_LIBS)
  set(DMGPLACE_PC_LIBS_PRIVATE "")
else()
  set(DMGPLACE_PC_LIBS_PRIVATE "-lompl -lfcl -loctomap -loctomath -lhdf5_serial -lcrypto -lpthread")
endif()
configure_file(cmake/dmgplace.pc.in ${PROJECT_BINARY_DIR}/dmgplace.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/dmgplace.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
