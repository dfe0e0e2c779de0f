# The .deb: `cpack -G DEB` in the build folder packs what `cmake --install` installs, under /usr.
# Runtime libraries are found by dpkg-shlibdeps (from the ELF files: libyaml-cpp, libopenmpi,
# libsumocpp -> sumo, libstdc++ ...); listed here is what the headers, the CMake package and the
# Python module need besides.
set(CPACK_PACKAGE_NAME stsim)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR "stsim")
set(CPACK_PACKAGE_CONTACT "stsim developers <stsim@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "space-time simulation toolkit: smart-car collision warnings for SUMO")
set(CPACK_PACKAGE_DESCRIPTION
    "The stsim tool (pool, robot-arm and automated-highway models on one space-time core, SUMO\nco-simulation, batch experiments), its C++ headers and static libraries with a CMake\npackage (find_package(stsim)) and pkg-config file, and the Python module stsim.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # stsim_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(stsim_deb_depends "libeigen3-dev (>= 3.4), libyaml-cpp-dev, libboost1.74-dev, liburdfdom-dev")
if(STSIM_WITH_SUMO)
  string(APPEND stsim_deb_depends ", sumo (>= 1.15)")  # libsumo's headers come with sumo
endif()
if(TARGET stsim_python)
  string(APPEND stsim_deb_depends ", python3 (>= 3.11), python3 (<< 3.12), python3-numpy")
endif()
set(CPACK_DEBIAN_PACKAGE_DEPENDS "${stsim_deb_depends}")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "sumo-tools, pkg-config, python3-matplotlib")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "python3-pandas")
set(CPACK_GENERATOR DEB)
include(CPack)
