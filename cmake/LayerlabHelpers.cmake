# One helper per kind of target.

# layerlab_add_library(NAME SOURCES ... DEPS ...): a static library under the
# namespaced alias layerlab::NAME, with the repository root on its include path.
function(layerlab_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_library(layerlab_${name} STATIC ${ARG_SOURCES})
  add_library(layerlab::${name} ALIAS layerlab_${name})
  target_include_directories(layerlab_${name} PUBLIC ${PROJECT_SOURCE_DIR})
  target_link_libraries(layerlab_${name} PUBLIC ${ARG_DEPS} PRIVATE layerlab_warnings)
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
