# The installable CMake package `ovpc`: `cmake --install build --prefix P`, then a consumer's
# find_package(ovpc) gives the imported targets ovpc::<folder> for every folder passed to
# ovpc_install_libraries (headers under P/include/ovpc/<folder>/, static libraries under P/lib).
#
# The libraries are static, so their PRIVATE link dependencies are exported as $<LINK_ONLY:...> and
# must exist in the consumer: ovpcConfig.cmake finds CGAL and nanoflann again, and the export carries
# the two project helpers the libraries link PRIVATE: ovpc::warnings (its flags never reach a
# consumer through LINK_ONLY) and ovpc::ompl (the OMPL library, see OvpcOmpl.cmake). A consumer
# compiles against Eigen only.
include_guard(GLOBAL)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

function(ovpc_install_libraries)
  set(targets)
  foreach(folder IN LISTS ARGN)
    set_target_properties(ovpc_${folder} PROPERTIES EXPORT_NAME ${folder})
    list(APPEND targets ovpc_${folder})
    install(DIRECTORY ${PROJECT_SOURCE_DIR}/${folder}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  endforeach()
  set_target_properties(ovpc_warnings PROPERTIES EXPORT_NAME warnings)
  set_target_properties(ovpc_ompl PROPERTIES EXPORT_NAME ompl)
  install(TARGETS ${targets} ovpc_warnings ovpc_ompl EXPORT ovpcTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
          RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
          INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})

  set(config_dir ${CMAKE_INSTALL_LIBDIR}/cmake/ovpc)
  install(EXPORT ovpcTargets NAMESPACE ovpc:: DESTINATION ${config_dir})
  configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/ovpcConfig.cmake.in
                                ${PROJECT_BINARY_DIR}/ovpcConfig.cmake
                                INSTALL_DESTINATION ${config_dir})
  write_basic_package_version_file(${PROJECT_BINARY_DIR}/ovpcConfigVersion.cmake
                                   VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
  install(FILES ${PROJECT_BINARY_DIR}/ovpcConfig.cmake ${PROJECT_BINARY_DIR}/ovpcConfigVersion.cmake
          DESTINATION ${config_dir})
endfunction()
