# The installed package: `cmake --install build --prefix P` puts the headers
# under P/include/layerlab/ (the public ones, cmake/public_headers.txt, in the
# repository's layout: layerlab.h, framework/..., systems/...), the static libraries under P/lib, the command under P/bin and
# the CMake package under P/lib/cmake/layerlab, so that a downstream project
#   find_package(layerlab 0.2 CONFIG REQUIRED [COMPONENTS Embree Ceres])
#   target_link_libraries(app PRIVATE layerlab::layerlab)
# builds against it (docs/cpp-package.md, examples/cpp_consumer/).
include(CMakePackageConfigHelpers)

# layerlab::layerlab: the library's whole core (every library but the optional
# calibration), and include/ so that <layerlab/layerlab.h> is found.
add_library(layerlab_all INTERFACE)
add_library(layerlab::layerlab ALIAS layerlab_all)
set_target_properties(layerlab_all PROPERTIES EXPORT_NAME layerlab)
target_link_libraries(layerlab_all INTERFACE layerlab::analysis)
target_include_directories(layerlab_all INTERFACE $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
install(TARGETS layerlab_all EXPORT layerlabTargets)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/cmake/public_headers.txt)
file(STRINGS ${PROJECT_SOURCE_DIR}/cmake/public_headers.txt public_headers REGEX "^[^# ]+$")
foreach(header IN LISTS public_headers)
  get_filename_component(folder ${header} DIRECTORY)
  install(FILES ${PROJECT_SOURCE_DIR}/${header} DESTINATION ${LAYERLAB_INSTALL_INCLUDEDIR}/${folder})
endforeach()
install(TARGETS layerlab RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
if(TARGET layerlab_cli_documents)  # where the shells and man(1) look for them
  install(FILES ${PROJECT_BINARY_DIR}/share/layerlab.bash DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions
          RENAME layerlab)
  install(FILES ${PROJECT_BINARY_DIR}/share/_layerlab DESTINATION ${CMAKE_INSTALL_DATADIR}/zsh/vendor-completions)
  install(FILES ${PROJECT_BINARY_DIR}/share/layerlab.1 DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
endif()

set(LAYERLAB_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/layerlab)
install(EXPORT layerlabTargets NAMESPACE layerlab:: DESTINATION ${LAYERLAB_CMAKEDIR})
if(LAYERLAB_WITH_CERES)
  install(EXPORT layerlabCeresTargets NAMESPACE layerlab:: DESTINATION ${LAYERLAB_CMAKEDIR})
endif()
# Before 1.0 a minor version may change the interface: 0.2 accepts 0.2.x only.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/layerlabConfigVersion.cmake COMPATIBILITY SameMinorVersion)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/layerlabConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/layerlabConfig.cmake INSTALL_DESTINATION ${LAYERLAB_CMAKEDIR})
install(FILES ${PROJECT_BINARY_DIR}/layerlabConfig.cmake ${PROJECT_BINARY_DIR}/layerlabConfigVersion.cmake
        DESTINATION ${LAYERLAB_CMAKEDIR})
