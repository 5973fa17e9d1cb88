# cmake/MvrInstall.cmake — what `cmake --install` puts under the prefix:
#   include/mvr/**                   the public headers (mvr/gl/ only when the gl backend is built)
#   lib/libmvr_*.a                   the libraries, exported as mvr::core, mvr::raster, mvr::composite,
#                                    mvr::adelson, mvr::backends, mvr::session, mvr::gl (when built)
#                                    and the interface target mvr::flags (C++20,
#                                    GLM_FORCE_XYZW_ONLY)
#   lib/cmake/mvr/                   mvrConfig.cmake, mvrConfigVersion.cmake, mvrTargets*.cmake
#   bin/mvr                          the command line tool (tools/cli)
# so that a project does
#   find_package(mvr CONFIG REQUIRED)            # optionally COMPONENTS gl
#   target_link_libraries(app PRIVATE mvr::backends)
# tests/install checks exactly that from a temporary prefix.
include(CMakePackageConfigHelpers)

set(MVR_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/mvr")

set(MVR_EXPORTED_TARGETS mvr_flags mvr_core mvr_raster mvr_composite mvr_io mvr_adelson mvr_backends mvr_session)
if(TARGET mvr_gl)
    list(APPEND MVR_EXPORTED_TARGETS mvr_gl)
endif()
if(TARGET mvr_vk)
    list(APPEND MVR_EXPORTED_TARGETS mvr_vk)
endif()
set(MVR_EXPORTED_COMPONENTS)
foreach(target IN LISTS MVR_EXPORTED_TARGETS)
    string(REGEX REPLACE "^mvr_" "" component "${target}")
    set_target_properties(${target} PROPERTIES EXPORT_NAME ${component})
    list(APPEND MVR_EXPORTED_COMPONENTS ${component})
endforeach()

install(TARGETS ${MVR_EXPORTED_TARGETS} EXPORT mvrTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
    INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})

set(MVR_HEADER_EXCLUDES)
if(NOT TARGET mvr_gl)
    set(MVR_HEADER_EXCLUDES PATTERN "gl" EXCLUDE)
endif()
if(NOT TARGET mvr_vk)
    list(APPEND MVR_HEADER_EXCLUDES PATTERN "vk" EXCLUDE)
endif()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/mvr DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
    FILES_MATCHING PATTERN "*.h" ${MVR_HEADER_EXCLUDES})

install(EXPORT mvrTargets NAMESPACE mvr:: DESTINATION ${MVR_INSTALL_CMAKEDIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/mvrConfig.cmake.in
    ${PROJECT_BINARY_DIR}/mvrConfig.cmake
    INSTALL_DESTINATION ${MVR_INSTALL_CMAKEDIR})
# 0.x: a minor version may break the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/mvrConfigVersion.cmake
    VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/mvrConfig.cmake ${PROJECT_BINARY_DIR}/mvrConfigVersion.cmake
    DESTINATION ${MVR_INSTALL_CMAKEDIR})
