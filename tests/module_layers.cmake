# docs/architecture.md says "a module includes only modules below it": its Modules table lists the folders
# of src/ from the ground up. This script holds every `#include "<module>/..."` under src/ against that order.
# Fails, naming the file and line, when a module includes one listed above it, or when a folder of src/ is
# missing from the table. Run: cmake -DAOVAR_SOURCE=<repository> -P tests/module_layers.cmake
cmake_minimum_required(VERSION 3.20)  # IN_LIST
if(NOT AOVAR_SOURCE)
  message(FATAL_ERROR "module_layers.cmake: give -DAOVAR_SOURCE=<repository root>")
endif()

# The table's rows in order: "| stage | `src/<folder>` | ...".
file(STRINGS ${AOVAR_SOURCE}/docs/architecture.md table_rows REGEX "^\\| [^|]+ \\| `src/[a-z_]+` \\|")
set(order "")
foreach(row IN LISTS table_rows)
  string(REGEX MATCH "`src/([a-z_]+)`" _ "${row}")
  list(APPEND order ${CMAKE_MATCH_1})
endforeach()
list(LENGTH order count)
if(count LESS 2)
  message(FATAL_ERROR "docs/architecture.md: no Modules table found (rows like | stage | `src/<folder>` | ...)")
endif()

set(problems "")
file(GLOB folders LIST_DIRECTORIES true RELATIVE ${AOVAR_SOURCE}/src ${AOVAR_SOURCE}/src/*)
foreach(folder IN LISTS folders)
  if(IS_DIRECTORY ${AOVAR_SOURCE}/src/${folder} AND NOT folder IN_LIST order)
    list(APPEND problems "src/${folder} is a module but has no row in docs/architecture.md's Modules table")
  endif()
endforeach()

foreach(module IN LISTS order)
  list(FIND order ${module} level)
  file(GLOB_RECURSE sources RELATIVE ${AOVAR_SOURCE} ${AOVAR_SOURCE}/src/${module}/*)
  foreach(source IN LISTS sources)
    file(STRINGS ${AOVAR_SOURCE}/${source} includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"[a-z_]+/")
    foreach(line IN LISTS includes)
      string(REGEX MATCH "\"([a-z_]+)/" _ "${line}")
      set(included ${CMAKE_MATCH_1})
      list(FIND order ${included} included_level)
      if(included_level GREATER level)
        string(STRIP "${line}" line)
        list(APPEND problems "${source}: ${line}: ${module} includes ${included}, listed above it")
      endif()
    endforeach()
  endforeach()
endforeach()

if(problems)
  list(JOIN problems "\n" text)
  message(FATAL_ERROR "${text}\n(docs/architecture.md, Modules: a module includes only modules below it; move "
                      "the call up to the including module's caller, or the row in the table)")
endif()
list(JOIN order " < " chain)
message(STATUS "module layers hold: ${chain}")
