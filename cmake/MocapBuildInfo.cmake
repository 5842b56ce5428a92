# Build info (version, git commit, dirty flag) for provenance run.json files.
# The header is generated at build time, not configure time, so a new commit is picked up by the next
# `cmake --build` without re-running cmake; BuildInfo.cmake rewrites the header only when its content
# changes, so an unchanged checkout recompiles nothing.
set(MOCAP_BUILD_INFO_DIR "${CMAKE_BINARY_DIR}/generated")
set(MOCAP_BUILD_INFO_HEADER "${MOCAP_BUILD_INFO_DIR}/mocap_build_info.h")

add_custom_target(mocap_build_info_gen
  COMMAND ${CMAKE_COMMAND}
          -DMOCAP_VERSION=${PROJECT_VERSION}
          -DMOCAP_SOURCE_DIR=${CMAKE_SOURCE_DIR}
          -DMOCAP_BUILD_INFO_HEADER=${MOCAP_BUILD_INFO_HEADER}
          -P ${CMAKE_SOURCE_DIR}/cmake/BuildInfo.cmake
  BYPRODUCTS ${MOCAP_BUILD_INFO_HEADER}
  COMMENT "Build info (git commit) for run.json"
  VERBATIM)

# Consumers get the include dir and build after the header exists (dependencies of an INTERFACE
# library are followed transitively by the targets linking it).
add_library(mocap_build_info INTERFACE)
target_include_directories(mocap_build_info INTERFACE ${MOCAP_BUILD_INFO_DIR})
add_dependencies(mocap_build_info mocap_build_info_gen)
