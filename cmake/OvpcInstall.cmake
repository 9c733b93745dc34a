# The installable CMake package `ovpc`: `cmake --install build --prefix P`, then a consumer's
# find_package(ovpc) gives the imported targets ovpc::<folder> for every folder passed to
# ovpc_install_libraries (headers under P/include/ovpc/<folder>/, static libraries under P/lib), and
# find_package(ovpc COMPONENTS <name>) adds those of an optional component (ovpc_install_component).
#
# Each part is its own install component: `libraries` (the base package, its config files and the
# default preset) and one per optional component, so that `cmake --install build --component
# libraries` installs the base alone.
#
# The libraries are static, so their PRIVATE link dependencies are exported as $<LINK_ONLY:...> and
# must exist in the consumer: ovpcConfig.cmake finds CGAL and nanoflann again (and a component's own
# dependencies when it is asked for), and the export carries the two project helpers the libraries
# link PRIVATE: ovpc::warnings (its flags never reach a consumer through LINK_ONLY) and ovpc::ompl (the
# OMPL library, see OvpcOmpl.cmake). A consumer compiles against Eigen only.
include_guard(GLOBAL)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(OVPC_INSTALL_CONFIG_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/ovpc)

# Installs the folders' libraries and headers into `export_set`, all in install component `component`.
function(_ovpc_install_folders export_set component)
  set(targets)
  foreach(folder IN LISTS ARGN)
    set_target_properties(ovpc_${folder} PROPERTIES EXPORT_NAME ${folder})
    list(APPEND targets ovpc_${folder})
    install(DIRECTORY ${PROJECT_SOURCE_DIR}/${folder}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
            COMPONENT ${component})
  endforeach()
  install(TARGETS ${targets} EXPORT ${export_set} COMPONENT ${component}
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
          RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
          INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(EXPORT ${export_set} NAMESPACE ovpc:: DESTINATION ${OVPC_INSTALL_CONFIG_DIR} COMPONENT ${component})
endfunction()

# The base package: find_package(ovpc) (install component `libraries`).
function(ovpc_install_libraries)
  set_target_properties(ovpc_warnings PROPERTIES EXPORT_NAME warnings)
  set_target_properties(ovpc_ompl PROPERTIES EXPORT_NAME ompl)
  install(TARGETS ovpc_warnings ovpc_ompl EXPORT ovpcTargets COMPONENT libraries)
  _ovpc_install_folders(ovpcTargets libraries ${ARGN})

  configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/ovpcConfig.cmake.in
                                ${PROJECT_BINARY_DIR}/ovpcConfig.cmake
                                INSTALL_DESTINATION ${OVPC_INSTALL_CONFIG_DIR})
  write_basic_package_version_file(${PROJECT_BINARY_DIR}/ovpcConfigVersion.cmake
                                   VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
  install(FILES ${PROJECT_BINARY_DIR}/ovpcConfig.cmake ${PROJECT_BINARY_DIR}/ovpcConfigVersion.cmake
          DESTINATION ${OVPC_INSTALL_CONFIG_DIR} COMPONENT libraries)
endfunction()

# An optional component `name` of the package: find_package(ovpc COMPONENTS name) loads
# ovpc_<name>Targets.cmake (install component `name`). Its folders may link the base package's.
function(ovpc_install_component name)
  _ovpc_install_folders(ovpc_${name}Targets ${name} ${ARGN})
endfunction()
