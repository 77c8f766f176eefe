# Run uniarc on one bad deck and check that it fails the way the deck's header says.
#
#   cmake -DUNIARC=<uniarc> -DDECK=<deck.inp> -DWORK=<scratch dir> -P check_bad_deck.cmake
#
# Header lines of the deck (at its top, in any order):
#   ** expect: <substring>|<substring>...   every substring must occur in stderr (required)
#   ** args: <more arguments>               appended to the command line (e.g. -D nosuch=1)
#   ** stderr starts: <prefix>              stderr must begin with it (no warning before the error)
#   ** deck: <path>                         run on this path (relative to the deck, or absolute) instead
#                                           of the deck
# Passes when uniarc exits with 2 (bad input), stderr has every expected substring, and the output
# directory, fresh and empty before the run, is still empty after it (nothing written on bad input).
foreach(variable UNIARC DECK WORK)
  if(NOT DEFINED ${variable})
    message(FATAL_ERROR "check_bad_deck.cmake needs -D${variable}=...")
  endif()
endforeach()

get_filename_component(deck_name "${DECK}" NAME_WE)
get_filename_component(deck_directory "${DECK}" DIRECTORY)

file(STRINGS "${DECK}" header_lines REGEX "^\\*\\* *(expect|args|deck|stderr starts):")
set(expected "")
set(stderr_prefix "")
set(extra_arguments "")
set(run_path "${DECK}")
foreach(header IN LISTS header_lines)
  if(header MATCHES "^\\*\\* *expect: *(.*)$")
    string(REPLACE "|" ";" expected "${CMAKE_MATCH_1}")
  elseif(header MATCHES "^\\*\\* *stderr starts: *(.*)$")
    set(stderr_prefix "${CMAKE_MATCH_1}")
  elseif(header MATCHES "^\\*\\* *args: *(.*)$")
    separate_arguments(extra_arguments UNIX_COMMAND "${CMAKE_MATCH_1}")
  elseif(header MATCHES "^\\*\\* *deck: *(.*)$")
    if(IS_ABSOLUTE "${CMAKE_MATCH_1}")
      set(run_path "${CMAKE_MATCH_1}")
    else()
      set(run_path "${deck_directory}/${CMAKE_MATCH_1}")
    endif()
  endif()
endforeach()
if(expected STREQUAL "")
  message(FATAL_ERROR "${DECK}: no '** expect:' header line")
endif()

set(output_directory "${WORK}/${deck_name}.out")
file(REMOVE_RECURSE "${output_directory}")
file(MAKE_DIRECTORY "${output_directory}")

execute_process(
  COMMAND "${UNIARC}" "${run_path}" -o "${output_directory}" ${extra_arguments}
  RESULT_VARIABLE exit_code
  OUTPUT_VARIABLE standard_output
  ERROR_VARIABLE standard_error)

set(failures "")
if(NOT exit_code STREQUAL "2")
  string(APPEND failures "  exit code ${exit_code}, expected 2\n")
endif()
foreach(substring IN LISTS expected)
  string(STRIP "${substring}" substring)
  string(FIND "${standard_error}" "${substring}" position)
  if(position EQUAL -1)
    string(APPEND failures "  stderr lacks: ${substring}\n")
  endif()
endforeach()
if(NOT stderr_prefix STREQUAL "")
  string(FIND "${standard_error}" "${stderr_prefix}" position)
  if(NOT position EQUAL 0)
    string(APPEND failures "  stderr does not start with: ${stderr_prefix}\n")
  endif()
endif()
file(GLOB left_over "${output_directory}/*")
if(left_over)
  string(APPEND failures "  the output directory is not empty: ${left_over}\n")
endif()

if(failures)
  message(FATAL_ERROR "bad deck ${deck_name}:\n${failures}--- stderr ---\n${standard_error}--- stdout ---\n${standard_output}")
endif()
message(STATUS "bad deck ${deck_name}: refused as expected\n${standard_error}")
