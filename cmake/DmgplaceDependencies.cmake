# Every dependency is a Debian package (scripts/deps installs them).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(HDF5 REQUIRED COMPONENTS C)
find_package(OpenSSL REQUIRED COMPONENTS Crypto)  # SHA-256 (libcrypto; HDF5 links it already)
find_package(CLI11 REQUIRED)
find_package(spdlog REQUIRED)  # the command line's messages (tools/cli/cli_log)
find_package(yaml-cpp REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(assimp REQUIRED)
find_package(urdfdom REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(TINYXML2 REQUIRED IMPORTED_TARGET tinyxml2)
find_package(PCL 1.12 REQUIRED COMPONENTS common io features filters kdtree octree sample_consensus search segmentation surface)
find_package(CGAL REQUIRED)
find_package(embree 3 REQUIRED)
find_package(Threads REQUIRED)
find_package(fcl 0.7 REQUIRED)
find_package(octomap REQUIRED)
find_package(ompl REQUIRED)
# OMPL ships no imported target.
add_library(dmgplace_ompl INTERFACE)
target_include_directories(dmgplace_ompl SYSTEM INTERFACE ${OMPL_INCLUDE_DIRS})
target_link_libraries(dmgplace_ompl INTERFACE ${OMPL_LIBRARIES})

# HDF5 as one imported target with SYSTEM includes.
add_library(dmgplace_hdf5 INTERFACE)
target_include_directories(dmgplace_hdf5 SYSTEM INTERFACE ${HDF5_INCLUDE_DIRS})
target_link_libraries(dmgplace_hdf5 INTERFACE ${HDF5_C_LIBRARIES})
target_compile_definitions(dmgplace_hdf5 INTERFACE ${HDF5_DEFINITIONS})

# PCL: only the modules we use (PCL_LIBRARIES would drag in VTK).
add_library(dmgplace_pcl INTERFACE)
target_include_directories(dmgplace_pcl SYSTEM INTERFACE ${PCL_INCLUDE_DIRS})
target_link_libraries(dmgplace_pcl INTERFACE pcl_common pcl_io pcl_features pcl_filters pcl_kdtree pcl_sample_consensus pcl_search pcl_segmentation pcl_surface pcl_octree)

add_library(dmgplace_urdfdom INTERFACE)
target_include_directories(dmgplace_urdfdom SYSTEM INTERFACE ${urdfdom_INCLUDE_DIRS})
target_link_libraries(dmgplace_urdfdom INTERFACE ${urdfdom_LIBRARIES})
