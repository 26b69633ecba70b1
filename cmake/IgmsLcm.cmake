# igms_lcm_types(<target> <file.lcm>...): runs lcm-gen at build time and gives
# <target> (an INTERFACE library) the generated C++ headers, their decoders
# bounded (IgmsLcmBounds.cmake). Nothing generated is committed.
set(IGMS_LCM_BOUNDS_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/IgmsLcmBounds.cmake)
function(igms_lcm_types target)
  set(out_dir ${CMAKE_CURRENT_BINARY_DIR}/generated)
  set(headers "")
  foreach(lcm_file IN LISTS ARGN)
    get_filename_component(abs ${lcm_file} ABSOLUTE)
    # The package is the first 'package x;' line; the type is the struct name.
    file(STRINGS ${abs} pkg_line REGEX "^package[ \t]+[A-Za-z0-9_]+;")
    string(REGEX MATCH "package[ \t]+([A-Za-z0-9_]+)" _ "${pkg_line}")
    set(pkg "${CMAKE_MATCH_1}")
    file(STRINGS ${abs} struct_lines REGEX "^struct[ \t]+[A-Za-z0-9_]+")
    foreach(line IN LISTS struct_lines)
      string(REGEX REPLACE "^struct[ \t]+([A-Za-z0-9_]+).*" "\\1" name "${line}")
      list(APPEND outputs ${out_dir}/${pkg}/${name}.hpp)
    endforeach()
    set(these ${outputs})
    set(bound_commands "")
    foreach(header IN LISTS these)
      list(APPEND bound_commands COMMAND ${CMAKE_COMMAND} -DHEADER=${header} -P ${IGMS_LCM_BOUNDS_SCRIPT})
    endforeach()
    add_custom_command(
      OUTPUT ${these}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${out_dir}
      COMMAND ${LCM_GEN} --cpp --cpp-std c++11 --cpp-hpath ${out_dir} ${abs}
      ${bound_commands}
      DEPENDS ${abs} ${IGMS_LCM_BOUNDS_SCRIPT}
      COMMENT "lcm-gen ${lcm_file}"
      VERBATIM)
    list(APPEND headers ${these})
    set(outputs "")
  endforeach()
  add_custom_target(${target}_gen DEPENDS ${headers})
  add_library(${target} INTERFACE)
  add_dependencies(${target} ${target}_gen)
  target_include_directories(${target} INTERFACE $<BUILD_INTERFACE:${out_dir}> $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}>
                                                 $<INSTALL_INTERFACE:include/igms/lcmtypes>)
  target_link_libraries(${target} INTERFACE lcm::lcm)
endfunction()
