# The steps every CMake consumer test takes (tests/consumers/*.cmake include this file and run with -P):
# configure, build, run the lookup, prove a second build does nothing and that a newer tool regenerates.
# Each failure is one FATAL_ERROR line naming the step.


# Configures SOURCE into BINARY (a fresh folder) with the extra -D arguments.
function(consumer_configure source binary)
  file(REMOVE_RECURSE ${binary})
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${source} -B ${binary} -G Ninja ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc)
    message(FATAL_ERROR "consumer: configure of ${source} failed (${rc}): ${out} ${err}")
  endif()
endfunction()

# Builds BINARY; the build's output goes to OUT_VAR.
function(consumer_build binary out_var)
  execute_process(COMMAND ${CMAKE_COMMAND} --build ${binary} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc)
    message(FATAL_ERROR "consumer: build of ${binary} failed (${rc}): ${out} ${err}")
  endif()
  set(${out_var} "${out}" PARENT_SCOPE)
endfunction()

# The example looks the default baseline up by its axes and prints its key and SPIR-V size.
function(consumer_lookup exe)
  execute_process(COMMAND ${exe} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc OR NOT out MATCHES "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp" OR NOT out MATCHES "bytes of SPIR-V")
    message(FATAL_ERROR "consumer: lookup by axes did not print the expected variant (${rc}): ${out} ${err}")
  endif()
endfunction()

# A build with nothing changed must do nothing: the generator rewrote nothing, so nothing recompiles.
function(consumer_expect_noop binary)
  execute_process(COMMAND ${CMAKE_COMMAND} --build ${binary} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc OR NOT out MATCHES "no work to do")
    message(FATAL_ERROR "consumer: a build with nothing changed was not a no-op: ${out} ${err}")
  endif()
endfunction()

# After TOOL's file is touched (what an upgrade or a rebuild of aovar does), the next build runs the
# generation step again, and the build after that is a no-op.
function(consumer_expect_regenerate binary tool)
  execute_process(COMMAND ${CMAKE_COMMAND} -E sleep 1.1)  # a later mtime than the stamp on any file system
  file(TOUCH_NOCREATE ${tool})
  consumer_build(${binary} out)
  if(NOT out MATCHES "aovar: generating shader variants")
    message(FATAL_ERROR "consumer: touching the tool ${tool} did not rerun the generation step: ${out}")
  endif()
  consumer_expect_noop(${binary})
endfunction()
