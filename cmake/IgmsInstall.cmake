# igms as a package: `cmake --install build --prefix P` puts the core layers
# and the message types (static libraries and headers), the programs, the
# page of the browser view, the Python message types and a CMake package
# (find_package(igms): igms::model ... igms::simulation, igms::lcmtypes) and a
# pkg-config file (igms.pc) under P. tests/package/ builds a downstream project
# against it.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(IGMS_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/igms)
set(igms_export_targets igms_model igms_kinematics igms_dynamics igms_model_io igms_integrate igms_realtime
    igms_geometry igms_contact igms_interaction igms_trajectory igms_scene igms_simulation igms_device_plugin)
if(IGMS_WITH_LCM)
  list(APPEND igms_export_targets igms_lcmtypes)
endif()
install(TARGETS ${igms_export_targets} EXPORT igmsTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/igms)
install(EXPORT igmsTargets NAMESPACE igms:: DESTINATION ${IGMS_INSTALL_CMAKEDIR})

# The device plugin ABI, for plugins built against the package: <igms/device_plugin.h>.
install(FILES ${PROJECT_SOURCE_DIR}/haptic_client/device/device_plugin.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/igms)
# Headers keep their paths ("core/dynamics/rnea.h") under include/igms.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/core/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/igms/core
        FILES_MATCHING PATTERN "*.h" PATTERN "cli" EXCLUDE)
if(IGMS_WITH_LCM)
  # The generated message headers ("igms/robot_state_t.hpp", bounded decoders) and channels.h, safe_decode.h.
  install(DIRECTORY ${PROJECT_BINARY_DIR}/lcmtypes/generated/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/igms/lcmtypes
          FILES_MATCHING PATTERN "*.hpp")
  install(FILES ${PROJECT_SOURCE_DIR}/lcmtypes/channels.h ${PROJECT_SOURCE_DIR}/lcmtypes/safe_decode.h
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/igms/lcmtypes)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/lcmtypes/ DESTINATION ${CMAKE_INSTALL_DATADIR}/igms/lcmtypes
          FILES_MATCHING PATTERN "*.lcm")
endif()

# The programs, and what they read at run time.
foreach(program igms-server igms-haptic igms-dyn igms-logger igms-replay igms-scenario igms-viewer igms-relay igms-command
                igms-spy igms-accuracy igms-ode-ref)
  if(TARGET ${program})
    install(TARGETS ${program} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  endif()
endforeach()
if(IGMS_WITH_WEB)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/web/page/ DESTINATION ${CMAKE_INSTALL_DATADIR}/igms/web/page)
endif()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenes ${PROJECT_SOURCE_DIR}/models DESTINATION ${CMAKE_INSTALL_DATADIR}/igms)

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/igmsConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/igmsConfig.cmake INSTALL_DESTINATION ${IGMS_INSTALL_CMAKEDIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/igmsConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/igmsConfig.cmake ${PROJECT_BINARY_DIR}/igmsConfigVersion.cmake
        DESTINATION ${IGMS_INSTALL_CMAKEDIR})

# pkg-config: the whole core in link order (libraries before what they use).
set(IGMS_PC_LCM_LIBS "")
set(IGMS_PC_LCM_CFLAGS "")
if(IGMS_WITH_LCM)
  set(IGMS_PC_LCM_LIBS "-llcm")  # Debian's lcm.pc needs glib's .pc: link it directly
  set(IGMS_PC_LCM_CFLAGS "-I\${includedir}/igms/lcmtypes")
endif()
# Relocatable: the prefix is found from the .pc file's own folder.
string(REGEX REPLACE "[^/]+" ".." IGMS_PC_PREFIX_REL "${CMAKE_INSTALL_LIBDIR}/pkgconfig")
configure_file(${PROJECT_SOURCE_DIR}/cmake/igms.pc.in ${PROJECT_BINARY_DIR}/igms.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/igms.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
igms_built("install rules, find_package(igms), igms.pc")
