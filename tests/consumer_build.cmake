# Configures, builds and runs the example consumer in a fresh folder; fails on any step.
file(REMOVE_RECURSE ${BINARY})
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE} -B ${BINARY} -G Ninja -DAOVAR_EXECUTABLE=${AOVAR}
                RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "consumer: configure failed (${rc})")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${BINARY} RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "consumer: build failed (${rc})")
endif()
execute_process(COMMAND ${BINARY}/variant_lookup RESULT_VARIABLE rc OUTPUT_VARIABLE out)
message(STATUS "${out}")
if(rc OR NOT out MATCHES "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp" OR NOT out MATCHES "bytes of SPIR-V")
  message(FATAL_ERROR "consumer: lookup by axes did not print the expected variant (${rc}): ${out}")
endif()
# A second build must be a no-op: the generator rewrote nothing, so nothing recompiles.
execute_process(COMMAND ${CMAKE_COMMAND} --build ${BINARY} -- -d explain RESULT_VARIABLE rc OUTPUT_VARIABLE out2
                ERROR_VARIABLE err2)
if(rc OR NOT out2 MATCHES "no work to do")
  message(FATAL_ERROR "consumer: second build was not a no-op: ${out2} ${err2}")
endif()
