# Warnings and sanitizers for project code only.
set(NADIR_WARNINGS -Wall -Wextra -Werror)

function(nadir_target_defaults target)
  target_compile_options(${target} PRIVATE ${NADIR_WARNINGS})
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
endfunction()

# nadir_test(NAME SOURCES ... DEPS ... [LABELS ...] [TIMEOUT s]): a GoogleTest
# executable registered with ctest, run with the checkout as working directory.
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
