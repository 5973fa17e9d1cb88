# cmake -P script of tests/install (arguments: see CMakeLists.txt). Fails with the failing step's
# output.
if(NOT MVR_BUILD_TYPE)
    set(MVR_BUILD_TYPE Release)
endif()
set(prefix ${MVR_WORK_DIR}/prefix)
set(build ${MVR_WORK_DIR}/consumer-build)
file(REMOVE_RECURSE ${MVR_WORK_DIR})

function(step what)
    execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "install test: ${what} failed (${rc}):\n${out}")
    endif()
    message(STATUS "install test: ${what}: ok")
    set(step_output "${out}" PARENT_SCOPE)
endfunction()

step("cmake --install" ${CMAKE_COMMAND} --install ${MVR_BUILD_DIR} --prefix ${prefix})
foreach(file include/mvr/backends.h include/mvr/core/framing.h include/mvr/session/recipe.h
        ${MVR_LIBDIR}/cmake/mvr/mvrConfig.cmake ${MVR_LIBDIR}/cmake/mvr/mvrConfigVersion.cmake
        ${MVR_LIBDIR}/cmake/mvr/mvrTargets.cmake bin/mvr)
    if(NOT EXISTS ${prefix}/${file})
        message(FATAL_ERROR "install test: ${prefix}/${file} was not installed")
    endif()
endforeach()

# Only the prefix: no package registry, so the build tree cannot stand in for the install.
set(configure ${CMAKE_COMMAND} -S ${MVR_CONSUMER_DIR} -B ${build}
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
    -DCMAKE_BUILD_TYPE=${MVR_BUILD_TYPE} -DCMAKE_CXX_COMPILER=${MVR_CXX_COMPILER})
if(MVR_CXX_LAUNCHER)
    list(APPEND configure -DCMAKE_CXX_COMPILER_LAUNCHER=${MVR_CXX_LAUNCHER})
endif()
step("configure the consumer" ${configure})
step("build the consumer" ${CMAKE_COMMAND} --build ${build} -j2)
step("run the consumer" ${build}/mvr_consumer)
message(STATUS "${step_output}")
