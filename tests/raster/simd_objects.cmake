# Fails when a SIMD kernel object (kernels_avx2.cpp, kernels_avx512.cpp: compiled with their own
# target flags) defines a weak function: an out-of-line copy of an inline function with external
# linkage (a header's, e.g. lighting.h's shadeBlinnPhong). The linker keeps one copy of such a
# function for every caller, and may keep this one, with AVX2 / AVX-512 instructions, for the
# scalar paths of a CPU without them. Kernels reach such functions through scalarKernels()
# instead, or keep them in an anonymous namespace (row_span.h).
#   cmake -DNM=<nm> -DOBJECTS=<object|object|…> -P simd_objects.cmake
string(REPLACE "|" ";" objects "${OBJECTS}")
set(checked 0)
set(found "")
foreach(object IN LISTS objects)
    if(NOT object MATCHES "kernels_avx")
        continue()
    endif()
    math(EXPR checked "${checked} + 1")
    execute_process(COMMAND "${NM}" -C --defined-only "${object}" OUTPUT_VARIABLE symbols
                    RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "error: ${NM} failed on ${object}")
    endif()
    string(REPLACE "\n" ";" lines "${symbols}")
    foreach(line IN LISTS lines)
        if(line MATCHES "^[0-9a-f]+ W (.*)$")
            string(APPEND found "\n  ${object}: ${CMAKE_MATCH_1}")
        endif()
    endforeach()
endforeach()
if(found)
    message(FATAL_ERROR "error: SIMD kernel objects define shared inline functions "
                        "(weak symbols; the linker may keep these copies for every caller):${found}")
endif()
message(STATUS "${checked} SIMD kernel object(s): no weak functions")
