# Helpers that give every dynterrain target the same warnings and sanitizer settings.
# Flags are set per target (PRIVATE), never globally.

function(dt_target_defaults target)
  target_compile_features(${target} PUBLIC cxx_std_20)
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                                             -Wno-sign-conversion)
    if(DT_WARNINGS_AS_ERRORS)
      target_compile_options(${target} PRIVATE -Werror)
    endif()
    if(DT_SANITIZE)
      # -fsanitize=undefined leaves out float-cast-overflow (a double outside an integer's range
      # converted to it is undefined); -fno-sanitize-recover=all makes every UBSan report fatal.
      target_compile_options(${target} PRIVATE -fsanitize=address,undefined,float-cast-overflow
                                               -fno-sanitize-recover=all -fno-omit-frame-pointer)
      target_link_options(${target} PRIVATE -fsanitize=address,undefined,float-cast-overflow)
    endif()
  endif()
endfunction()

# With DT_SANITIZE, every test run by ctest gets the sanitizer runtime options: ctest reads
# sanitizer_env.cmake before any test and sets them in its own environment, so tests and the
# processes they start (drills, peers) inherit them. Options already set by the caller are kept.
# docs/testing.md explains each option and the suppressions.
function(dt_sanitizer_test_environment)
  if(NOT DT_SANITIZE)
    return()
  endif()
  # exitcode 86 (also on a leak report): a report is told apart from a program's own failure
  # (tests expect exit 1 or 2 from bad input).
  set(asan "halt_on_error=1:exitcode=86:detect_leaks=1:check_initialization_order=1")
  set(asan "${asan}:detect_stack_use_after_return=1")
  set(ubsan "halt_on_error=1:exitcode=86:print_stacktrace=1")
  set(lsan "suppressions=${PROJECT_SOURCE_DIR}/tests/lsan.supp")
  set(file ${PROJECT_BINARY_DIR}/sanitizer_env.cmake)
  file(WRITE ${file} "# Written by dt_sanitizer_test_environment (cmake/DynterrainTargets.cmake).\n")
  foreach(pair "ASAN_OPTIONS;${asan}" "UBSAN_OPTIONS;${ubsan}" "LSAN_OPTIONS;${lsan}")
    list(GET pair 0 var)
    list(GET pair 1 value)
    file(APPEND ${file} "if(NOT DEFINED ENV{${var}})\n  set(ENV{${var}} \"${value}\")\nendif()\n")
  endforeach()
  set_property(DIRECTORY ${PROJECT_SOURCE_DIR} APPEND PROPERTY TEST_INCLUDE_FILES ${file})
endfunction()

# dt_library(name SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
function(dt_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(${name} ${ARG_SOURCES})
  target_include_directories(${name} PUBLIC ${PROJECT_SOURCE_DIR})
  target_link_libraries(${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  dt_target_defaults(${name})
endfunction()

# dt_executable(name SOURCES ... [DEPS ...])
function(dt_executable name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS})
  dt_target_defaults(${name})
endfunction()

# dt_test(name SOURCES ... DEPS ... LABELS unit|integration|drill|slow [TIMEOUT s])
# One GoogleTest executable registered as one ctest test with the given labels.
function(dt_test name)
  cmake_parse_arguments(ARG "" "TIMEOUT" "SOURCES;DEPS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main)
  dt_target_defaults(${name})
  add_test(NAME ${name} COMMAND ${name} --gtest_brief=1)
  if(NOT ARG_LABELS)
    set(ARG_LABELS unit)
  endif()
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 300)
  endif()
  set_tests_properties(${name} PROPERTIES LABELS "${ARG_LABELS}" TIMEOUT ${ARG_TIMEOUT})
endfunction()

# dt_benchmark(name SOURCES ... DEPS ...)
function(dt_benchmark name)
  if(NOT DT_BUILD_BENCHMARKS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} benchmark::benchmark)
  dt_target_defaults(${name})
endfunction()
