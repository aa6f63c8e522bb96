# Package test: `cpack -G DEB` from the build folder makes a .deb that holds the tool, the templates and the
# CMake package, and declares the Debian packages it needs (the libraries the tool links, found by
# dpkg-shlibdeps, and the Vulkan drivers it loads). Arguments: -DAOVAR_BUILD= -DWORK=

file(REMOVE_RECURSE ${WORK})
execute_process(COMMAND cpack -G DEB --config ${AOVAR_BUILD}/CPackConfig.cmake -B ${WORK}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
file(GLOB deb ${WORK}/aovar_*.deb)
if(rc OR NOT deb)
  message(FATAL_ERROR "package: cpack -G DEB failed (${rc}): ${out} ${err}")
endif()
execute_process(COMMAND dpkg-deb -f ${deb} Package Version Depends OUTPUT_VARIABLE fields RESULT_VARIABLE rc)
foreach(needed "Package: aovar" "Version: [0-9]+\\.[0-9]+\\.[0-9]+" "libembree3" "libtbb" "libosmesa6" "libvulkan1"
               "mesa-vulkan-drivers" "libegl1" "libegl-mesa0" "libgles2" "libnlopt" "libsimdjson" "libstdc\\+\\+6")
  if(rc OR NOT fields MATCHES "${needed}")
    message(FATAL_ERROR "package: the .deb's control does not declare '${needed}': ${fields}")
  endif()
endforeach()
execute_process(COMMAND dpkg-deb -c ${deb} OUTPUT_VARIABLE files RESULT_VARIABLE rc)
foreach(file usr/bin/aovar usr/share/aovar/shader_src/aovar.toml usr/share/aovar/shader_src/ao/gtao.glsl
             usr/lib/cmake/aovar/aovarConfig.cmake usr/lib/cmake/aovar/aovarTargets.cmake
             usr/lib/cmake/aovar/AOVarShaders.cmake)
  if(rc OR NOT files MATCHES "\\./${file}\n")
    message(FATAL_ERROR "package: the .deb does not hold /${file}")
  endif()
endforeach()
