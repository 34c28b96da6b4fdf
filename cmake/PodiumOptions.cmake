# Build options shared by every folder (docs/style.md "Tests, headers, names, build").
option(PODIUM_SANITIZE "Build with address and undefined-behaviour sanitizers" OFF)
option(PODIUM_TSAN "Build with the thread sanitizer (scheduler work)" OFF)
option(PODIUM_WERROR "Treat warnings as errors" ON)
# The sanitizer builds (CMakePresets.json) run tests only; the benchmarks would double their build time.
option(PODIUM_BUILD_BENCH "Build the benchmarks in bench/" ON)

if(NOT CMAKE_BUILD_TYPE AND NOT CMAKE_CONFIGURATION_TYPES)
  set(CMAKE_BUILD_TYPE Release CACHE STRING "Build type" FORCE)
endif()

set(CMAKE_CXX_STANDARD 20)
set(CMAKE_CXX_STANDARD_REQUIRED ON)
set(CMAKE_CXX_EXTENSIONS OFF)
set(CMAKE_POSITION_INDEPENDENT_CODE ON)
set(CMAKE_EXPORT_COMPILE_COMMANDS ON)

find_program(CCACHE_PROGRAM ccache)
if(CCACHE_PROGRAM)
  # base_dir makes cache hits survive a fresh clone in another folder (CI).
  set(CMAKE_CXX_COMPILER_LAUNCHER ${CMAKE_COMMAND} -E env CCACHE_BASEDIR=${CMAKE_SOURCE_DIR} CCACHE_NOHASHDIR=1 ${CCACHE_PROGRAM})
endif()

# Our own warnings: applied per target so third-party headers are not affected.
function(podium_warnings target)
  # -Wno-restrict: GCC 12 reports false positives inside std::string concatenation (GCC bug 105329).
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wno-restrict)
  # The sanitizers' instrumentation makes GCC 12 report uninitialised reads inside libstdc++'s
  # std::regex and std::function that are not there (GCC bug 105562); Release builds keep the warning.
  if(PODIUM_SANITIZE OR PODIUM_TSAN)
    target_compile_options(${target} PRIVATE -Wno-maybe-uninitialized)
  endif()
  if(PODIUM_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

if(PODIUM_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
if(PODIUM_TSAN)
  add_compile_options(-fsanitize=thread)
  add_link_options(-fsanitize=thread)
endif()

# One folder = one library target podium_<folder>, public headers in <folder>/include.
function(podium_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(podium_${name} ${ARG_SOURCES})
  target_include_directories(podium_${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include
                                            PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
  target_link_libraries(podium_${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  podium_warnings(podium_${name})
endfunction()

# A GoogleTest executable registered with CTest; LABELS default to "unit".
function(podium_test name)
  cmake_parse_arguments(ARG "SERIAL" "TIMEOUT;RESOURCE_LOCK" "SOURCES;DEPS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  # podium_test_main (tests/support) sets PODIUM_BIN, PODIUM_PLUGIN_PATH and PODIUM_SHARED_DIR.
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} GTest::gtest podium_test_main)
  podium_warnings(${name})
  if(NOT ARG_LABELS)
    set(ARG_LABELS unit)
  endif()
  # A second label names the layer under test (tests/<layer>/...), e.g. dir:store, so a
  # sanitizer run can pick layers: ctest -L unit -L '^dir:(store|orchestrator)$'.
  file(RELATIVE_PATH rel ${CMAKE_SOURCE_DIR}/tests ${CMAKE_CURRENT_SOURCE_DIR})
  string(REGEX REPLACE "/.*" "" layer "${rel}")
  if(layer AND NOT layer MATCHES "^\\.\\.")
    # The unit-test executables of a layer, as one target (unit_tests_<layer>), so a sanitizer
    # build can build just the layers it runs.
    if("unit" IN_LIST ARG_LABELS)
      if(NOT TARGET unit_tests_${layer})
        add_custom_target(unit_tests_${layer})
      endif()
      add_dependencies(unit_tests_${layer} ${name})
    endif()
    list(APPEND ARG_LABELS dir:${layer})
  endif()
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 300)
  endif()
  # Sanitized code runs several times slower (ASan about 2-3x, TSan 5-15x); the limits are for hangs.
  if(PODIUM_SANITIZE OR PODIUM_TSAN)
    math(EXPR ARG_TIMEOUT "${ARG_TIMEOUT} * 5")
  endif()
  # RESOURCE_LOCK: tests sharing a resource (e.g. the test Slurm cluster) never run at once.
  set(lock)
  if(ARG_RESOURCE_LOCK)
    set(lock RESOURCE_LOCK ${ARG_RESOURCE_LOCK})
  endif()
  # SERIAL: the test measures throughput, so nothing else may run beside it.
  if(ARG_SERIAL)
    list(APPEND lock RUN_SERIAL TRUE)
  endif()
  gtest_discover_tests(${name} PROPERTIES TIMEOUT ${ARG_TIMEOUT} ${lock} DISCOVERY_TIMEOUT 60)
  # gtest_discover_tests flattens a list-valued property (LABELS "unit;dir:x" would set LABELS to
  # "unit" and a property named "dir:x"), so the labels are set by a script CTest reads after the
  # discovered tests, on the list it defines (<name>_TESTS).
  set(label_script ${CMAKE_CURRENT_BINARY_DIR}/${name}_labels.cmake)
  file(WRITE ${label_script} "if(${name}_TESTS)\n  set_tests_properties(\${${name}_TESTS} PROPERTIES LABELS \"${ARG_LABELS}\")\nendif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${label_script})
endfunction()
