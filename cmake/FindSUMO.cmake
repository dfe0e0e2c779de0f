# FindSUMO: SUMO 1.15 ships no CMake config. Debian installs the headers in /usr/include/libsumo
# and the libraries libsumocpp.so (embedded SUMO) and libtracicpp.so (TraCI client).
# Defines SUMO::libsumo and SUMO::libtraci, and SUMO_BINARY (the sumo executable).
find_path(SUMO_INCLUDE_DIR libsumo/libsumo.h PATHS /usr/include /usr/local/include $ENV{SUMO_HOME}/include)
find_library(SUMO_LIBSUMO_LIBRARY NAMES sumocpp PATHS $ENV{SUMO_HOME}/bin $ENV{SUMO_HOME}/lib)
find_library(SUMO_LIBTRACI_LIBRARY NAMES tracicpp PATHS $ENV{SUMO_HOME}/bin $ENV{SUMO_HOME}/lib)
find_program(SUMO_BINARY sumo PATHS $ENV{SUMO_HOME}/bin)
find_program(SUMO_GUI_BINARY sumo-gui PATHS $ENV{SUMO_HOME}/bin)
find_program(SUMO_NETCONVERT netconvert PATHS $ENV{SUMO_HOME}/bin)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(SUMO REQUIRED_VARS SUMO_INCLUDE_DIR SUMO_LIBSUMO_LIBRARY SUMO_LIBTRACI_LIBRARY SUMO_BINARY)

if(SUMO_FOUND AND NOT TARGET SUMO::libsumo)
  add_library(SUMO::libsumo UNKNOWN IMPORTED)
  set_target_properties(SUMO::libsumo PROPERTIES IMPORTED_LOCATION "${SUMO_LIBSUMO_LIBRARY}"
                        INTERFACE_INCLUDE_DIRECTORIES "${SUMO_INCLUDE_DIR}")
  add_library(SUMO::libtraci UNKNOWN IMPORTED)
  set_target_properties(SUMO::libtraci PROPERTIES IMPORTED_LOCATION "${SUMO_LIBTRACI_LIBRARY}"
                        INTERFACE_INCLUDE_DIRECTORIES "${SUMO_INCLUDE_DIR}")
endif()
mark_as_advanced(SUMO_INCLUDE_DIR SUMO_LIBSUMO_LIBRARY SUMO_LIBTRACI_LIBRARY)
