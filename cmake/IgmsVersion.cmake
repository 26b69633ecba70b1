# IGMS_BUILD_VERSION: the project version and the git commit at configure time
# (a header in the build tree; reconfigure to refresh it).
set(IGMS_GIT_COMMIT "unknown")
find_package(Git QUIET)
if(GIT_FOUND AND EXISTS ${PROJECT_SOURCE_DIR}/.git)
  execute_process(COMMAND ${GIT_EXECUTABLE} describe --always --dirty --abbrev=12
                  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR} OUTPUT_VARIABLE IGMS_GIT_COMMIT
                  OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
endif()
set(IGMS_BUILD_VERSION "igms ${PROJECT_VERSION} (${IGMS_GIT_COMMIT})")
file(WRITE ${CMAKE_BINARY_DIR}/generated/igms_build_info.h.tmp
     "#pragma once\n#define IGMS_BUILD_VERSION \"${IGMS_BUILD_VERSION}\"\n")
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different ${CMAKE_BINARY_DIR}/generated/igms_build_info.h.tmp
                ${CMAKE_BINARY_DIR}/generated/igms_build_info.h)
include_directories(${CMAKE_BINARY_DIR}/generated)
