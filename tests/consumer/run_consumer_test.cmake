# CTest tests package.consumer* (cmake -P): installs the build tree to a fresh prefix, then
# configures, builds and runs the consumer project beside this file against it, with the build's
# compiler and build type. Fails on the first step that fails; the work directory is removed on
# success.
#
# -D variables: OVPC_BINARY_DIR (the build tree), CONSUMER_SOURCE_DIR, WORK_DIR (a parent for the
# test's own directory), CONFIG, GENERATOR, CXX_COMPILER, optional CXX_COMPILER_LAUNCHER and SANITIZE
# (the build's OVPC_SANITIZE: the consumer is built with the same sanitizers, or it would not link),
# and optional:
#   COMPONENT   install only this install component (e.g. libraries: the package without backends)
#   BACKENDS    ON: the consumer asks for the backends component and runs a cycle with it
#   OCTOMAP     "forbidden": `ldd` of the consumer must not list liboctomap; "expected": it must
foreach(var IN ITEMS OVPC_BINARY_DIR CONSUMER_SOURCE_DIR WORK_DIR CONFIG GENERATOR CXX_COMPILER)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "run_consumer_test.cmake: -D${var}=... is required")
  endif()
endforeach()

# A directory of its own, so that runs of different build trees or overlapping runs never share files.
string(RANDOM LENGTH 10 ALPHABET 0123456789abcdefghijklmnopqrstuvwxyz suffix)
set(dir "${WORK_DIR}/run-${suffix}")
set(prefix "${dir}/prefix")
file(REMOVE_RECURSE "${dir}")
file(MAKE_DIRECTORY "${dir}")

function(step name)
  message(STATUS "package.consumer: ${name}")
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "package.consumer: ${name} failed (${rc}); files kept in ${dir}")
  endif()
endfunction()

set(component)
set(what "the build")
if(COMPONENT)
  set(component --component "${COMPONENT}")
  set(what "component ${COMPONENT}")
endif()
step("install ${what} to ${prefix}"
     "${CMAKE_COMMAND}" --install "${OVPC_BINARY_DIR}" --prefix "${prefix}" --config "${CONFIG}" ${component})

if(COMPONENT STREQUAL "libraries")
  file(GLOB_RECURSE extra "${prefix}/*backends*" "${prefix}/*octomap*")
  if(extra)
    message(FATAL_ERROR "package.consumer: the libraries component installed ${extra}")
  endif()
endif()

set(launcher)
if(CXX_COMPILER_LAUNCHER)
  set(launcher "-DCMAKE_CXX_COMPILER_LAUNCHER=${CXX_COMPILER_LAUNCHER}")
endif()
set(sanitize)
if(SANITIZE)
  set(sanitize "-DCMAKE_CXX_FLAGS=-fsanitize=${SANITIZE} -fno-sanitize-recover=all"
               "-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=${SANITIZE}")
endif()
step("configure the consumer"
     "${CMAKE_COMMAND}" -S "${CONSUMER_SOURCE_DIR}" -B "${dir}/build" -G "${GENERATOR}"
     "-DCMAKE_BUILD_TYPE=${CONFIG}" "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}" ${launcher} ${sanitize}
     "-DCMAKE_PREFIX_PATH=${prefix}" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF "-DOVPC_CONSUMER_BACKENDS=${BACKENDS}"
     # The empty generator expression keeps multi-config generators from adding a per-config folder.
     "-DCMAKE_RUNTIME_OUTPUT_DIRECTORY=${dir}/bin/$<0:>")

# The package found must be the one just installed, not one elsewhere on the system.
file(STRINGS "${dir}/build/CMakeCache.txt" found REGEX "^ovpc_DIR:")
if(NOT found MATCHES "=${prefix}/")
  message(FATAL_ERROR "package.consumer: the consumer found ${found}, not the package in ${prefix}")
endif()

step("build the consumer" "${CMAKE_COMMAND}" --build "${dir}/build" --config "${CONFIG}")
step("run the consumer" "${dir}/bin/ovpc_consumer" "${dir}")

# What the executable loads: OctoMap only through the backends component.
if(OCTOMAP)
  execute_process(COMMAND ldd "${dir}/bin/ovpc_consumer" OUTPUT_VARIABLE libraries RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "package.consumer: ldd failed (${rc}); files kept in ${dir}")
  endif()
  string(FIND "${libraries}" "liboctomap" at)
  if(OCTOMAP STREQUAL "forbidden" AND NOT at EQUAL -1)
    message(FATAL_ERROR "package.consumer: the consumer depends on OctoMap:\n${libraries}files kept in ${dir}")
  elseif(OCTOMAP STREQUAL "expected" AND at EQUAL -1)
    message(FATAL_ERROR "package.consumer: ldd lists no liboctomap:\n${libraries}files kept in ${dir}")
  endif()
  message(STATUS "package.consumer: liboctomap ${OCTOMAP} and ldd agrees")
endif()

file(REMOVE_RECURSE "${dir}")
