# One INTERFACE target carries the project's warning flags; every project target links it
# PRIVATE so that flags never leak to users of the libraries.
add_library(ovpc_warnings INTERFACE)
add_library(ovpc::warnings ALIAS ovpc_warnings)
if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  target_compile_options(ovpc_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor)
endif()
