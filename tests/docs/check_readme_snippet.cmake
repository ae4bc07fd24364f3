# SPDX-License-Identifier: BSD-3-Clause
# CTest docs.readme_snippet: the README's first ```cpp block must be, character for character, the planner-facing
# part of examples/01_embed_the_planner.cpp (between its "---- The planner-facing part" and "---- End of the
# planner-facing part" lines, indentation of the enclosing function removed). Example 01 is compiled and run as
# example.01_embed_the_planner, so the README's snippet cannot rot.
# Usage: cmake -DREADME=... -DEXAMPLE=... -P check_readme_snippet.cmake
file(READ "${EXAMPLE}" ex)
string(FIND "${ex}" "// ---- The planner-facing part" a)
string(FIND "${ex}" "// ---- End of the planner-facing part" b)
if(a EQUAL -1 OR b EQUAL -1)
  message(FATAL_ERROR "${EXAMPLE}: the planner-facing part's marker lines are missing")
endif()
string(SUBSTRING "${ex}" ${a} -1 tail)
string(FIND "${tail}" "\n" nl)
math(EXPR start "${a} + ${nl} + 1")
math(EXPR len "${b} - ${start}")
string(SUBSTRING "${ex}" ${start} ${len} code)
string(REGEX REPLACE "[ ]+$" "" code "${code}")          # the indentation before the end marker
string(REGEX REPLACE "^    " "" code "${code}")
string(REPLACE "\n    " "\n" code "${code}")

file(READ "${README}" md)
string(FIND "${md}" "```cpp\n" c)
if(c EQUAL -1)
  message(FATAL_ERROR "${README}: no ```cpp block")
endif()
math(EXPR c "${c} + 7")
string(SUBSTRING "${md}" ${c} -1 rest)
string(FIND "${rest}" "```" d)
string(SUBSTRING "${rest}" 0 ${d} snippet)

if(NOT snippet STREQUAL code)
  message(FATAL_ERROR "README.md's first C++ snippet differs from the planner-facing part of ${EXAMPLE}.\n"
                      "--- README:\n${snippet}--- example:\n${code}")
endif()
string(REGEX MATCHALL "\n" lines "${snippet}")
list(LENGTH lines n)
if(n GREATER 20)
  message(FATAL_ERROR "README.md's first C++ snippet has ${n} lines (at most 20)")
endif()
message(STATUS "README snippet = examples/01 planner-facing part (${n} lines)")
