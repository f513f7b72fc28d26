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

# dt_fuzzer(name FOLDER f SOURCES ... [INCLUDES ...] LIBS ... RUNS n MAX_LEN bytes TIMEOUT s)
# A libFuzzer target (fuzz preset: DT_BUILD_FUZZERS, clang) whose seed corpus is
# <source>/<f>/fuzz/corpus, and the ctest entry <name minus _fuzzer>_fuzz_short running it for
# RUNS inputs. In the fuzz preset that runs the fuzzer built there; in every other preset
# cmake/fuzz_short.sh first builds it with clang in <build>/fuzz-short (one tree for every
# fuzzer, under one resource lock), so a gcc suite includes the short run too.
function(dt_fuzzer name)
  cmake_parse_arguments(ARG "" "FOLDER;RUNS;MAX_LEN;TIMEOUT" "SOURCES;INCLUDES;LIBS" ${ARGN})
  string(REGEX REPLACE "_fuzzer$" "_fuzz_short" test_name ${name})
  set(corpus ${PROJECT_SOURCE_DIR}/${ARG_FOLDER}/fuzz/corpus)
  if(DT_BUILD_FUZZERS)
    if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
      message(FATAL_ERROR "DT_BUILD_FUZZERS needs clang (use the fuzz preset)")
    endif()
    # The code under test is compiled into the fuzzer so libFuzzer sees its coverage.
    add_executable(${name} ${ARG_SOURCES})
    target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR})
    if(ARG_INCLUDES)
      target_include_directories(${name} SYSTEM PRIVATE ${ARG_INCLUDES})
    endif()
    target_link_libraries(${name} PRIVATE ${ARG_LIBS})
    target_compile_features(${name} PRIVATE cxx_std_20)
    target_compile_options(${name} PRIVATE -fsanitize=fuzzer,address,undefined
                                           -fno-sanitize-recover=all)
    target_link_options(${name} PRIVATE -fsanitize=fuzzer,address,undefined)
    # New inputs go to a build directory, never into the committed seed corpus.
    add_test(NAME ${test_name}
             COMMAND sh -c "mkdir -p ${name}_out && exec $<TARGET_FILE:${name}> -runs=${ARG_RUNS} -seed=1 -max_len=${ARG_MAX_LEN} ${name}_out ${corpus}"
             WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
    set_tests_properties(${test_name} PROPERTIES LABELS "unit" TIMEOUT ${ARG_TIMEOUT})
  else()
    add_test(NAME ${test_name}
             COMMAND ${PROJECT_SOURCE_DIR}/cmake/fuzz_short.sh ${PROJECT_SOURCE_DIR}
                     ${CMAKE_BINARY_DIR}/fuzz-short ${name} ${ARG_FOLDER} ${ARG_RUNS} ${ARG_MAX_LEN})
    set_tests_properties(${test_name} PROPERTIES LABELS "unit" TIMEOUT ${ARG_TIMEOUT}
                                                 SKIP_RETURN_CODE 77
                                                 RESOURCE_LOCK fuzz_short_tree)
  endif()
endfunction()
