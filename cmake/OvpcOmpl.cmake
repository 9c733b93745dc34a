# Wraps OMPL in one INTERFACE target, ovpc::ompl.
#
# OMPL 1.5.2 (Debian libompl-dev) exports variables only. Its OMPL_INCLUDE_DIRS lists /usr/include,
# which as a -isystem path breaks libstdc++'s #include_next, and its OMPL_LIBRARIES hard-codes
# absolute paths to Boost libraries (serialization, filesystem, system) and a bare "ode". libompl.so
# records its own runtime dependencies, so the target links the OMPL library alone and adds only
# OMPL's own include directory, as SYSTEM so that OMPL's headers do not trip the project's warnings.
include_guard(GLOBAL)

find_package(ompl REQUIRED)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)

find_library(OVPC_OMPL_LIBRARY NAMES ompl PATHS ${OMPL_LIBRARY_DIRS} NO_DEFAULT_PATH)
if(NOT OVPC_OMPL_LIBRARY)
  message(FATAL_ERROR "OvpcOmpl: libompl not found in '${OMPL_LIBRARY_DIRS}' (install libompl-dev)")
endif()

add_library(ovpc_ompl INTERFACE)
add_library(ovpc::ompl ALIAS ovpc_ompl)
target_include_directories(ovpc_ompl SYSTEM INTERFACE ${OMPL_INCLUDE_DIR})
target_link_libraries(ovpc_ompl INTERFACE ${OVPC_OMPL_LIBRARY} Eigen3::Eigen)
message(STATUS "OMPL ${OMPL_VERSION}: ${OVPC_OMPL_LIBRARY}")
