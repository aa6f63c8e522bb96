# aovar_add_shader_variants(<target> MANIFEST <file> [TARGETS vulkan gl45 gles30] [OUTPUT_DIR <dir>]
#                           [VARIANTS <glob>... | FROM_TABLE <cost_table.json> [FOR <family|backend>...]
#                            [BUDGET_MS <ms> | BUDGET_OF <key> | MAX_ERROR <rmse>]] [WERROR])
#
# Generates the manifest's shader variants at build time and defines <target>, a static library with the
# SPIR-V and GLSL embedded and the lookup API in <target>.h (namespace <target>). The step re-runs when the
# manifest or any template or include it read changes (depfile); unchanged outputs are not rewritten, so
# the library only recompiles when a program really changed.
#
# The tool is aovar::aovar: the imported executable of find_package(aovar CONFIG), or the build tree's target
# when aovar is the project or a subproject (FetchContent, add_subdirectory). AOVAR_EXECUTABLE (a path)
# overrides it. The step depends on the tool's file, so a new aovar regenerates every consumer's shaders.
#
# FROM_TABLE generates only what a cost table (aovar sweep, aovar ship) keeps: per GPU family (FOR navi21:
# its roofline estimate, sweep --gpu) and measured backend (FOR lavapipe) the front `aovar select` answers
# along, or with BUDGET_MS / BUDGET_OF / MAX_ERROR only select's pick; the header then has
# pick(device, budget_ms), pick_level, step_up / step_down (docs/install.md). The step re-runs when the
# table changes. A table from another manifest, an unknown name in FOR or a target without rows fails the
# step with one line; an empty FROM_TABLE or one naming no file fails at configure, in one line.
#
# <target> becomes a C++ namespace and the names of the generated files, so it must be a C++ identifier.
include_guard(GLOBAL)

# One line naming the function and what to change when <target> cannot be a C++ namespace and file name.
function(_aovar_check_target_name target)
  set(keywords alignas alignof and and_eq asm auto bitand bitor bool break case catch char char8_t char16_t
      char32_t class compl concept const consteval constexpr constinit const_cast continue co_await co_return
      co_yield decltype default delete do double dynamic_cast else enum explicit export extern false float for
      friend goto if inline int long mutable namespace new noexcept not not_eq nullptr operator or or_eq private
      protected public register reinterpret_cast requires return short signed sizeof static static_assert
      static_cast struct switch template this thread_local throw true try typedef typeid typename union
      unsigned using virtual void volatile wchar_t while xor xor_eq std)
  if(NOT target MATCHES "^[A-Za-z][A-Za-z0-9_]*$" OR target MATCHES "__")
    message(FATAL_ERROR "aovar_add_shader_variants(${target}): the target name becomes a C++ namespace and file "
                        "names, so it must be letters, digits and single underscores, starting with a letter "
                        "(e.g. my_ssao)")
  endif()
  if(target IN_LIST keywords)
    message(FATAL_ERROR "aovar_add_shader_variants(${target}): '${target}' is a C++ keyword and cannot name the "
                        "generated namespace; choose another target name (e.g. ${target}_shaders)")
  endif()
endfunction()

# The aovar program a configure step can run: AOVAR_EXECUTABLE, or an imported aovar::aovar's file; empty for
# aovar built in this same build (FetchContent), which does not exist before the build.
function(_aovar_configure_time_tool tool out_var)
  set(program "")
  if(EXISTS "${tool}")
    set(program "${tool}")
  elseif(TARGET aovar::aovar)
    get_target_property(imported aovar::aovar IMPORTED)
    if(imported)
      get_target_property(program aovar::aovar IMPORTED_LOCATION)
      if(NOT program)
        get_target_property(configs aovar::aovar IMPORTED_CONFIGURATIONS)
        foreach(config IN LISTS configs)
          get_target_property(program aovar::aovar IMPORTED_LOCATION_${config})
          if(program)
            break()
          endif()
        endforeach()
      endif()
    endif()
  endif()
  if(NOT program OR NOT EXISTS "${program}")
    set(program "")
  endif()
  set(${out_var} "${program}" PARENT_SCOPE)
endfunction()

