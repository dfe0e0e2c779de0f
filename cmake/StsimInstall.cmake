# Install rules and the CMake / pkg-config packages, in one place: `cmake --install build --prefix P`
# installs the stsim tool, the public headers, the libraries (static), the shipped networks, the
# CMake package (find_package(stsim) -> stsim::<name>) and stsim.pc. Included last from the top
# CMakeLists.txt, so every library target exists. A new library is one stsim_install_library() line.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(STSIM_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/stsim CACHE STRING
    "Where the CMake package files go, relative to the prefix")

# The version header: <stsim/version.hpp>, from project(stsim VERSION ...).
set(stsim_generated_include ${PROJECT_BINARY_DIR}/generated/include)
configure_file(${PROJECT_SOURCE_DIR}/cmake/version.hpp.in ${stsim_generated_include}/stsim/version.hpp @ONLY)
target_include_directories(stcore PUBLIC $<BUILD_INTERFACE:${stsim_generated_include}>)
install(FILES ${stsim_generated_include}/stsim/version.hpp DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/stsim)

# Linked PRIVATE into the static libraries, so their exported link interface names it
# ($<LINK_ONLY:...>: it carries only warning flags, which consumers never see).
install(TARGETS stsim_warnings EXPORT stsimTargets)
set_target_properties(stsim_warnings PROPERTIES EXPORT_NAME warnings)

