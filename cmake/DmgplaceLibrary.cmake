# Settings every dmgplace library shares: include folders for the build and install trees, the
# export header, and for shared builds a version, a SONAME and an export list.
include(GenerateExportHeader)

# dmgplace_library(TARGET SHORT): SHORT is formats, runtime or tools.
function(dmgplace_library target short)
  string(TOUPPER ${short} upper)
  generate_export_header(${target} BASE_NAME DMGPLACE_${upper}
    EXPORT_FILE_NAME ${PROJECT_BINARY_DIR}/include/dmgplace/${short}/export.hpp)
  # include/ is what is installed, all of it; internal/ (same dmgplace/<library>/ paths) is for
  # the build tree only: the libraries, the CLI, the tests and the benchmarks.
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/internal>
    $<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON EXPORT_NAME ${short}
                                             OUTPUT_NAME dmgplace_${short})
  get_target_property(type ${target} TYPE)
  if(type STREQUAL "SHARED_LIBRARY")
    # Everything in namespace dmgplace is exported (the CLI and the tests use more than the
    # embedding API); the version script keeps every other symbol local (cmake/dmgplace_exports.map).
    # Before 1.0 each minor release may break the ABI, so the SONAME carries it (.so.0.2).
    if(PROJECT_VERSION_MAJOR EQUAL 0)
      set(soversion ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
    else()
      set(soversion ${PROJECT_VERSION_MAJOR})
    endif()
    set_target_properties(${target} PROPERTIES VERSION ${PROJECT_VERSION} SOVERSION ${soversion}
                                               CXX_VISIBILITY_PRESET default VISIBILITY_INLINES_HIDDEN ON)
    target_link_options(${target} PRIVATE "LINKER:--version-script=${PROJECT_SOURCE_DIR}/cmake/dmgplace_exports.map"
                                          "LINKER:--no-undefined")
    set_property(TARGET ${target} APPEND PROPERTY LINK_DEPENDS ${PROJECT_SOURCE_DIR}/cmake/dmgplace_exports.map)
  endif()
endfunction()
