# Consumer test: aovar through FetchContent, generator only, with the render packages hidden; the
# subcommands left out say so. Arguments: -DAOVAR_SOURCE= -DWORK= (a scratch folder).
include(${CMAKE_CURRENT_LIST_DIR}/steps.cmake)
consumer_configure(${CMAKE_CURRENT_LIST_DIR}/fetchcontent ${WORK}/build -DAOVAR_SOURCE=${AOVAR_SOURCE}
                   "-DAOVAR_LOOKUP_VARIANTS=alchemy-s08-*")
file(STRINGS ${WORK}/build/CMakeCache.txt build_type REGEX "^CMAKE_BUILD_TYPE:")
if(build_type MATCHES "RelWithDebInfo")
  message(FATAL_ERROR "consumer: the subproject forced the parent's build type: ${build_type}")
endif()
consumer_build(${WORK}/build out)
consumer_lookup(${WORK}/build/variant_lookup/variant_lookup)
consumer_expect_noop(${WORK}/build)
set(tool ${WORK}/build/_deps/aovar-build/aovar)
consumer_expect_regenerate(${WORK}/build ${tool})

# A subcommand the generator-only build lacks: one line and exit 2 (an error), not a usage message.
execute_process(COMMAND ${tool} measure --scene builtin:atrium RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "^aovar measure is not in this build: .*AOVAR_WITH_RENDER=ON[^\n]*\n$")
  message(FATAL_ERROR "consumer: generator-only `aovar measure` did not say it is not in the build (${rc}): ${err}")
endif()
