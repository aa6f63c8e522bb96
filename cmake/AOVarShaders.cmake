# aovar_add_shader_variants(<target> MANIFEST <file> [TARGETS vulkan gl45 gles30] [OUTPUT_DIR <dir>]
#                           [VARIANTS <glob>...] [WERROR])
#
# Generates the manifest's shader variants at build time and defines <target>, a static library with the
# SPIR-V and GLSL embedded and the lookup API in <target>.h (namespace <target>). The step re-runs when the
# manifest or any template or include it read changes (depfile); unchanged outputs are not rewritten, so
# the library only recompiles when a program really changed.
#
# Needs AOVAR_EXECUTABLE (path or generator expression of the aovar tool).
include_guard(GLOBAL)

function(aovar_add_shader_variants target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "WERROR" "MANIFEST;OUTPUT_DIR" "TARGETS;VARIANTS")
  if(NOT arg_MANIFEST)
    message(FATAL_ERROR "aovar_add_shader_variants(${target}): MANIFEST is required")
  endif()
  if(NOT AOVAR_EXECUTABLE)
    message(FATAL_ERROR "aovar_add_shader_variants(${target}): set AOVAR_EXECUTABLE to the aovar tool")
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

  # OUTPUT is a stamp touched on every run; the sources are BYPRODUCTS, so Ninja's restat sees that an
  # unchanged header or source was not rewritten and skips recompiling the library.
  add_custom_command(
    OUTPUT "${out}/${target}.stamp"
    BYPRODUCTS "${out}/${target}.h" "${out}/${target}.cpp"
    COMMAND ${AOVAR_EXECUTABLE} ${args}
    DEPENDS "${manifest}" ${AOVAR_EXECUTABLE_TARGET}
    DEPFILE "${out}/${target}.d"
    COMMENT "aovar: generating shader variants of ${arg_MANIFEST}"
    VERBATIM)
  add_library(${target} STATIC "${out}/${target}.cpp" "${out}/${target}.stamp")
  target_include_directories(${target} PUBLIC "${out}")
  target_compile_features(${target} PUBLIC cxx_std_17)
endfunction()
