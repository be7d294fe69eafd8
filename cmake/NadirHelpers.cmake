# Warnings and sanitizers for project code only.
set(NADIR_WARNINGS -Wall -Wextra -Werror)

# Debug information of the Debug and RelWithDebInfo builds: "full" (-g) or
# "lines" (-g1: functions and file:line, enough for backtraces and sanitizer
# reports, no variables; about a third less compile time and objects a tenth
# the size). GCC generates the same code either way. CI builds with lines.
set(NADIR_DEBUG_INFO full CACHE STRING "Debug information: full or lines")
set_property(CACHE NADIR_DEBUG_INFO PROPERTY STRINGS full lines)
if(NOT NADIR_DEBUG_INFO MATCHES "^(full|lines)$")
  message(FATAL_ERROR "NADIR_DEBUG_INFO is '${NADIR_DEBUG_INFO}'; allowed: full, lines")
endif()

function(nadir_target_defaults target)
  target_compile_options(${target} PRIVATE ${NADIR_WARNINGS})
  if(NADIR_DEBUG_INFO STREQUAL "lines")
    target_compile_options(${target} PRIVATE $<$<CONFIG:Debug,RelWithDebInfo>:-g1>)
  endif()
  set_property(GLOBAL APPEND PROPERTY NADIR_COMPILED_TARGETS ${target})
  if(NADIR_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
endfunction()

# nadir_library(NAME SOURCES ... DEPS ...): one library per folder.
function(nadir_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_library(${name} STATIC ${ARG_SOURCES})
  target_include_directories(${name} PUBLIC ${CMAKE_SOURCE_DIR})
  target_link_libraries(${name} PUBLIC ${ARG_DEPS})
  set_target_properties(${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  nadir_target_defaults(${name})
endfunction()

# nadir_executable(nadir_NAME SOURCES ... DEPS ...): lands in build/bin/.
function(nadir_executable name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS})
  nadir_target_defaults(${name})
  set_property(GLOBAL APPEND PROPERTY NADIR_PROGRAMS ${name})
endfunction()

# Called once, after every target is defined: `nadir_programs` builds every
# program (no tests, benchmarks), `nadir_demo_programs` only what
# launch_scripts/demo.sh runs (setup.sh --demo).
function(nadir_program_targets)
  get_property(programs GLOBAL PROPERTY NADIR_PROGRAMS)
  add_custom_target(nadir_programs)
  add_dependencies(nadir_programs ${programs})
  if(TARGET nadir_lcmtypes_jar)
    add_dependencies(nadir_programs nadir_lcmtypes_jar)  # lcm-spy's types
  endif()
  add_custom_target(nadir_demo_programs)
  foreach(program nadir_sim nadir_tracker nadir_vo_solver nadir_yaw_fusion nadir_log nadir_eval)
    if(TARGET ${program})
      add_dependencies(nadir_demo_programs ${program})
    endif()
  endforeach()
endfunction()

# nadir_test(NAME SOURCES ... DEPS ... [LABELS ...] [TIMEOUT s]): a GoogleTest
# executable registered with ctest, run with the checkout as working directory
# (TIMEOUT doubled in the ASan/UBSan build).
function(nadir_test name)
  cmake_parse_arguments(ARG "" "TIMEOUT" "SOURCES;DEPS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gmock GTest::gtest_main)
  target_compile_definitions(${name} PRIVATE
    NADIR_SOURCE_DIR="${CMAKE_SOURCE_DIR}" NADIR_BINARY_DIR="${CMAKE_BINARY_DIR}")
  nadir_target_defaults(${name})
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 300)
  endif()
  if(NADIR_SANITIZE)
    # A timeout is there to stop a hung suite, not to time it: machines of
    # this kind differ up to 3x, and ASan/UBSan slows the solvers 10-30x.
    math(EXPR ARG_TIMEOUT "${ARG_TIMEOUT} * 2")
  endif()
  add_test(NAME ${name} COMMAND ${name} WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
  set_tests_properties(${name} PROPERTIES TIMEOUT ${ARG_TIMEOUT} LABELS "${ARG_LABELS}"
    ENVIRONMENT "NADIR_BIN_DIR=${CMAKE_BINARY_DIR}/bin")
  # Tests on the shared udpm group must not overlap (they would hear each
  # other), nor may tests that host Aravis fake GigE cameras on the same
  # loopback (label netns): they share the GigE Vision control port.
  set(locks "")
  if("udpm" IN_LIST ARG_LABELS)
    list(APPEND locks udpm)
  endif()
  if("netns" IN_LIST ARG_LABELS)
    list(APPEND locks gige_loopback)
  endif()
  if(locks)
    set_tests_properties(${name} PROPERTIES RESOURCE_LOCK "${locks}")
  endif()
endfunction()

# nadir_benchmark(nadir_bench_NAME SOURCES ... DEPS ...): Google Benchmark
# executable in build/bin/; not run by ctest (timings are never pass/fail).
function(nadir_benchmark name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} benchmark::benchmark benchmark::benchmark_main)
  target_compile_definitions(${name} PRIVATE NADIR_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
  nadir_target_defaults(${name})
endfunction()

# NADIR_MODULES (a ;-list, empty = all) restricts which folders are built,
# so one module can be worked on while another is mid-change.
set(NADIR_MODULES "" CACHE STRING "Only these process/tool folders (empty: all)")

# Adds every direct subfolder of `parent` that has a CMakeLists.txt, sorted.
function(nadir_add_module_folders parent)
  file(GLOB children LIST_DIRECTORIES true RELATIVE ${CMAKE_SOURCE_DIR}/${parent}
       ${CMAKE_SOURCE_DIR}/${parent}/*)
  list(SORT children)
  foreach(child ${children})
    if(NADIR_MODULES AND NOT child IN_LIST NADIR_MODULES)
      continue()
    endif()
    if(EXISTS ${CMAKE_SOURCE_DIR}/${parent}/${child}/CMakeLists.txt)
      add_subdirectory(${CMAKE_SOURCE_DIR}/${parent}/${child} ${CMAKE_BINARY_DIR}/${parent}/${child})
    endif()
  endforeach()
endfunction()

# Precompiled headers for the test suites: the third-party headers most of
# them include (the standard library, Eigen, OpenCV, LCM, yaml-cpp,
# GoogleTest) are parsed once per build instead of once per source (about a
# fifth less compile time for a suite's source). Only suites: the forced
# include changes how GCC instantiates and inlines, so the libraries and
# programs keep their own parse and exactly the code they had. Only suites
# that link nadir_common (and so already see these headers' include folders
# and flags) use it. CMake builds with -Winvalid-pch, so with -Werror a flag
# mismatch fails instead of silently parsing the headers again.
# NADIR_PRECOMPILED_HEADERS=OFF builds without; it is the default under a
# ccache launcher, which does not cache sources compiled with a precompiled
# header unless its sloppiness setting allows it.
if(CMAKE_CXX_COMPILER_LAUNCHER MATCHES "ccache")
  option(NADIR_PRECOMPILED_HEADERS "Precompile the test suites' third-party headers" OFF)
else()
  option(NADIR_PRECOMPILED_HEADERS "Precompile the test suites' third-party headers" ON)
endif()
set(NADIR_PCH_HEADERS
  <algorithm> <array> <chrono> <cmath> <cstdint> <cstdio> <cstdlib> <cstring> <deque>
  <fstream> <functional> <limits> <map> <memory> <mutex> <optional> <random> <set>
  <sstream> <stdexcept> <string> <thread> <utility> <vector>
  <Eigen/Dense> <opencv2/core.hpp> <opencv2/imgproc.hpp> <lcm/lcm-cpp.hpp> <yaml-cpp/yaml.h>
  <gtest/gtest.h> <gmock/gmock.h>)

# True in `out` when `target` links `wanted`, directly or through nadir targets.
function(nadir_links target wanted out)
  get_target_property(deps ${target} LINK_LIBRARIES)
  set(${out} FALSE PARENT_SCOPE)
  foreach(dep IN LISTS deps)
    if(dep STREQUAL wanted)
      set(${out} TRUE PARENT_SCOPE)
      return()
    endif()
    if(TARGET ${dep} AND dep MATCHES "^nadir_")
      get_target_property(type ${dep} TYPE)
      if(NOT type STREQUAL "INTERFACE_LIBRARY")
        nadir_links(${dep} ${wanted} found)
        if(found)
          set(${out} TRUE PARENT_SCOPE)
          return()
        endif()
      endif()
    endif()
  endforeach()
endfunction()

# Called once, after every target is defined.
function(nadir_precompile_headers)
  if(NOT NADIR_PRECOMPILED_HEADERS)
    return()
  endif()
  get_property(targets GLOBAL PROPERTY NADIR_COMPILED_TARGETS)
  foreach(target IN LISTS targets)
    nadir_links(${target} GTest::gtest is_suite)
    nadir_links(${target} nadir_common links_common)
    if(NOT is_suite OR NOT links_common)
      continue()
    endif()
    if(NOT TARGET nadir_pch_suite)
      set(pch_source ${CMAKE_BINARY_DIR}/nadir_pch.cc)
      file(CONFIGURE OUTPUT ${pch_source} CONTENT "// Only carries the precompiled header.\n")
      add_library(nadir_pch_suite OBJECT ${pch_source})
      target_link_libraries(nadir_pch_suite PRIVATE nadir_common GTest::gtest GTest::gmock)
      target_compile_definitions(nadir_pch_suite PRIVATE
        NADIR_SOURCE_DIR="${CMAKE_SOURCE_DIR}" NADIR_BINARY_DIR="${CMAKE_BINARY_DIR}")
      nadir_target_defaults(nadir_pch_suite)
      target_precompile_headers(nadir_pch_suite PRIVATE ${NADIR_PCH_HEADERS})
    endif()
    target_precompile_headers(${target} REUSE_FROM nadir_pch_suite)
  endforeach()
endfunction()
