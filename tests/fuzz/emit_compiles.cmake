# Compiles every pick table the table_cpp harness emits for its corpus (issue 54): whatever names a table
# holds, the generated C++ compiles and holds them as literals. -DHARNESS -DCORPUS -DCXX -DWORK.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND ${CMAKE_COMMAND} -E env AOVAR_FUZZ_EMIT_DIR=${WORK} ${HARNESS} ${CORPUS}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the table_cpp harness failed on its corpus (${rc}): ${out}")
endif()
file(GLOB units ${WORK}/*.cpp)
list(LENGTH units count)
if(count LESS 4)
  message(FATAL_ERROR "the table_cpp harness emitted ${count} pick tables for its corpus, expected at least 4")
endif()
foreach(unit IN LISTS units)
  execute_process(COMMAND ${CXX} -std=c++20 -fsyntax-only -Wall -Werror -Wno-unused-function -Wno-unused-variable ${unit}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${unit} does not compile: ${out}")
  endif()
endforeach()
message(STATUS "${count} emitted pick tables compile")