# FROM_TABLE's table is checked when the project is configured, not first at build time: its manifest, its
# names, the targets and pick asked for, and the calibration it was scored with (found, with the scored
# bytes). A refusal fails the configure with aovar's one line. The table is a configure dependency, so a new
# table is checked again. With aovar built in the same build the check waits for the build's own run.
function(_aovar_check_table_at_configure target tool table)
  _aovar_configure_time_tool("${tool}" program)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${table}")
  if(NOT program)
    return()
  endif()
  execute_process(COMMAND "${program}" ${ARGN} --check-table RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    string(STRIP "${err}" err)
    string(REGEX REPLACE ".*\n" "" err "${err}")  # aovar's one-line refusal is its last line
    message(FATAL_ERROR "aovar_add_shader_variants(${target}): ${err}")
  endif()
endfunction()

function(aovar_add_shader_variants target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "WERROR" "MANIFEST;OUTPUT_DIR;FROM_TABLE;BUDGET_MS;BUDGET_OF;MAX_ERROR"
                        "TARGETS;VARIANTS;FOR")
  if(NOT arg_MANIFEST)
    message(FATAL_ERROR "aovar_add_shader_variants(${target}): MANIFEST is required")
  endif()
  _aovar_check_target_name(${target})
  if(AOVAR_EXECUTABLE)
    set(tool "${AOVAR_EXECUTABLE}")
    set(tool_depends "${AOVAR_EXECUTABLE}")
  elseif(TARGET aovar::aovar)
    # The target name gives the build order in a build tree and, for the imported executable, a file-level
    # dependency on its location: an upgraded or rebuilt tool reruns the step.
    set(tool aovar::aovar)
    set(tool_depends aovar::aovar)
  else()
    message(FATAL_ERROR "aovar_add_shader_variants(${target}): no aovar tool: find_package(aovar CONFIG REQUIRED) "
                        "first, or set AOVAR_EXECUTABLE to the aovar program")
  endif()
  get_filename_component(manifest "${arg_MANIFEST}" ABSOLUTE)
  if(NOT arg_OUTPUT_DIR)
    set(arg_OUTPUT_DIR "${CMAKE_CURRENT_BINARY_DIR}/${target}")
  endif()
  set(out "${arg_OUTPUT_DIR}")
  set(args generate --manifest "${manifest}" --out "${out}" --emit cpp --namespace ${target}
           --depfile "${out}/${target}.d" --depfile-target "${out}/${target}.stamp" --stamp "${out}/${target}.stamp")
  if(arg_TARGETS)
    list(JOIN arg_TARGETS "," targets)
    list(APPEND args --targets ${targets})
  endif()
  foreach(glob IN LISTS arg_VARIANTS)
    list(APPEND args --variants "${glob}")
  endforeach()
  if(arg_WERROR)
    list(APPEND args --werror)
  endif()
  set(table_depends "")
  # FROM_TABLE with no value (an unset variable) or an empty one would generate the whole space without a
  # pick table; a missing file would fail the build with the generator's "missing and no known rule".
  # (cmake_parse_arguments drops an empty value before CMP0174, so the arguments are read as given.)
  set(table_given FALSE)
  set(table_empty FALSE)
  math(EXPR last_arg "${ARGC} - 1")
  foreach(i RANGE 1 ${last_arg})
    if("${ARGV${i}}" STREQUAL "FROM_TABLE")
      set(table_given TRUE)
      math(EXPR next "${i} + 1")
      if(next GREATER last_arg OR "${ARGV${next}}" STREQUAL "" OR "${ARGV${next}}" MATCHES
         "^(FOR|TARGETS|VARIANTS|MANIFEST|OUTPUT_DIR|BUDGET_MS|BUDGET_OF|MAX_ERROR|WERROR)$")
        set(table_empty TRUE)
      endif()
    endif()
  endforeach()
  if(table_empty)
    message(FATAL_ERROR "aovar_add_shader_variants(${target}): FROM_TABLE is empty (an unset variable?): give the "
                        "cost_table.json of an aovar sweep or ship, or leave FROM_TABLE out")
  endif()
  if(DEFINED arg_FROM_TABLE)
    get_filename_component(table "${arg_FROM_TABLE}" ABSOLUTE)
    if(NOT EXISTS "${table}" OR IS_DIRECTORY "${table}")
      message(FATAL_ERROR "aovar_add_shader_variants(${target}): FROM_TABLE ${table}: no such file: give the "
                          "cost_table.json of an aovar sweep or ship (aovar sweep --out DIR writes DIR/cost_table.json)")
    endif()
  endif()
  if(DEFINED arg_FROM_TABLE)
    if(arg_VARIANTS)
      message(FATAL_ERROR "aovar_add_shader_variants(${target}): FROM_TABLE chooses the variants; leave out VARIANTS")
    endif()
    get_filename_component(table "${arg_FROM_TABLE}" ABSOLUTE)
    set(table_depends "${table}")
    list(APPEND args --from-table "${table}")
    if(arg_FOR)
      list(JOIN arg_FOR "," for_targets)
      list(APPEND args --for ${for_targets})
    endif()
    foreach(pick BUDGET_MS BUDGET_OF MAX_ERROR)
      if(DEFINED arg_${pick})
        string(TOLOWER "${pick}" option)
        string(REPLACE "_" "-" option "${option}")
        list(APPEND args --${option} "${arg_${pick}}")
      endif()
    endforeach()
  elseif(arg_FOR OR DEFINED arg_BUDGET_MS OR DEFINED arg_BUDGET_OF OR DEFINED arg_MAX_ERROR)
    message(FATAL_ERROR "aovar_add_shader_variants(${target}): FOR, BUDGET_MS, BUDGET_OF and MAX_ERROR need FROM_TABLE")
  endif()
  if(DEFINED arg_FROM_TABLE)
    _aovar_check_table_at_configure(${target} "${tool}" "${table}" ${args})
  endif()

  # OUTPUT is a stamp touched on every run; the sources are BYPRODUCTS, so Ninja's restat sees that an
  # unchanged header or source was not rewritten and skips recompiling the library.
  add_custom_command(
    OUTPUT "${out}/${target}.stamp"
    BYPRODUCTS "${out}/${target}.h" "${out}/${target}.cpp"
    COMMAND ${tool} ${args}
    DEPENDS "${manifest}" ${table_depends} ${tool_depends}
    DEPFILE "${out}/${target}.d"
    COMMENT "aovar: generating shader variants of ${arg_MANIFEST}"
    VERBATIM)
  add_library(${target} STATIC "${out}/${target}.cpp" "${out}/${target}.stamp")
  target_include_directories(${target} PUBLIC "${out}")
  target_compile_features(${target} PUBLIC cxx_std_17)
endfunction()
