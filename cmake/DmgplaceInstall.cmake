# `cmake --install`: headers, libraries, the CMake package (find_package(dmgplace) with targets
# dmgplace::formats, dmgplace::runtime and, as a component, dmgplace::tools) and dmgplace.pc.
include(CMakePackageConfigHelpers)
set(DMGPLACE_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/dmgplace)
set(inc ${CMAKE_INSTALL_INCLUDEDIR}/dmgplace)

# Public headers. formats: the artifact API, all of it. runtime: the embedding API
# (dmgplace/runtime.hpp) and the plain types it uses; the planner's own headers, which name OMPL
# types, stay in the source tree. tools: the offline API but the benchmark baseline.
install(DIRECTORY formats/include/dmgplace/formats DESTINATION ${inc})
install(FILES runtime/include/dmgplace/runtime.hpp DESTINATION ${inc})
install(FILES runtime/include/dmgplace/runtime/types.hpp DESTINATION ${inc}/runtime)
install(FILES runtime/include/dmgplace/runtime/placement/placement_query.hpp
              runtime/include/dmgplace/runtime/placement/placement_result.hpp DESTINATION ${inc}/runtime/placement)
install(DIRECTORY runtime/include/dmgplace/runtime/grasp DESTINATION ${inc}/runtime)
install(FILES runtime/include/dmgplace/runtime/robot/kinematics.hpp DESTINATION ${inc}/runtime/robot)
install(FILES runtime/include/dmgplace/runtime/system/available_cpus.hpp DESTINATION ${inc}/runtime/system)
install(DIRECTORY tools/include/dmgplace/tools DESTINATION ${inc}
        PATTERN "arm_problem.hpp" EXCLUDE    # bench-mbm's problems: the planner internals it names are not installed
        PATTERN "yaml_file.hpp" EXCLUDE)     # yaml-cpp types
install(DIRECTORY ${PROJECT_BINARY_DIR}/include/dmgplace DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})  # export.hpp

# Libraries. Helper INTERFACE targets (system include paths, absolute library paths) go along so
# that a static build's link dependencies resolve in the consumer.
set_target_properties(dmgplace_formats dmgplace_runtime dmgplace_tools PROPERTIES INSTALL_RPATH "$ORIGIN")
set_target_properties(dmgplace PROPERTIES INSTALL_RPATH "$ORIGIN/../${CMAKE_INSTALL_LIBDIR}")
install(TARGETS dmgplace_formats dmgplace_runtime dmgplace_hdf5 dmgplace_ompl EXPORT dmgplaceTargets
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
