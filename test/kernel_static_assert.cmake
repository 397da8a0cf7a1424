# Compiles kernel_static_assert.cpp (both cases, syntax only) once and writes the compiler's output
# to OUTPUT, where kernel_static_assert_1 and kernel_static_assert_2 look for meshfit's messages.
# Passes whatever the compiler says: the two tests judge the output.
#   cmake -DCXX=... -DSOURCE=... -DOUTPUT=... -DINCLUDE=... -DBINARY_INCLUDE=... -DEIGEN_INCLUDE=... -P ...
file(REMOVE "${OUTPUT}")
execute_process(COMMAND "${CXX}" -std=c++17 -fsyntax-only -I${INCLUDE} -I${BINARY_INCLUDE} -isystem ${EIGEN_INCLUDE}
                        "${SOURCE}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
file(WRITE "${OUTPUT}" "exit status: ${rc}\n${out}")
message("${CXX} -fsyntax-only ${SOURCE}: exit status ${rc}, output in ${OUTPUT}")
