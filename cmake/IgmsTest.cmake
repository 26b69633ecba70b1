# igms_add_test(<name> SOURCES ... LIBS ... LABEL <unit|crosscheck|replay|integration|stress>)
# A GoogleTest executable registered with ctest under its label.
function(igms_add_test name)
  cmake_parse_arguments(T "" "LABEL;TIMEOUT" "SOURCES;LIBS" ${ARGN})
  add_executable(${name} ${T_SOURCES})
  target_link_libraries(${name} PRIVATE ${T_LIBS} GTest::gtest GTest::gtest_main)
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR})
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 600)
  endif()
  add_test(NAME ${name} COMMAND ${name} --gtest_color=no)
  set_tests_properties(${name} PROPERTIES LABELS "${T_LABEL}" TIMEOUT ${T_TIMEOUT}
                       ENVIRONMENT "IGMS_SOURCE_DIR=${PROJECT_SOURCE_DIR}")
endfunction()

# igms_add_netns_test(<name> SOURCES ... LIBS ... PORT <udp port> [ENV k=v ...])
# A GoogleTest binary that opens udpm:// sockets: ctest runs it inside a private
# network namespace (scripts/netns_run.sh), on a port of its own.
function(igms_add_netns_test name)
  cmake_parse_arguments(T "" "PORT;TIMEOUT" "SOURCES;LIBS;ENV" ${ARGN})
  add_executable(${name} ${T_SOURCES})
  target_link_libraries(${name} PRIVATE ${T_LIBS} GTest::gtest GTest::gtest_main)
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR})
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 300)
  endif()
  add_test(NAME ${name} COMMAND ${PROJECT_SOURCE_DIR}/scripts/netns_run.sh $<TARGET_FILE:${name}> --gtest_color=no)
  set_tests_properties(${name} PROPERTIES LABELS integration TIMEOUT ${T_TIMEOUT}
    ENVIRONMENT "IGMS_TEST_PORT=${T_PORT};IGMS_SOURCE_DIR=${PROJECT_SOURCE_DIR};${T_ENV}")
endfunction()
