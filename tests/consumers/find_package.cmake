# Consumer test: aovar installed under a prefix (cmake --install), the example found through
# find_package(aovar CONFIG) and the installed default manifest. Arguments: -DAOVAR_SOURCE= -DAOVAR_BUILD=
# -DWORK= (a scratch folder).
include(${CMAKE_CURRENT_LIST_DIR}/steps.cmake)
set(prefix ${WORK}/prefix)
file(REMOVE_RECURSE ${prefix})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${AOVAR_BUILD} --prefix ${prefix}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc)
  message(FATAL_ERROR "consumer: cmake --install failed (${rc}): ${err}")
endif()
foreach(file bin/aovar share/aovar/shader_src/aovar.toml lib/cmake/aovar/aovarConfig.cmake
             lib/cmake/aovar/aovarConfigVersion.cmake lib/cmake/aovar/aovarTargets.cmake
             lib/cmake/aovar/AOVarShaders.cmake)
  if(NOT EXISTS ${prefix}/${file})
    message(FATAL_ERROR "consumer: the install has no ${file}")
  endif()
endforeach()

consumer_configure(${AOVAR_SOURCE}/examples/variant_lookup ${WORK}/build -DCMAKE_PREFIX_PATH=${prefix}
                   "-DAOVAR_LOOKUP_VARIANTS=alchemy-s08-*")
file(STRINGS ${WORK}/build/CMakeCache.txt manifest REGEX "^AOVAR_LOOKUP_MANIFEST:")
if(NOT manifest MATCHES "${prefix}/share/aovar/shader_src/aovar.toml")
  message(FATAL_ERROR "consumer: find_package(aovar) did not give the installed manifest: ${manifest}")
endif()
consumer_build(${WORK}/build out)
consumer_lookup(${WORK}/build/variant_lookup)
consumer_expect_noop(${WORK}/build)
consumer_expect_regenerate(${WORK}/build ${prefix}/bin/aovar)

# Target names that cannot be a C++ namespace and file name are refused at configure time, in one line.
foreach(name my-ssao namespace 3d_ao)
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${CMAKE_CURRENT_LIST_DIR}/bad_name -B ${WORK}/bad_name -G Ninja
                          -DCMAKE_PREFIX_PATH=${prefix} -DAOVAR_TEST_TARGET=${name}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  file(REMOVE_RECURSE ${WORK}/bad_name)
  if(rc EQUAL 0 OR NOT err MATCHES "aovar_add_shader_variants\\(${name}\\): ")
    message(FATAL_ERROR "consumer: the target name '${name}' was not refused (${rc}): ${err}")
  endif()
endforeach()
