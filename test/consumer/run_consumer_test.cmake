# Installs meshfit from MESHFIT_BUILD_DIR into WORK_DIR/prefix, then builds and runs the consumer.
file(REMOVE_RECURSE "${WORK_DIR}")
if(NOT BUILD_TYPE)
  set(BUILD_TYPE Release)
endif()
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  message("${out}")
endfunction()
# The library component only: the package must not need the command (which the test does not build).
run(${CMAKE_COMMAND} --install "${MESHFIT_BUILD_DIR}" --prefix "${WORK_DIR}/prefix" --config ${BUILD_TYPE}
    --component meshfit_library)
file(GLOB shared_libraries "${WORK_DIR}/prefix/lib*/libmeshfit.so*")
file(GLOB static_libraries "${WORK_DIR}/prefix/lib*/libmeshfit.a")
if(SHARED)
  if(NOT shared_libraries OR static_libraries)
    message(FATAL_ERROR "a shared build must install libmeshfit.so (and no libmeshfit.a): ${shared_libraries} ${static_libraries}")
  endif()
elseif(NOT static_libraries OR shared_libraries)
  message(FATAL_ERROR "a static build must install libmeshfit.a (and no libmeshfit.so): ${static_libraries} ${shared_libraries}")
endif()
# The exported link interface names targets, never a file by its absolute path (a package built
# here must work where the libraries live elsewhere): the config finds each dependency again.
file(GLOB targets_file "${WORK_DIR}/prefix/lib*/cmake/meshfit/meshfitTargets.cmake")
if(NOT targets_file)
  message(FATAL_ERROR "no meshfitTargets.cmake installed under ${WORK_DIR}/prefix")
endif()
file(READ "${targets_file}" exported)
string(REGEX MATCHALL "INTERFACE_LINK_LIBRARIES \"[^\"]*\"" link_interfaces "${exported}")
if(NOT link_interfaces)
  message(FATAL_ERROR "${targets_file} has no INTERFACE_LINK_LIBRARIES")
endif()
# (Items are separated by ';' (the list MATCHALL returns is joined by ';' too), or start a
# generator expression: $<LINK_ONLY:/usr/lib/...>.)
if(link_interfaces MATCHES "[\";:>]/" OR link_interfaces MATCHES "/usr/lib")
  message(FATAL_ERROR "the exported target links a library by its absolute path:\n${link_interfaces}")
endif()
message("exported link interface (no absolute path): ${link_interfaces}")
run(${CMAKE_COMMAND} -S "${CONSUMER_SOURCE_DIR}" -B "${WORK_DIR}/build"
    -DCMAKE_BUILD_TYPE=${BUILD_TYPE} "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix")
run(${CMAKE_COMMAND} --build "${WORK_DIR}/build")
run("${WORK_DIR}/build/consumer" "${EXAMPLE_DATA_DIR}")

# The examples (component meshfit_examples): their sources, data and the VTK converter are
# installed, and the installed examples build against the installed package and read the
# installed data (io_example, the quickest to build; it writes io_example_output.obj).
run(${CMAKE_COMMAND} --install "${MESHFIT_BUILD_DIR}" --prefix "${WORK_DIR}/prefix" --config ${BUILD_TYPE}
    --component meshfit_examples)
set(examples "${WORK_DIR}/prefix/share/doc/meshfit/examples")
foreach(file CMakeLists.txt io_example.cpp deform_coarse_example.cpp deform_fine_example.cpp partition_example.cpp
             smooth_example.cpp fit_example.cpp make_example_data.cpp make_more_example_data.cpp
             example_data_common.h data/README.md data/template.off data/curves.polylines.txt data/pairs.txt
             data/curves-2.polylines.txt data/pairs-2.txt data/sheet/template.off data/elephant/pairs.txt)
  if(NOT EXISTS "${examples}/${file}")
    message(FATAL_ERROR "not installed: ${examples}/${file}")
  endif()
endforeach()
set(converter "${WORK_DIR}/prefix/share/meshfit/mesh_to_vtk.py")
if(NOT EXISTS "${converter}")
  message(FATAL_ERROR "not installed: ${converter}")
endif()
file(READ "${converter}" converter_text LIMIT 200)
if(NOT converter_text MATCHES "^#!")
  message(FATAL_ERROR "${converter} is not the script")
endif()
execute_process(COMMAND test -x "${converter}" RESULT_VARIABLE not_executable)
if(not_executable)
  message(FATAL_ERROR "${converter} is not executable")
endif()
# (At -O1 in a Release build, as meshfit's own build compiles the examples: this proves that they
# build and run against the installed package; -O3's code generation would add 5 s of CPU and
# prove nothing more. The consumer above stays at the build type's flags: it checks the header
# templates of fit_template_to_curves, on two mesh types, compiled as a Release user compiles them.)
set(examples_flags)
if(BUILD_TYPE STREQUAL "Release")
  set(examples_flags "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -DNDEBUG")
endif()
run(${CMAKE_COMMAND} -S "${examples}" -B "${WORK_DIR}/examples-build"
    -DCMAKE_BUILD_TYPE=${BUILD_TYPE} "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix" ${examples_flags})
run(${CMAKE_COMMAND} --build "${WORK_DIR}/examples-build" --target io_example)
execute_process(COMMAND "${WORK_DIR}/examples-build/io_example" WORKING_DIRECTORY "${WORK_DIR}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "share/doc/meshfit/examples/data/template.off: 2562 vertices")
  message(FATAL_ERROR "the installed io_example failed (${rc}) or did not read the installed data:\n${out}\n${err}")
endif()
message("${out}")

if(SHARED)
  # The consumer runs against the installed library (found through its build RPATH), not a copy
  # in the build folder.
  find_program(LDD ldd)
  if(LDD)
    execute_process(COMMAND "${LDD}" "${WORK_DIR}/build/consumer" OUTPUT_VARIABLE linked RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0 OR NOT linked MATCHES "libmeshfit\\.so[^\n]*=> ${WORK_DIR}/prefix/")
      message(FATAL_ERROR "the consumer is not linked to the installed libmeshfit.so:\n${linked}")
    endif()
    message("${linked}")
  endif()
endif()
