# Sanitizer and fuzzing builds.
#
#   -DOVPC_SANITIZE=address,undefined   every project target built and linked with
#                                       -fsanitize=address,undefined (gcc or clang); any runtime
#                                       report stops the program (no recovery)
#   -DOVPC_FUZZ=ON                      the libFuzzer harnesses in fuzz/ (clang only); the project's
#                                       code is instrumented for coverage, and OVPC_SANITIZE defaults
#                                       to address,undefined
#
# The sanitizers' default options and the suppression files in cmake/sanitizers/ (third-party
# libraries only) are compiled into every executable, so a test, `ovpc run` or a fuzz harness from
# such a build needs no environment variables (ASAN_OPTIONS and friends still add to them).
set(OVPC_SANITIZE "" CACHE STRING "Sanitizers for every target, e.g. address,undefined (empty: none)")
option(OVPC_FUZZ "Build the libFuzzer harnesses in fuzz/ (needs clang)" OFF)

if(OVPC_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "OVPC_FUZZ needs clang (libFuzzer): configure with -DCMAKE_CXX_COMPILER=clang++ "
                        "-DCMAKE_C_COMPILER=clang (scripts/install-deps --with-fuzz installs them)")
  endif()
  if(OVPC_SANITIZE STREQUAL "")
    set(OVPC_SANITIZE "address,undefined" CACHE STRING "" FORCE)
  endif()
  # Coverage instrumentation for libFuzzer in every target; only the harnesses link its main().
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()

if(NOT OVPC_SANITIZE STREQUAL "")
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    message(FATAL_ERROR "OVPC_SANITIZE needs gcc or clang")
  endif()
  message(STATUS "Sanitizers: ${OVPC_SANITIZE}")
  add_compile_options(-fsanitize=${OVPC_SANITIZE} -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${OVPC_SANITIZE} -fno-sanitize-recover=all)
  set(OVPC_SANITIZER_DIR ${PROJECT_SOURCE_DIR}/cmake/sanitizers)
  configure_file(${OVPC_SANITIZER_DIR}/sanitizer_defaults.cc.in ${PROJECT_BINARY_DIR}/sanitizer_defaults.cc @ONLY)
endif()

# Adds the sanitizers' default options to every executable defined so far in `dir` and below (call
# it last, from the top-level CMakeLists.txt).
function(ovpc_add_sanitizer_defaults dir)
  if(OVPC_SANITIZE STREQUAL "")
    return()
  endif()
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  foreach(target IN LISTS targets)
    get_target_property(type ${target} TYPE)
    if(type STREQUAL "EXECUTABLE")
      target_sources(${target} PRIVATE ${PROJECT_BINARY_DIR}/sanitizer_defaults.cc)
    endif()
  endforeach()
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(subdir IN LISTS subdirs)
    ovpc_add_sanitizer_defaults(${subdir})
  endforeach()
endfunction()
