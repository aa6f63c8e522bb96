# FROM_TABLE that cannot be a table fails at configure with aovar's one line (issue 54, reproduction 11):
# an unset variable (no value), an empty string, a missing file and a folder. Before, the unset one generated
# the whole space and the build failed with "'pick' is not a member"; a missing file gave Ninja's "missing
# and no known rule". Only configures (no tool runs). Arguments: -DAOVAR_SOURCE= -DAOVAR_EXE= -DWORK=
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/a_folder.json)
foreach(case "unset|FROM_TABLE \${UNSET_TABLE}|FROM_TABLE is empty"
             "empty|FROM_TABLE \"\"|FROM_TABLE is empty"
             "missing|FROM_TABLE ${WORK}/no_such/cost_table.json|cost_table.json: no such file"
             "folder|FROM_TABLE ${WORK}/a_folder.json|a_folder.json: no such file")
  string(REPLACE "|" ";" parts "${case}")
  list(GET parts 0 name)
  list(GET parts 1 call)
  list(GET parts 2 expected)
  set(project ${WORK}/${name})
  file(WRITE ${project}/CMakeLists.txt "cmake_minimum_required(VERSION 3.25)\nproject(t NONE)\n"
       "set(AOVAR_EXECUTABLE ${AOVAR_EXE})\ninclude(${AOVAR_SOURCE}/cmake/AOVarShaders.cmake)\n"
       "aovar_add_shader_variants(shaders MANIFEST ${AOVAR_SOURCE}/shader_src/aovar.toml ${call})\n")
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${project} -B ${project}/build RESULT_VARIABLE rc
                  OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 0)
    message(FATAL_ERROR "from_table_configure: ${name}: configure succeeded: ${out}")
  endif()
  string(REGEX REPLACE "[ \n]+" " " err "${err}")  # CMake wraps a message's lines
  string(FIND "${err}" "aovar_add_shader_variants(shaders): " at_function)
  string(FIND "${err}" "${expected}" at_expected)
  if(at_function EQUAL -1 OR at_expected EQUAL -1)
    message(FATAL_ERROR "from_table_configure: ${name}: expected '${expected}', got: ${err}")
  endif()
endforeach()
message(STATUS "from_table_configure: 4 tables refused at configure")
