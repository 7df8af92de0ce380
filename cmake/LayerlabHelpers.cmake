# One helper per kind of target.

# layerlab_leave_out(OPTION PART REASON ERROR), in an optional part's cmake/
# file: leaves PART out (listed with REASON at the end of the configuration)
# and returns from that file, or stops with "OPTION=ON ERROR" when OPTION asked
# for the part. A macro, so that return() leaves the including file.
macro(layerlab_leave_out option part reason error)
  if(${option} STREQUAL "ON")
    message(FATAL_ERROR "${option}=ON ${error}")
  endif()
  list(APPEND LAYERLAB_LEFT_OUT "${part} (${reason})")
  return()
endmacro()

# layerlab_add_library(NAME SOURCES ... DEPS ... [EXPORT SET]): a static library
# under the namespaced alias layerlab::NAME, whose includes read
# "layerlab/<folder>/<file>.h". It is installed (cmake/LayerlabInstall.cmake)
# and exported as layerlab::NAME in the export set SET (default
# layerlabTargets; an optional part has its own); its public headers are
# installed with the others (cmake/public_headers.txt).
function(layerlab_add_library name)
  cmake_parse_arguments(ARG "" "EXPORT" "SOURCES;DEPS" ${ARGN})
  if(NOT ARG_EXPORT)
    set(ARG_EXPORT layerlabTargets)
  endif()
  add_library(layerlab_${name} STATIC ${ARG_SOURCES})
  add_library(layerlab::${name} ALIAS layerlab_${name})
  set_target_properties(layerlab_${name} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(layerlab_${name} PUBLIC $<BUILD_INTERFACE:${LAYERLAB_BUILD_INCLUDEDIR}>
                                                     $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(layerlab_${name} PUBLIC ${ARG_DEPS} PRIVATE $<BUILD_INTERFACE:layerlab_warnings>)
  install(TARGETS layerlab_${name} EXPORT ${ARG_EXPORT} ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
endfunction()

# layerlab_add_test(NAME SOURCES ... DEPS ...): a GoogleTest executable whose
# tests ctest discovers one by one. LAYERLAB_DATA_DIR points at ../shared/data
# when it exists (tests that need it skip otherwise).
function(layerlab_add_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} layerlab_test_support GTest::gtest_main layerlab_warnings)
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT 600)
endfunction()
