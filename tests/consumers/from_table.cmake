# Consumer test of FROM_TABLE: an installed aovar sweeps a few variants (lavapipe, 64x36, with the navi21
# estimate), and examples/variant_lookup (its table_lookup) builds its shader library from that cost table through
# find_package(aovar). Checks: the generated set is the table's front for the requested targets (computed
# here from the table's rows, apart from aovar); a second build is a no-op and touching the table reruns the
# step; the pick table answers as `aovar select` for several budgets and devices; a foreign manifest and an
# unknown family are refused in one line. Arguments: -DAOVAR_SOURCE= -DAOVAR_BUILD= -DWORK=
include(${CMAKE_CURRENT_LIST_DIR}/steps.cmake)
set(prefix ${WORK}/prefix)
file(REMOVE_RECURSE ${WORK})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${AOVAR_BUILD} --prefix ${prefix}
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(rc)
  message(FATAL_ERROR "from_table: cmake --install failed (${rc}): ${err}")
endif()
set(aovar ${prefix}/bin/aovar)
set(table ${WORK}/sweep/cost_table.json)
execute_process(COMMAND ${aovar} sweep --manifest ${prefix}/share/aovar/shader_src/aovar.toml --scene builtin:stairs --view overview --size 64x36 --rays 16 --reps 3
                        --warmup 0 --gpu navi21 --gpu-size 640x360 --no-cache --no-prune
                        --variants "alchemy-s0[48]-p0-nrg8-zdep-rst-d16-bsep-x1-hp"
                        --variants "alchemy-s16-p0-nrg8-zdep-rst-d16-bsep-x1-hp"
                        --variants "hbao-s08-p0-nrgb8-zdep-rst-d16-bsep-x1-hp"
                        --variants "sc2-s08-p0-nrgb8-zdep-rst-d16-bsep-x1-hp" --out ${WORK}/sweep
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(rc OR NOT EXISTS ${table})
  message(FATAL_ERROR "from_table: the test sweep failed (${rc}): ${err}")
endif()

# The front of one target from the table's rows (one view, so a row is its variant's worst view): the
# variants no other beats, that is with no other at no more time and less error, or less time and no more
# error. Time: the navi21 estimate, or the measured decision time (paired, else min).
function(table_front target out_var)
  file(READ ${table} json)
  string(JSON count LENGTH "${json}" rows)
  math(EXPR last "${count} - 1")
  set(keys "")
  set(times "")
  set(errors "")
  foreach(i RANGE ${last})
    string(JSON row GET "${json}" rows ${i})
    string(JSON same ERROR_VARIABLE none GET "${row}" same_code_as)
    string(JSON rmse ERROR_VARIABLE no_error GET "${row}" error rmse)
    string(JSON predicted GET "${row}" predicted)
    if(same OR no_error OR predicted)
      continue()
    endif()
    if(target STREQUAL "lavapipe")
      string(JSON time ERROR_VARIABLE no_paired GET "${row}" time_ms paired)
      if(no_paired OR NOT time GREATER 0)
        string(JSON time GET "${row}" time_ms min)
      endif()
    else()
      string(JSON time GET "${row}" gpu ${target} est_ms)
    endif()
    string(JSON key GET "${row}" variant)
    list(APPEND keys ${key})
    list(APPEND times ${time})
    list(APPEND errors ${rmse})
  endforeach()
  list(LENGTH keys n)
  math(EXPR last "${n} - 1")
  set(front "")
  foreach(i RANGE ${last})
    list(GET times ${i} ti)
    list(GET errors ${i} ei)
    set(beaten FALSE)
    foreach(j RANGE ${last})
      list(GET times ${j} tj)
      list(GET errors ${j} ej)
      if((tj LESS_EQUAL ti AND ej LESS ei) OR (tj LESS ti AND ej LESS_EQUAL ei))
        set(beaten TRUE)
      endif()
    endforeach()
    if(NOT beaten)
      list(GET keys ${i} key)
      list(APPEND front ${key})
    endif()
  endforeach()
  set(${out_var} "${front}" PARENT_SCOPE)
  set(${out_var}_times "${times}" PARENT_SCOPE)
endfunction()

set(build ${WORK}/build)
consumer_configure(${AOVAR_SOURCE}/examples/variant_lookup ${build} -DCMAKE_PREFIX_PATH=${prefix}
                   -DAOVAR_LOOKUP_TABLE=${table} -DAOVAR_LOOKUP_FOR=navi21,lavapipe)
consumer_build(${build} out)

# The generated set: the keys of the variant table, against the union of the two fronts.
file(STRINGS ${build}/table_shaders/table_shaders.cpp generated REGEX "^  {\"[a-z0-9-]+\", {")
list(TRANSFORM generated REPLACE "^  {\"([a-z0-9-]+)\".*" "\\1")
table_front(navi21 navi21_front)
table_front(lavapipe lavapipe_front)
set(expected ${navi21_front} ${lavapipe_front})
list(REMOVE_DUPLICATES expected)
list(SORT expected)
list(SORT generated)
if(NOT generated STREQUAL expected)
  message(FATAL_ERROR "from_table: generated ${generated}, the table's fronts are ${expected} "
                      "(navi21: ${navi21_front}; lavapipe: ${lavapipe_front})")
endif()

consumer_expect_noop(${build})
consumer_expect_regenerate(${build} ${table})

# pick() against `aovar select` on the same table, at every candidate's time (on the front or between its
# points), below all of them and above all of them.
function(expect_pick_is_select budget device_args select_args)
  execute_process(COMMAND ${build}/table_lookup ${budget} ${device_args} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  execute_process(COMMAND ${aovar} select --table ${table} --budget-ms ${budget} ${select_args} --json
                  RESULT_VARIABLE select_rc OUTPUT_VARIABLE json ERROR_VARIABLE select_err)
  if(rc OR NOT out MATCHES "\npick[^:]*: ([a-z0-9-]+) ")
    message(FATAL_ERROR "from_table: table_lookup ${budget} ${device_args} failed (${rc}): ${out} ${err}")
  endif()
  set(picked ${CMAKE_MATCH_1})
  string(JSON ok GET "${json}" ok)
  if(ok)
    string(JSON chosen GET "${json}" choice variant)
    if(NOT picked STREQUAL chosen OR NOT out MATCHES "\npick: ")
      message(FATAL_ERROR "from_table: budget ${budget} ms (${device_args}): pick() gave ${picked}, select ${chosen}: ${out}")
    endif()
  elseif(NOT out MATCHES "\npick \\(nothing fits, the fastest\\): ")  # pick() says so, gives the fastest
    message(FATAL_ERROR "from_table: budget ${budget} ms: select found nothing, pick() claims a fit: ${out}")
  endif()
endfunction()
foreach(target navi21 lavapipe)
  if(target STREQUAL "navi21")
    set(devices "0x1002 0x73BF" "0x1002 0x163F")  # RX 6800 XT: navi21; Steam Deck: vangogh -> nearest, navi21
    set(select_args --target navi21)
  else()
    set(devices "")  # lavapipe
    set(select_args --backend lavapipe)
  endif()
  set(budgets 1e-9 ${${target}_front_times} 1e9)
  foreach(budget IN LISTS budgets)
    if(devices)
      foreach(device IN LISTS devices)
        separate_arguments(device_args UNIX_COMMAND "${device}")
        expect_pick_is_select(${budget} "${device_args}" "${select_args}")
      endforeach()
    else()
      expect_pick_is_select(${budget} "" "${select_args}")
    endif()
  endforeach()
endforeach()
execute_process(COMMAND ${build}/table_lookup 1 0x1002 0x73BF OUTPUT_VARIABLE rx6800xt)
execute_process(COMMAND ${build}/table_lookup 1 0x1002 0x163F OUTPUT_VARIABLE steamdeck)
execute_process(COMMAND ${build}/table_lookup 1 0x10de 0x2684 OUTPUT_VARIABLE other)  # not AMD: the measured backend
if(NOT rx6800xt MATCHES "family navi21 -> front navi21" OR NOT steamdeck MATCHES "family vangogh -> front navi21"
   OR NOT other MATCHES "-> front lavapipe")
  message(FATAL_ERROR "from_table: the device map: RX 6800 XT ${rx6800xt}; Steam Deck ${steamdeck}; another vendor ${other}")
endif()

# Refusals, each aovar's one line, when the project is configured (FROM_TABLE checks the table then, with the
# installed tool: generate --check-table): an unknown family, a family the table has no rows for, a table
# measured with another manifest (a copy whose sample counts differ, so the table's keys are not in it), and a
# calibration edited after the sweep scored the table with it (issue 53).
file(COPY ${AOVAR_SOURCE}/shader_src DESTINATION ${WORK}/other)
file(READ ${WORK}/other/shader_src/aovar.toml toml)
string(REPLACE "samples      = [4, 6, 8, 12, 16, 24, 32]" "samples      = [5, 6, 9, 12, 17, 24, 32]" toml "${toml}")
file(WRITE ${WORK}/other/shader_src/aovar.toml "${toml}")
set(calibration_file ${prefix}/share/aovar/shader_src/calibration.json)
file(READ ${calibration_file} scored)
foreach(case "navi99|-DAOVAR_LOOKUP_FOR=navi99|--for 'navi99': not an AMD GPU family or a backend"
             "navi22|-DAOVAR_LOOKUP_FOR=navi22|cost_table.json: no rows with an error for GPU family 'navi22'"
             "manifest|-DAOVAR_LOOKUP_MANIFEST=${WORK}/other/shader_src/aovar.toml|cost_table.json: error: this cost table was measured with another manifest"
             "calibration|-DAOVAR_LOOKUP_FOR=navi21|changed after the table was scored")
  string(REPLACE "|" ";" case "${case}")
  list(GET case 0 name)
  list(GET case 1 define)
  list(GET case 2 message)
  if(name STREQUAL "calibration")
    file(WRITE ${calibration_file} "${scored}\n")  # the same fit with one more byte: not the bytes that were scored
  endif()
  file(REMOVE_RECURSE ${WORK}/refused_${name})
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${AOVAR_SOURCE}/examples/variant_lookup -B ${WORK}/refused_${name} -G Ninja
                          -DCMAKE_PREFIX_PATH=${prefix} -DAOVAR_LOOKUP_TABLE=${table} ${define}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  file(WRITE ${calibration_file} "${scored}")
  string(REGEX REPLACE "[ \n]+" " " err "${err}")  # CMake wraps a message's lines
  string(REPLACE ";" "," err "${err}")  # a ';' in a message would split the list of matches
  string(REGEX MATCHALL "aovar_add_shader_variants\\([a-z_]+\\): [^\n]*${message}" found "${err}")
  list(LENGTH found n)
  if(rc EQUAL 0 OR NOT n EQUAL 1)
    message(FATAL_ERROR "from_table: ${name} was not refused at configure in aovar's one line (${rc}, ${n}): ${out} ${err}")
  endif()
endforeach()
