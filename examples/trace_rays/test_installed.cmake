# ctest script: installs the library from BUILD_DIR into a prefix inside it,
# builds this example against the *installed* package (not the source tree),
# runs it on MESH and checks that its rays hit. Also checks that the exported
# link interface names no OpenImageIO and no OpenMesh, and that the installed
# CLI finds its image module (OpenImageIO, loaded only to write an image) in
# the prefix.
#   cmake -DBUILD_DIR=... -DEXAMPLE_DIR=... -DMESH=... -P test_installed.cmake
foreach(var BUILD_DIR EXAMPLE_DIR MESH)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "test_installed.cmake: -D${var}=... is required")
    endif()
endforeach()

set(work ${BUILD_DIR}/example_trace_rays)
set(prefix ${work}/prefix)
file(REMOVE_RECURSE ${work})

function(run what)
    execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
    endif()
    set(run_output "${out}" PARENT_SCOPE)
endfunction()

run("installing the library" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix}
    --component subdivtrace_dev)

file(GLOB_RECURSE exported ${prefix}/*/subdivtraceTargets*.cmake)
if(NOT exported)
    message(FATAL_ERROR "no subdivtraceTargets*.cmake under ${prefix}")
endif()
foreach(f ${exported})
    file(READ ${f} text)
    if(text MATCHES "OpenImageIO|OIIO|OpenMesh")
        message(FATAL_ERROR "${f}: the installed library's link interface names "
                            "OpenImageIO or OpenMesh")
    endif()
endforeach()

run("configuring the example" ${CMAKE_COMMAND} -S ${EXAMPLE_DIR} -B ${work}/build
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
run("building the example" ${CMAKE_COMMAND} --build ${work}/build)
# The package must come from the prefix, not from the source tree.
file(STRINGS ${work}/build/CMakeCache.txt found_dir REGEX "^subdivtrace_DIR:")
if(NOT found_dir MATCHES "${prefix}")
    message(FATAL_ERROR "the example found subdivtrace elsewhere: ${found_dir}")
endif()

run("running the example" ${work}/build/trace_rays ${MESH} 7)
message(STATUS "trace_rays output:\n${run_output}")
if(NOT run_output MATCHES "ray [0-9]+: hit t=")
    message(FATAL_ERROR "the example's rays hit nothing:\n${run_output}")
endif()

# The CLI component: `render` loads the image module from <prefix>/<libdir>/subdivtrace.
run("installing the CLI" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix}
    --component subdivtrace_cli)
file(GLOB_RECURSE module ${prefix}/*/subdivtrace/libsubdivtrace_image.so)
if(NOT module)
    message(FATAL_ERROR "no image module under ${prefix}")
endif()
run("rendering with the installed CLI" ${prefix}/bin/subdivtrace render ${MESH}
    -o ${work}/installed.png --width 32 --height 24 --quiet)
if(NOT EXISTS ${work}/installed.png)
    message(FATAL_ERROR "the installed CLI wrote no image")
endif()
# With the module gone, render says where it looked (and writes nothing).
file(REMOVE ${module})
execute_process(COMMAND ${prefix}/bin/subdivtrace render ${MESH} -o ${work}/missing.png
    --width 8 --height 6 --quiet RESULT_VARIABLE rc ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT err MATCHES "image module" OR EXISTS ${work}/missing.png)
    message(FATAL_ERROR "without its module the CLI should fail naming it (rc ${rc}):\n${err}")
endif()
