# Options: optional parts are on when their packages are found.
option(IGMS_BUILD_TESTS "Build the ctest suites" ON)
option(IGMS_BUILD_BENCH "Build the benchmarks (needs KDL as the peer)" ON)
option(IGMS_WITH_KDL "Cross-check and benchmark against KDL (tests and bench only)" ON)
option(IGMS_WITH_LCM "Build the LCM message types and transport" ON)
option(IGMS_WITH_WEB "Build the browser view (igms-viewer, the web device): websocketpp, Boost.Asio" ON)
option(IGMS_WITH_PYTHON "Build the igms Python module (nanobind from the project's .venv: scripts/setup/python_env.sh)" ON)
# -march=native with code that includes KDL headers and links Debian's KDL
# segfaults (Eigen alignment mismatch): off by default, never on KDL targets.
option(IGMS_NATIVE "Compile the dynamics library with -march=native" OFF)
# igms-peer-bench: Pinocchio and MuJoCo from their PyPI wheels (scripts/bench/bench.sh --peers sets both).
option(IGMS_PEER_BENCH "Build igms-peer-bench (needs PyPI pin and mujoco in IGMS_PEER_SITE)" OFF)
set(IGMS_PEER_SITE "" CACHE PATH "The site-packages folder holding PyPI pin and mujoco (for IGMS_PEER_BENCH)")

# What is built and what is left out, collected across directories.
function(igms_built what)
  set_property(GLOBAL APPEND PROPERTY IGMS_BUILT "${what}")
endfunction()
function(igms_left_out what why)
  set_property(GLOBAL APPEND PROPERTY IGMS_LEFT_OUT "${what} (${why})")
endfunction()

function(igms_print_summary)
  get_property(built GLOBAL PROPERTY IGMS_BUILT)
  get_property(left_out GLOBAL PROPERTY IGMS_LEFT_OUT)
  message(STATUS "igms ${PROJECT_VERSION}, ${CMAKE_BUILD_TYPE} build")
  foreach(item IN LISTS built)
    message(STATUS "  built:    ${item}")
  endforeach()
  foreach(item IN LISTS left_out)
    message(STATUS "  left out: ${item}")
  endforeach()
endfunction()
