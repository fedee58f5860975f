# Runs a command only when a shared data file exists; otherwise prints the skip message the C++
# tests use (tests/test_data.hpp), which the test's SKIP_REGULAR_EXPRESSION turns into a skip.
#   cmake -DDATA=<file> -P shared_data_test.cmake <command> [args...]
if(NOT EXISTS "${DATA}")
  cmake_path(NORMAL_PATH DATA OUTPUT_VARIABLE shown)
  message("shared data missing: ${shown} (the shared data folder lives beside the clone)")
  return()
endif()
# The command: every argument after the script's name.
set(command)
set(after_p FALSE)
math(EXPR last "${CMAKE_ARGC} - 1")
foreach(i RANGE ${last})
  if(after_p)
    list(APPEND command "${CMAKE_ARGV${i}}")
  elseif("${CMAKE_ARGV${i}}" STREQUAL "-P")
    set(after_p TRUE)
  endif()
endforeach()
list(POP_FRONT command)  # the script itself
execute_process(COMMAND ${command} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "exit status ${rc}: ${command}")
endif()