set(stsim_installed_libs "")
# stsim_install_library(<target> <export name> <include dir>): the library as stsim::<export name>
# (and the same alias in the tree, beside the st:: one), its headers from <include dir>.
function(stsim_install_library target name include_dir)
  if(NOT TARGET ${target} OR "${target}" IN_LIST stsim_installed_libs)
    return()
  endif()
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  if(NOT TARGET stsim::${name})
    add_library(stsim::${name} ALIAS ${target})
  endif()
  # the SUMO plugin in an export set of its own: find_package(stsim COMPONENTS arm) loads
  # neither it nor SUMO
  set(export_set stsimTargets)
  if(name STREQUAL "cosim")
    set(export_set stsimCosimTargets)
  endif()
  install(TARGETS ${target} EXPORT ${export_set}
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
          INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  if(EXISTS ${PROJECT_SOURCE_DIR}/${include_dir})
    install(DIRECTORY ${PROJECT_SOURCE_DIR}/${include_dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
            FILES_MATCHING PATTERN "*.hpp" PATTERN "*.h")
  endif()
  set(stsim_installed_libs ${stsim_installed_libs} ${target} PARENT_SCOPE)
endfunction()

# The in-tree libraries `target` links (aliases resolved), public or private: a static library's
# private links are part of what its users link.
function(stsim_in_tree_links target out)
  set(result "")
  get_target_property(libs ${target} LINK_LIBRARIES)
  foreach(l IN LISTS libs)
    if(TARGET ${l})
      get_target_property(real ${l} ALIASED_TARGET)
      if(real)
        set(l ${real})
      endif()
      get_target_property(imported ${l} IMPORTED)
      get_target_property(type ${l} TYPE)
      if(NOT imported AND type MATCHES "^(STATIC|SHARED)_LIBRARY$")
        list(APPEND result ${l})
      endif()
    endif()
  endforeach()
  set(${out} ${result} PARENT_SCOPE)
endfunction()

# The experiment runner (batch/, st::batch) is the tool's, not a library for plugins: not
# installed, so a consumer needs no MPI.
stsim_install_library(stsim_cosim cosim cosim/lib/include)
stsim_install_library(starm_service arm_service models/arm/include)
stsim_install_library(starm arm models/arm/include)
stsim_install_library(stpool pool models/pool/include)
stsim_install_library(sthighway highway models/highway/include)
stsim_install_library(stio io io/include)
stsim_install_library(stnet net net/include)
stsim_install_library(stcore core stcore/include)
# Whatever else they link is installed too (install(EXPORT) needs every linked target exported),
# named after its target; list a new library above to name it.
set(stsim_queue ${stsim_installed_libs})
while(stsim_queue)
  list(POP_FRONT stsim_queue t)
  stsim_in_tree_links(${t} deps)
  foreach(d IN LISTS deps)
    if(NOT d IN_LIST stsim_installed_libs)
      string(REGEX REPLACE "^(stsim_|st)" "" name ${d})
      get_target_property(dir ${d} SOURCE_DIR)
      file(RELATIVE_PATH rel ${PROJECT_SOURCE_DIR} ${dir}/include)
      message(STATUS "stsim: installing ${d} as stsim::${name} (linked by ${t}; name it in cmake/StsimInstall.cmake)")
      stsim_install_library(${d} ${name} ${rel})
      list(APPEND stsim_queue ${d})
    endif()
  endforeach()
endwhile()

install(TARGETS stsim RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/networks/ DESTINATION ${CMAKE_INSTALL_DATADIR}/stsim/networks)
# the plot scripts the tool runs (stsim batch's report, the conflict map): found beside the
# executable first (bin/../share/stsim, st::io::dataFile), then in the source tree
install(FILES ${PROJECT_SOURCE_DIR}/batch/plots.py ${PROJECT_SOURCE_DIR}/models/highway/conflict_map.py
        DESTINATION ${CMAKE_INSTALL_DATADIR}/stsim)
# the page of stsim pool serve (one self-contained file: nothing fetched from elsewhere)
install(FILES ${PROJECT_SOURCE_DIR}/models/pool/serve/web/index.html DESTINATION ${CMAKE_INSTALL_DATADIR}/stsim/pool)
# the arm scenarios (examples/arm_loop runs one)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/models/arm/scenarios/ DESTINATION ${CMAKE_INSTALL_DATADIR}/stsim/arm)

# CMake package
install(EXPORT stsimTargets NAMESPACE stsim:: DESTINATION ${STSIM_INSTALL_CMAKEDIR})
if(TARGET stsim_cosim)
  install(EXPORT stsimCosimTargets NAMESPACE stsim:: DESTINATION ${STSIM_INSTALL_CMAKEDIR})
endif()
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/stsimConfig.cmake.in
  ${PROJECT_BINARY_DIR}/stsimConfig.cmake
  INSTALL_DESTINATION ${STSIM_INSTALL_CMAKEDIR}
  PATH_VARS CMAKE_INSTALL_INCLUDEDIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/stsimConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/stsimConfig.cmake ${PROJECT_BINARY_DIR}/stsimConfigVersion.cmake
        DESTINATION ${STSIM_INSTALL_CMAKEDIR})
if(STSIM_WITH_SUMO)
  install(FILES ${PROJECT_SOURCE_DIR}/cmake/FindSUMO.cmake DESTINATION ${STSIM_INSTALL_CMAKEDIR})
endif()

# pkg-config: stsim.pc, relocatable (the prefix is found from the .pc file's own place)
# static libraries in link order, users before what they use (a depth-first post-order, reversed)
function(stsim_link_order_visit t)
  get_property(seen GLOBAL PROPERTY STSIM_LINK_ORDER)
  if(t IN_LIST seen)
    return()
  endif()
  stsim_in_tree_links(${t} deps)
  foreach(d IN LISTS deps)
    stsim_link_order_visit(${d})
  endforeach()
  set_property(GLOBAL APPEND PROPERTY STSIM_LINK_ORDER ${t})
endfunction()
foreach(t IN LISTS stsim_installed_libs)
  stsim_link_order_visit(${t})
endforeach()
get_property(stsim_link_order GLOBAL PROPERTY STSIM_LINK_ORDER)
list(REVERSE stsim_link_order)
set(stsim_pc_libs "")
foreach(lib IN LISTS stsim_link_order)
  string(APPEND stsim_pc_libs " -l$<TARGET_FILE_BASE_NAME:${lib}>")
endforeach()
if(STSIM_WITH_SUMO)
  string(APPEND stsim_pc_libs " -lsumocpp -ltracicpp")
endif()
if(TARGET stnet)
  string(APPEND stsim_pc_libs " -pthread")
endif()
string(STRIP "${stsim_pc_libs}" stsim_pc_libs)
file(RELATIVE_PATH stsim_pc_up /${CMAKE_INSTALL_LIBDIR}/pkgconfig /)
string(REGEX REPLACE "/$" "" stsim_pc_up "${stsim_pc_up}")
configure_file(${PROJECT_SOURCE_DIR}/cmake/stsim.pc.in ${PROJECT_BINARY_DIR}/stsim.pc.in @ONLY)
file(GENERATE OUTPUT ${PROJECT_BINARY_DIR}/stsim.pc INPUT ${PROJECT_BINARY_DIR}/stsim.pc.in)
install(FILES ${PROJECT_BINARY_DIR}/stsim.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# the .deb (cpack -G DEB)
include(StsimPackaging)
