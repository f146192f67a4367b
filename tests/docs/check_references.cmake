# cmake -DSOURCE_DIR=... -P check_references.cmake
# The repository stands alone: code and docs name no file outside it, and every file they name
# inside it exists (the shipped examples and scripts included).
# - No mention of DESIGN.md or of ../shared (a folder beside the repository, not in it).
# - Every docs/NAME.md named in a header, a source file or the README exists.
# - Every relative Markdown link in README.md and docs/*.md points to an existing file.
cmake_policy(SET CMP0009 NEW)
if(NOT DEFINED SOURCE_DIR)
  message(FATAL_ERROR "check_references.cmake: SOURCE_DIR is not set")
endif()
file(GLOB_RECURSE code RELATIVE ${SOURCE_DIR}
     ${SOURCE_DIR}/include/*.hpp ${SOURCE_DIR}/src/*.cpp ${SOURCE_DIR}/src/*.hpp ${SOURCE_DIR}/apps/*.cpp
     ${SOURCE_DIR}/apps/*.hpp ${SOURCE_DIR}/bench/*.cpp ${SOURCE_DIR}/tests/*.cpp ${SOURCE_DIR}/tests/*.hpp
     ${SOURCE_DIR}/cmake/*.in ${SOURCE_DIR}/cmake/*.cmake ${SOURCE_DIR}/CMakeLists.txt
     ${SOURCE_DIR}/examples/*.yaml ${SOURCE_DIR}/fuzz/*.cpp ${SOURCE_DIR}/fuzz/*.hpp ${SOURCE_DIR}/scripts/*.sh
     ${SOURCE_DIR}/python/*.cpp ${SOURCE_DIR}/python/*.hpp ${SOURCE_DIR}/python/*.py ${SOURCE_DIR}/python/*.pyi
     ${SOURCE_DIR}/tests/*.py ${SOURCE_DIR}/examples/*.py)
file(GLOB docs RELATIVE ${SOURCE_DIR} ${SOURCE_DIR}/docs/*.md)
set(problems "")
foreach(file IN LISTS code docs ITEMS README.md)
  file(READ ${SOURCE_DIR}/${file} text)
  if(text MATCHES "DESIGN\\.md|\\.\\./shared|shared/spec")
    list(APPEND problems "${file}: names '${CMAKE_MATCH_0}', which is not in the repository")
  endif()
  string(REGEX MATCHALL "docs/[A-Za-z0-9_.-]+\\.md" named "${text}")
  list(REMOVE_DUPLICATES named)
  foreach(doc IN LISTS named)
    if(NOT EXISTS ${SOURCE_DIR}/${doc})
      list(APPEND problems "${file}: names ${doc}, which does not exist")
    endif()
  endforeach()
endforeach()
foreach(file IN LISTS docs ITEMS README.md)
  get_filename_component(dir ${SOURCE_DIR}/${file} DIRECTORY)
  file(READ ${SOURCE_DIR}/${file} text)
  # Square brackets and semicolons have meaning in CMake lists: take them out first.
  string(REPLACE "[" "<" text "${text}")
  string(REPLACE "]" ">" text "${text}")
  string(REPLACE ";" "," text "${text}")
  string(REGEX MATCHALL ">\\([^)#, \n]+" links "${text}")
  foreach(link IN LISTS links)
    string(SUBSTRING "${link}" 2 -1 target)
    if(target MATCHES "^[a-z]+:")
      continue()  # http:, https:, mailto:
    endif()
    if(NOT EXISTS ${dir}/${target})
      list(APPEND problems "${file}: links to ${target}, which does not exist")
    endif()
  endforeach()
endforeach()
if(problems)
  list(JOIN problems "\n" text)
  message(FATAL_ERROR "references that do not resolve:\n${text}")
endif()
list(LENGTH code n_code)
list(LENGTH docs n_docs)
message(STATUS "checked ${n_code} code files, ${n_docs} docs and README.md: every reference resolves")
