# Consumer test: aovar configured as the top-level project with AOVAR_WITH_RENDER=OFF while every render
# dependency is hidden. It must configure, and nothing in its build may link a render library. (Building
# the generator alone is what tests/consumers/fetchcontent.cmake does.) Arguments: -DAOVAR_SOURCE= -DWORK=
include(${CMAKE_CURRENT_LIST_DIR}/steps.cmake)
set(hidden)
foreach(package embree TBB Vulkan NLopt glm tinyobjloader TinyGLTF PkgConfig simdjson)
  list(APPEND hidden -DCMAKE_DISABLE_FIND_PACKAGE_${package}=ON)
endforeach()
consumer_configure(${AOVAR_SOURCE} ${WORK}/build -DAOVAR_WITH_RENDER=OFF -DAOVAR_BUILD_TESTS=OFF ${hidden})
file(READ ${WORK}/build/build.ninja ninja)
foreach(library embree tbb vulkan OSMesa nlopt simdjson)
  if(ninja MATCHES "lib${library}")
    message(FATAL_ERROR "consumer: the generator-only build links lib${library}")
  endif()
endforeach()
# With rendering asked for, the same hidden packages make the configure fail.
execute_process(COMMAND ${CMAKE_COMMAND} -S ${AOVAR_SOURCE} -B ${WORK}/render -G Ninja -DAOVAR_BUILD_TESTS=OFF ${hidden}
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(rc EQUAL 0)
  message(FATAL_ERROR "consumer: a render configure succeeded with the render packages hidden: were they hidden?")
endif()
